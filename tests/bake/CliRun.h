// Runs the sluice-bake program (SLUICE_BAKE_EXE) from tests and captures what it prints.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <sys/wait.h>

namespace sluice::bake::clirun {

/// What one run of sluice-bake did.
struct RunResult {
    int code = -1; ///< exit code, -1 if it did not exit normally
    std::string out;
    std::string err;
};

/// A whole file as bytes in a string (empty if it cannot be read).
inline std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// `arg` single-quoted for the shell.
inline std::string quote(const std::string& arg) {
    std::string quoted = "'";
    for (char c : arg)
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

/// Runs sluice-bake with `args` (each quoted for the shell), capturing stdout and stderr in
/// files in `dir`.
inline RunResult runBake(const std::filesystem::path& dir, const std::vector<std::string>& args) {
    std::string command = quote(SLUICE_BAKE_EXE);
    for (const std::string& arg : args)
        command += " " + quote(arg);
    const std::filesystem::path out = dir / "stdout.txt", err = dir / "stderr.txt";
    command += " >" + quote(out.string()) + " 2>" + quote(err.string());
    const int status = std::system(command.c_str());
    RunResult run;
    run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = readText(out);
    run.err = readText(err);
    return run;
}

/// `what` printed for a failed expectation: the command's output.
inline std::string shown(const RunResult& run) {
    return "exit " + std::to_string(run.code) + "\nstdout:\n" + run.out + "\nstderr:\n" + run.err;
}

} // namespace sluice::bake::clirun
