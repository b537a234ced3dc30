// Numbers in messages and summaries: the shortest text with a given number of significant
// digits ("%g"), as every tool prints them.
#pragma once

#include <cstdio>
#include <string>

namespace sluice::format {

/// `value` with at most `digits` significant digits, trailing zeros dropped ("0.0267", "1e+03").
inline std::string significant(double value, int digits = 6) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    return text;
}

} // namespace sluice::format
