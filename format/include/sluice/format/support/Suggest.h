// Words for messages: the known word closest to a mistyped one, and counted nouns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sluice::format {

/// Levenshtein distance between two byte strings (insert, delete, substitute: 1 each).
std::size_t editDistance(std::string_view a, std::string_view b);

/// The candidate nearest to `word` by editDistance, if it is close enough to be a typo: at most
/// 2 edits and at most half the word's length ("bkae" suggests "bake"); words shorter than 3 or
/// longer than 64 bytes get none ("-x" does not suggest "-o"). Ties go to the first candidate.
std::optional<std::string> closestMatch(std::string_view word,
                                        const std::vector<std::string>& candidates);

/// "1 triangle", "2 triangles": `count` and the noun, plural unless the count is 1.
/// `pluralForm` defaults to `singular` + "s".
std::string plural(std::uint64_t count, std::string_view singular,
                   std::string_view pluralForm = {});

/// " (did you mean 'bake'?)" for the closestMatch of `word`, or "" when there is none.
std::string didYouMean(std::string_view word, const std::vector<std::string>& candidates,
                       char quote = '\'');

} // namespace sluice::format
