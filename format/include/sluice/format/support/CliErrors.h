// Command-line parse errors as one plain line naming the program, and number checks for options.
//
// Header-only and included only by command-line programs (sluice-bake, sluice-play): it needs
// CLI11, which the format library itself does not link.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "sluice/format/support/Suggest.h"

namespace sluice::format::cli {

namespace detail {

/// `text` read whole as a double; false if it is not a number ("abc", "1x", "").
inline bool readDouble(const std::string& text, double& value) {
    if (text.empty())
        return false;
    char* end = nullptr;
    value = std::strtod(text.c_str(), &end);
    return end == text.c_str() + text.size();
}

/// The shortest plain text of a limit for messages ("0.01", "4096").
inline std::string limitText(double value) {
    std::string text = std::to_string(value);
    if (text.find('.') != std::string::npos) {
        text.erase(text.find_last_not_of('0') + 1);
        if (text.back() == '.')
            text.pop_back();
    }
    return text;
}

/// The deepest subcommand that started parsing, or `app` itself.
inline const CLI::App& deepestCommand(const CLI::App& app) {
    const CLI::App* current = &app;
    for (;;) {
        const std::vector<const CLI::App*> parsed =
            current->get_subcommands([](const CLI::App* sub) { return sub->parsed(); });
        if (parsed.empty())
            return *current;
        current = parsed.front();
    }
}

/// Every spelling of `command`'s options ("--resolution", "-o", ...), for suggestions.
inline std::vector<std::string> optionNames(const CLI::App& command) {
    std::vector<std::string> names;
    for (const CLI::Option* option : command.get_options()) {
        for (const std::string& name : option->get_lnames())
            names.push_back("--" + name);
        for (const std::string& name : option->get_snames())
            names.push_back("-" + name);
    }
    return names;
}

/// The arguments nothing consumed, in command-line order, from `command` and its parents.
inline std::vector<std::string> leftOver(const CLI::App& app, const CLI::App& command) {
    std::vector<std::string> words = command.remaining();
    if (&command != &app)
        for (const std::string& word : app.remaining())
            words.push_back(word);
    return words;
}

/// "unknown option '--resolutoin' (did you mean '--resolution'?)" for the first word that
/// looks like an option, "unexpected argument 'x'" otherwise; "" when there is none.
inline std::string describeLeftOver(const CLI::App& command,
                                    const std::vector<std::string>& words) {
    for (const std::string& word : words) {
        if (word.size() < 2 || word[0] != '-')
            continue;
        const std::string name = word.substr(0, word.find('='));
        return "unknown option '" + name + "'" + didYouMean(name, optionNames(command));
    }
    if (!words.empty())
        return "unexpected argument '" + words.front() + "'";
    return {};
}

/// The words of an option's value as given, for messages ("" when unknown).
inline std::string givenValue(const CLI::App& command, const std::string& name) {
    const CLI::Option* option = command.get_option_no_throw(name);
    if (option == nullptr || option->results().empty())
        return {};
    return option->results().back();
}

/// The message for a parse error other than help and version, without the program name.
inline std::string parseErrorMessage(const CLI::App& app, const CLI::ParseError& e) {
    const CLI::App& command = deepestCommand(app);
    const std::string what = e.what();

    // A missing or misspelled subcommand: CLI11 says only "A subcommand is required".
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr && &command == &app &&
        !app.get_subcommands({}).empty() && what.rfind("A subcommand", 0) == 0) {
        std::vector<std::string> commands;
        for (const CLI::App* sub : app.get_subcommands({}))
            commands.push_back(sub->get_name());
        const std::vector<std::string> words = app.remaining();
        if (!words.empty() && words.front()[0] != '-')
            return "unknown command '" + words.front() + "'" + didYouMean(words.front(), commands);
        if (!words.empty())
            return describeLeftOver(app, words);
        std::string list;
        for (const std::string& name : commands)
            list += (list.empty() ? "" : ", ") + name;
        return "missing a command (one of: " + list + ")";
    }
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
        const std::string text = describeLeftOver(command, leftOver(app, command));
        if (!text.empty())
            return text;
    }
    // "NAME: problem" from the checks below: said as "NAME VALUE: problem".
    if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr) {
        const std::size_t colon = what.find(": ");
        if (colon != std::string::npos) {
            const std::string name = what.substr(0, colon);
            const std::string value = givenValue(command, name);
            if (!value.empty())
                return name + " " + value + what.substr(colon);
        }
    }
    // A number option without a check, given something that is not a number of its type.
    if (dynamic_cast<const CLI::ConversionError*>(&e) != nullptr) {
        const std::string prefix = "Could not convert: ";
        const std::size_t equals = what.find(" = ");
        if (what.rfind(prefix, 0) == 0 && equals != std::string::npos)
            return what.substr(prefix.size(), equals - prefix.size()) + " " +
                   what.substr(equals + 3) + ": not a number";
    }
    // "--resolution: 1 required UINT:INT in [1 - 4096] missing": an option given no value.
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr) {
        const std::size_t colon = what.find(": ");
        const std::string suffix = " missing";
        if (colon != std::string::npos && what.size() > suffix.size() &&
            what.compare(what.size() - suffix.size(), suffix.size(), suffix) == 0)
            return what.substr(0, colon) + " needs a value";
    }
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
        const std::string suffix = " is required";
        if (what.size() > suffix.size() &&
            what.compare(what.size() - suffix.size(), suffix.size(), suffix) == 0)
            return "missing " + what.substr(0, what.size() - suffix.size());
    }
    return what;
}

} // namespace detail

