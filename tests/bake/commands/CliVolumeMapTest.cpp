// `sluice-bake bake --volume-map`: the boundary model's volume map baked into the asset on the
// GPU (llvmpipe without one), shown by `info`, checked by `validate` against a brute-force
// integration (which catches a map changed after the bake), and bad supports refused.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRun.h"
#include "TestMeshes.h"
#include "sluice/bake/validate/VolumeMapCheck.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/GridSamples.h"

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;
using clirun::runBake;
using clirun::shown;

TEST(CliVolumeMap, BakedShownAndCheckedAgainstBruteForce) {
    const fs::path dir = testmesh::tempDir("cli-volume-map");
    const fs::path mesh = testmesh::writeTempObj(
        testmesh::boxSoup({0.0, 0.0, 0.0}, {0.2, 0.12, 0.16}), "cli-volume-map-mesh", "box.obj");
    ASSERT_FALSE(mesh.empty());
    const fs::path asset = dir / "box.slc";
    const std::vector<std::string> bake = {"bake",         mesh.string(), "-o",
                                           asset.string(), "--backend",   "cgal",
                                           "--voxel-size", "0.01",        "--quiet"};
    std::vector<std::string> withMaps = bake;
    withMaps.insert(withMaps.end(), {"--volume-map", "0.04,0.06"});
    clirun::RunResult run = runBake(dir, withMaps);
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    auto read = format::readAsset(asset);
    ASSERT_TRUE(read) << read.error().message();
    ASSERT_EQ(read->volumeMaps.size(), 2u);
    EXPECT_EQ(read->volumeMaps[0].support, 0.04);
    EXPECT_EQ(read->volumeMaps[1].support, 0.06);

    run = runBake(dir, {"info", "--json", asset.string()});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    const nlohmann::json info = nlohmann::json::parse(run.out);
    ASSERT_EQ(info["volumeMaps"].size(), 2u);
    EXPECT_EQ(info["volumeMaps"][0]["support"], 0.04);
    EXPECT_EQ(info["volumeMaps"][0]["points"], format::volumeMapPoints(*read));
    EXPECT_GT(info["volumeMaps"][0]["nonZero"].get<int>(), 100); // the box's edges and corners
    EXPECT_EQ(info["header"]["minor"], format::kAssetMinor);

    const std::vector<std::string> validate = {"validate", asset.string(), mesh.string()};
    std::vector<std::string> validateJson = validate;
    validateJson.push_back("--json");
    run = runBake(dir, validateJson);
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    const nlohmann::json report = nlohmann::json::parse(run.out);
    ASSERT_EQ(report["volumeMaps"].size(), 2u);
    for (const auto& map : report["volumeMaps"]) {
        RecordProperty("max_error_support_" + std::to_string(map["support"].get<double>()),
                       std::to_string(map["maxError"].get<double>()));
        EXPECT_GT(map["pointsChecked"].get<int>(), 1000);
        EXPECT_EQ(map["nonZeroBeyondReach"], 0);
        EXPECT_LE(map["maxError"].get<double>(), report["limits"]["maxMapError"].get<double>());
    }

    // A map changed after the bake, at the point the check found worst: validate fails.
    const VolumeMapCheck worst = checkVolumeMap(*read, read->volumeMaps[0]);
    read->volumeMaps[0].values[worst.worstPoint] += 0.2f;
    ASSERT_TRUE(format::writeAsset(asset, *read));
    run = runBake(dir, validate);
    EXPECT_EQ(run.code, kExitCheckFailed) << shown(run);
    EXPECT_NE(run.out.find("volume map support 0.04"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("OVER"), std::string::npos) << run.out;
}

TEST(CliVolumeMap, RefusesASupportThatIsNoPositiveNumberWritingNothing) {
    const fs::path dir = testmesh::tempDir("cli-volume-map-bad");
    const fs::path mesh = testmesh::writeTempObj(
        testmesh::boxSoup({0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}), "cli-volume-map-bad-mesh", "box.obj");
    const fs::path asset = dir / "box.slc";
    for (const char* bad : {"0", "-0.04", "nan", "0.04,abc", "0.04,0.04", "1,2,3,4,5,6,7,8,9"}) {
        clirun::expectRejected(dir,
                               {"bake", mesh.string(), "-o", asset.string(), "--backend", "cgal",
                                "--resolution", "16", "--quiet", "--volume-map", bad},
                               "--volume-map", asset);
    }
}

} // namespace
} // namespace sluice::bake
