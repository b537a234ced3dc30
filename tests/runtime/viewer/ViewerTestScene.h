// A scene for the viewer's body tests, written into a test's folder: one box of half the
// water's density floating in a small tank, seen by a fixed camera.
#pragma once

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "RuntimeTestScenes.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::rt::test {

/// Side of the floating box [m] (4 particle spacings).
inline constexpr float kFloatingBoxSide = 0.08f;

/// Writes `box.slc` (an analytic cube of kFloatingBoxSide) and `floating-box.json` into `dir`
/// and returns the scene's path: water 0.1 m deep in a 0.24 x 0.24 m domain at 2 cm spacing
/// (about 700 particles, small enough for llvmpipe), the box half under water at the centre,
/// the camera looking at it from above one corner.
inline std::filesystem::path writeFloatingBoxScene(const std::filesystem::path& dir) {
    const double h = 0.5 * double(kFloatingBoxSide);
    const auto box = testscene::boxColliderAsset(glm::dvec3(-h), glm::dvec3(h), 0.005);
    const auto written = format::writeAsset(dir / "box.slc", box);
    EXPECT_TRUE(written) << written.error().message();
    const std::filesystem::path scene = dir / "floating-box.json";
    std::ofstream(scene) << R"({
    "version": 1,
    "name": "floating-box",
    "simulation": { "spacing": 0.02 },
    "fluid": [ { "box": { "min": [-0.12, 0.0, -0.12], "max": [0.12, 0.1, 0.12] } } ],
    "colliders": [
        { "asset": "box.slc", "translation": [0.0, 0.1, 0.0], "dynamic": { "density": 500 } }
    ],
    "domain": { "min": [-0.12, 0.0, -0.12], "max": [0.12, 0.35, 0.12] },
    "camera": { "position": [0.3, 0.35, 0.45], "target": [0.0, 0.1, 0.0], "fov": 45 }
})";
    return scene;
}

} // namespace sluice::rt::test
