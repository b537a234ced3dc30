// `bake --sparse --for-spacing`: the band is picked for the particle spacing the collider will
// meet, sluice-play's band check accepts it, and `info` says what a band serves.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRun.h"
#include "TestMeshes.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/scene/SolverReach.h"

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace clirun;

/// The demo sphere (0.5 m across) baked sparse at 32 voxels with `extra`; its asset.
format::ColliderAsset bakeSparse(const fs::path& dir, const std::vector<std::string>& extra) {
    std::vector<std::string> args = {
        "bake", kSphereObj.string(), "-o",     (dir / "s.slc").string(), "--resolution",
        "32",   "--sparse",          "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult run = runBake(dir, args);
    EXPECT_EQ(run.code, kExitOk) << shown(run);
    auto asset = format::readAsset(dir / "s.slc");
    EXPECT_TRUE(asset) << asset.error().message();
    return asset ? *asset : format::ColliderAsset{};
}

TEST(CliSparseBand, ForSpacingPicksTheSmallestBandADynamicBodyThereNeeds) {
    const fs::path dir = testmesh::tempDir("cli-for-spacing");
    for (double spacing : {0.01, 0.02, 0.03}) {
        const format::ColliderAsset asset =
            bakeSparse(dir, {"--for-spacing", std::to_string(spacing)});
        const double voxel = asset.meta.voxelSize;
        const double needed =
            format::requiredBandVoxels(format::colliderReach(spacing, 2.0 * spacing, true), voxel);
        // Whole voxels, enough, and not one more than enough.
        EXPECT_EQ(asset.meta.bandWidth, std::ceil(asset.meta.bandWidth)) << spacing;
        EXPECT_GE(asset.meta.bandWidth, needed) << spacing;
        EXPECT_LT(asset.meta.bandWidth - 1.0, needed) << spacing;
        // What info says the band serves covers the spacing it was baked for, in both roles.
        EXPECT_GE(format::largestSpacingForBand(asset.meta.bandWidth, voxel, true), spacing);
        EXPECT_GE(format::largestSpacingForBand(asset.meta.bandWidth, voxel, false), spacing);
    }
    // 2 cm at 32 voxels over 0.5 m (15.6 mm voxels): h + 0.05 s = 4.1 cm, 2.62 + 1.73 voxels.
    EXPECT_EQ(bakeSparse(dir, {"--for-spacing", "0.02"}).meta.bandWidth, 5.0);
    // A larger kernel reaches farther: 8.1 cm is 5.18 + 1.73 voxels.
    EXPECT_EQ(
        bakeSparse(dir, {"--for-spacing", "0.02", "--for-kernel-radius", "0.08"}).meta.bandWidth,
        7.0);
}

TEST(CliSparseBand, InfoSaysWhichSpacingsABandServes) {
    const fs::path dir = testmesh::tempDir("cli-band-serves");
    const format::ColliderAsset asset = bakeSparse(dir, {"--band", "5"});
    const RunResult text = runBake(dir, {"info", (dir / "s.slc").string()});
    ASSERT_EQ(text.code, kExitOk) << shown(text);
    EXPECT_NE(text.out.find("  band serves   exact to "), std::string::npos) << text.out;
    const RunResult js = runBake(dir, {"info", (dir / "s.slc").string(), "--json"});
    ASSERT_EQ(js.code, kExitOk) << shown(js);
    const json info = json::parse(js.out);
    const double voxel = asset.meta.voxelSize;
    // (5 - sqrt 3) voxels exact: twice that for a particle radius, / 2.05 for a body's kernel
    // (h = 2 s and the surface offset, 0.05 s).
    EXPECT_NEAR(info["bandServes"]["staticSpacing"].get<double>(),
                2.0 * (5.0 - std::sqrt(3.0)) * voxel, 1e-9);
    EXPECT_NEAR(info["bandServes"]["dynamicSpacing"].get<double>(),
                (5.0 - std::sqrt(3.0)) * voxel / 2.05, 1e-9);
    // A dense asset has no band.
    const RunResult dense = runBake(dir, {"bake", kSphereObj.string(), "-o",
                                          (dir / "d.slc").string(), "--resolution", "8", "-q"});
    ASSERT_EQ(dense.code, kExitOk) << shown(dense);
    EXPECT_TRUE(
        json::parse(runBake(dir, {"info", (dir / "d.slc").string(), "--json"}).out)["bandServes"]
            .is_null());
}

TEST(CliSparseBand, BadForSpacingArgumentsExitTwoAndWriteNothing) {
    const fs::path dir = testmesh::tempDir("cli-for-spacing-bad");
    const fs::path out = dir / "x.slc";
    const std::string mesh = kSphereObj.string();
    const std::vector<std::string> bake = {"bake", mesh, "-o", out.string(), "--resolution", "32"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> args = bake;
        args.insert(args.end(), extra.begin(), extra.end());
        return args;
    };
    expectRejected(dir, with({"--for-spacing", "0.02"}), "--sparse", out);
    expectRejected(dir, with({"--sparse", "--for-spacing", "0.02", "--band", "4"}), "--band", out);
    expectRejected(dir, with({"--sparse", "--for-spacing", "0"}), "--for-spacing", out);
    expectRejected(dir, with({"--sparse", "--for-spacing", "nan"}), "--for-spacing", out);
    expectRejected(dir, with({"--sparse", "--for-kernel-radius", "0.04"}), "--for-spacing", out);
    // 1.5 to 4 spacings, as a scene allows.
    expectRejected(dir, with({"--sparse", "--for-spacing", "0.02", "--for-kernel-radius", "0.1"}),
                   "--for-kernel-radius", out);
    // 0.5 m over 15.6 mm voxels: 1 m spacing needs 140 voxels, over the 64 a band may have.
    expectRejected(dir, with({"--sparse", "--for-spacing", "1"}), "over the 64", out);
}

} // namespace
} // namespace sluice::bake
