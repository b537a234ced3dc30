// The mass properties in what sluice-bake prints: bake --json, info and info --json.
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRun.h"
#include "TestMeshes.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/format/asset/AssetHeader.h"

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace clirun;

const fs::path kVersion1_0Asset =
    fs::path(SLUICE_SOURCE_DIR) / "tests" / "format" / "data" / "asset-v1.0.slc";
const fs::path kVersion1_1Asset =
    fs::path(SLUICE_SOURCE_DIR) / "tests" / "format" / "data" / "asset-v1.1.slc";

TEST(CliMass, BakeAndInfoPrintTheMassPropertiesOfAClosedMesh) {
    const fs::path dir = testmesh::tempDir("cli-mass");
    const fs::path asset = dir / "sphere.slc";
    const RunResult bake = runBake(dir, {"bake", kSphereObj.string(), "-o", asset.string(),
                                         "--backend", "cgal", "--resolution", "16", "--json"});
    ASSERT_EQ(bake.code, kExitOk) << shown(bake);
    const json baked = json::parse(bake.out)["asset"]["massProperties"];
    ASSERT_TRUE(baked.is_object()) << bake.out;

    // The demo sphere (radius 0.25, 1280 triangles) has a little less than the ball's volume.
    const double ball = 4.0 / 3.0 * std::numbers::pi * 0.25 * 0.25 * 0.25;
    const double volume = baked["volume"].get<double>();
    EXPECT_LT(volume, ball);
    EXPECT_GT(volume, 0.97 * ball);
    ASSERT_EQ(baked["centerOfMass"].size(), 3u);
    ASSERT_EQ(baked["inertia"].size(), 3u);
    for (int row = 0; row < 3; ++row) {
        ASSERT_EQ(baked["inertia"][row].size(), 3u);
        EXPECT_NEAR(baked["inertia"][row][row].get<double>(), 0.4 * volume * 0.25 * 0.25,
                    0.03 * 0.4 * volume * 0.25 * 0.25);
        for (int col = 0; col < 3; ++col)
            EXPECT_EQ(baked["inertia"][row][col], baked["inertia"][col][row]);
    }

    // info --json reads back the same numbers; the text names them.
    const RunResult info = runBake(dir, {"info", asset.string(), "--json"});
    ASSERT_EQ(info.code, kExitOk) << shown(info);
    const json read = json::parse(info.out);
    EXPECT_EQ(read["header"]["minor"], format::kAssetMinor);
    EXPECT_EQ(read["massProperties"], baked);
    const RunResult text = runBake(dir, {"info", asset.string()});
    ASSERT_EQ(text.code, kExitOk) << shown(text);
    EXPECT_NE(text.out.find("\n  mass          volume "), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("\n  inertia       about the centre of mass"), std::string::npos)
        << text.out;
}

TEST(CliMass, AnOpenMeshAndAVersion1_0AssetHaveNone) {
    const fs::path dir = testmesh::tempDir("cli-mass-none");
    const fs::path obj = testmesh::writeTempObj(testmesh::boxSoup({0, 0, 0}, {1, 1, 1}, true),
                                                "cli-mass-none", "open.obj");
    const fs::path asset = dir / "open.slc";
    const RunResult bake = runBake(dir, {"bake", obj.string(), "-o", asset.string(), "--backend",
                                         "cgal", "--resolution", "8", "--json"});
    ASSERT_EQ(bake.code, kExitOk) << shown(bake);
    EXPECT_TRUE(json::parse(bake.out)["asset"]["massProperties"].is_null()) << bake.out;
    const RunResult info = runBake(dir, {"info", asset.string()});
    ASSERT_EQ(info.code, kExitOk) << shown(info);
    EXPECT_NE(info.out.find("\n  mass          not recorded (the source mesh is not a closed"),
              std::string::npos)
        << info.out;

    const RunResult old = runBake(dir, {"info", kVersion1_0Asset.string(), "--json"});
    ASSERT_EQ(old.code, kExitOk) << shown(old);
    EXPECT_EQ(json::parse(old.out)["header"]["minor"], 0);
    EXPECT_TRUE(json::parse(old.out)["massProperties"].is_null()) << old.out;
    const RunResult oldText = runBake(dir, {"info", kVersion1_0Asset.string()});
    ASSERT_EQ(oldText.code, kExitOk) << shown(oldText);
    EXPECT_NE(oldText.out.find("predates format 1.1"), std::string::npos) << oldText.out;
}

TEST(CliMass, AVersion1_1AssetShowsItsMassAndIsDense) {
    const fs::path dir = testmesh::tempDir("cli-mass-v1.1");
    const RunResult info = runBake(dir, {"info", kVersion1_1Asset.string(), "--json"});
    ASSERT_EQ(info.code, kExitOk) << shown(info);
    const json read = json::parse(info.out);
    EXPECT_EQ(read["header"]["minor"], 1);
    EXPECT_EQ(read["layout"], "dense");
    EXPECT_EQ(read["bandWidth"], 0.0);
    // makeAsset's ball of radius 0.3 (tests/format/AssetTestUtil.h).
    EXPECT_DOUBLE_EQ(read["massProperties"]["volume"].get<double>(),
                     4.0 / 3.0 * std::numbers::pi * 0.3 * 0.3 * 0.3);
    const RunResult text = runBake(dir, {"info", kVersion1_1Asset.string()});
    ASSERT_EQ(text.code, kExitOk) << shown(text);
    EXPECT_NE(text.out.find("\n  mass          volume "), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("\n  layout        dense"), std::string::npos) << text.out;
}

} // namespace
} // namespace sluice::bake
