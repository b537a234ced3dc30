// Edit distance and the closest known word, for "did you mean" in error messages.
#include "sluice/format/support/Suggest.h"

#include <algorithm>

namespace sluice::format {

namespace {
constexpr std::size_t kMaxWordLength = 64;   // [bytes] longer words are not typos of ours
constexpr std::size_t kMaxTypoDistance = 2;  // [edits]
} // namespace

std::size_t editDistance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j)
        row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

std::optional<std::string> closestMatch(std::string_view word,
                                        const std::vector<std::string>& candidates) {
    if (word.size() < 3 || word.size() > kMaxWordLength)
        return std::nullopt;
    const std::size_t limit = std::min(kMaxTypoDistance, word.size() / 2);
    const std::string* best = nullptr;
    std::size_t bestDistance = limit + 1;
    for (const std::string& candidate : candidates) {
        const std::size_t d = editDistance(word, candidate);
        if (d < bestDistance) {
            bestDistance = d;
            best = &candidate;
        }
    }
    if (best == nullptr)
        return std::nullopt;
    return *best;
}

std::string plural(std::uint64_t count, std::string_view singular, std::string_view pluralForm) {
    std::string text = std::to_string(count) + " ";
    if (count == 1)
        return text + std::string(singular);
    return text + (pluralForm.empty() ? std::string(singular) + "s" : std::string(pluralForm));
}

std::string didYouMean(std::string_view word, const std::vector<std::string>& candidates,
                       char quote) {
    const auto best = closestMatch(word, candidates);
    if (!best)
        return {};
    return std::string(" (did you mean ") + quote + *best + quote + "?)";
}

} // namespace sluice::format
