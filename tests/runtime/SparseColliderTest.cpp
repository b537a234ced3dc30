// Sparse (NanoVDB) colliders in a scene: sluice-play cannot sample them yet and says so.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "sluice/format/AssetIO.h"
#include "sluice/format/SceneIO.h"
#include "sluice/rt/Simulation.h"

namespace fs = std::filesystem;
using namespace sluice;

TEST(SparseCollider, ASceneNamingOneIsRejectedAsUnsupportedBeforeAnyGlWork) {
    const fs::path dir = fs::path(SLUICE_TEST_TMP) / "sparse-collider";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // A valid sparse asset (the fuzz seed): the reader accepts it, the runtime does not.
    const fs::path asset =
        fs::path(SLUICE_SOURCE_DIR) / "tests/fuzz/corpus/asset_reader/sphere-sparse.slc";
    auto read = format::readAsset(asset);
    ASSERT_TRUE(read.ok()) << read.error().message();
    ASSERT_TRUE(read->sparse());
    fs::copy_file(asset, dir / "sparse.slc");
    {
        std::ofstream out(dir / "scene.json");
        out << R"({ "simulation": { "spacing": 0.02 },
  "fluid": [ { "box": { "min": [0.3, 0.3, 0.3], "max": [0.4, 0.4, 0.4] } } ],
  "colliders": [ { "asset": "sparse.slc" } ] })";
    }
    auto scene = format::readScene(dir / "scene.json");
    ASSERT_TRUE(scene.ok()) << scene.error().message();
    auto colliders = rt::loadSceneColliders(*scene);
    ASSERT_FALSE(colliders.ok());
    EXPECT_EQ(colliders.error().code, ErrorCode::Unsupported);
    EXPECT_NE(colliders.error().detail.find("without --sparse"), std::string::npos)
        << colliders.error().detail;
    EXPECT_NE(colliders.error().detail.find("colliders[0]"), std::string::npos);
}