/// Handles a CLI11 parse error of `app` (the program's top-level app): --help and --version
/// print as CLI11 prints them and return 0; every other error prints one line on stderr,
///   "PROGRAM[ SUBCOMMAND]: message (see PROGRAM[ SUBCOMMAND] --help)",
/// and returns `badInputCode`. The messages: "unknown command 'bkae' (did you mean 'bake'?)",
/// "unknown option '--resolutoin' (did you mean '--resolution'?)", "--resolution abc: not a
/// number", "--resolution 0: expected a whole number from 1 to 4096", "missing --output",
/// "--resolution needs a value".
inline int reportParseError(CLI::App& app, const CLI::ParseError& e, std::string_view program,
                            int badInputCode) {
    if (dynamic_cast<const CLI::Success*>(&e) != nullptr)
        return app.exit(e);
    const CLI::App& command = detail::deepestCommand(app);
    std::string name(program);
    if (&command != &app)
        name += " " + command.get_name();
    std::cerr << name << ": " << detail::parseErrorMessage(app, e) << " (see " << name
              << " --help)\n";
    return badInputCode;
}

/// CLI11 check: a whole number in [lo, hi]. Fails with "not a number", "not a whole number" or
/// "expected a whole number from LO to HI" (reportParseError puts the option and value first).
inline CLI::Validator wholeNumber(std::int64_t lo, std::int64_t hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            double value = 0.0;
            if (!detail::readDouble(text, value) || std::isnan(value))
                return "not a number";
            if (std::isfinite(value) && value != std::floor(value))
                return "not a whole number";
            if (!(value >= double(lo) && value <= double(hi)))
                return "expected a whole number from " + std::to_string(lo) + " to " +
                       std::to_string(hi);
            return {};
        },
        "INT in [" + std::to_string(lo) + " - " + std::to_string(hi) + "]");
}

/// CLI11 check: a whole number of `noun` >= lo. The upper limit `hi` guards the type and is not
/// advertised: above it the message is "too many NOUN". Fails with "expected a whole number of
/// NOUN >= LO" otherwise.
inline CLI::Validator countAtLeast(std::uint64_t lo, std::uint64_t hi, std::string noun) {
    return CLI::Validator(
        [lo, hi, noun](std::string& text) -> std::string {
            double value = 0.0;
            if (!detail::readDouble(text, value) || std::isnan(value))
                return "not a number";
            if (std::isfinite(value) && value != std::floor(value))
                return "not a whole number";
            if (value < double(lo))
                return "expected a whole number of " + noun + " >= " + std::to_string(lo);
            if (!(value <= double(hi)))
                return "too many " + noun;
            return {};
        },
        "INT >= " + std::to_string(lo));
}

/// CLI11 check: a finite number > 0 (or >= 0 with `allowZero`). Fails with "not a number" or
/// "expected a finite number > 0" (CLI11's PositiveNumber prints DBL_MAX in full and lets NaN
/// through).
inline CLI::Validator finiteNumber(bool allowZero) {
    return CLI::Validator(
        [allowZero](std::string& text) -> std::string {
            double value = 0.0;
            if (!detail::readDouble(text, value))
                return "not a number";
            if (!std::isfinite(value) || (allowZero ? value < 0.0 : value <= 0.0))
                return std::string("expected a finite number ") + (allowZero ? ">= 0" : "> 0");
            return {};
        },
        allowZero ? "NUMBER >= 0" : "NUMBER > 0");
}

/// CLI11 check: a number in [lo, hi]. Fails with "not a number" or "expected a number from LO
/// to HI".
inline CLI::Validator numberIn(double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            double value = 0.0;
            if (!detail::readDouble(text, value) || std::isnan(value))
                return "not a number";
            if (!(value >= lo && value <= hi))
                return "expected a number from " + detail::limitText(lo) + " to " +
                       detail::limitText(hi);
            return {};
        },
        "NUMBER in [" + detail::limitText(lo) + " - " + detail::limitText(hi) + "]");
}

} // namespace sluice::format::cli
