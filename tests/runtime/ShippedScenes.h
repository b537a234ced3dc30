// Test support: the shipped scenes (assets/*.json) the runtime's suites run one by one, and the
// test name of each ("dam-break.json" -> "dambreak").
#pragma once

#include <string>

#include <gtest/gtest.h>

namespace sluice::rt::test {

/// Every shipped scene small enough for a test step (the terrain's has its own test).
inline auto shippedScenes() {
    return ::testing::Values("drop.json", "dam-break.json", "wave-sphere.json", "funnel.json",
                             "martin-moyce.json", "float.json", "crates.json");
}

/// A test name from a scene file name: its stem without dashes.
struct ShippedSceneName {
    template <typename Info> std::string operator()(const Info& info) const {
        std::string name = info.param;
        name = name.substr(0, name.find('.'));
        std::erase(name, '-');
        return name;
    }
};

} // namespace sluice::rt::test
