// Sparse (NanoVDB) colliders in a scene: loaded for the GPU sampler when their band covers what
// the solver reads, refused with the --band to re-bake with when it does not.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "colliders/ColliderBands.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/format/scene/SolverReach.h"
#include "sluice/rt/sim/Simulation.h"

namespace fs = std::filesystem;
using namespace sluice;

namespace {

// A scene in its own folder around the committed sparse sphere (the fuzz seed: band 2 voxels of
// 0.05 m, radius 0.2 m at the origin), with `spacing` and the collider's extra JSON.
// With `withMass` the asset also carries the mass properties of its solid (a closed mesh's, as
// the baker stores them), which a dynamic sparse collider needs.
format::Scene sceneWithSparseSphere(const std::string& name, double spacing,
                                    const std::string& colliderExtra = "", bool withMass = false) {
    const fs::path dir = fs::path(SLUICE_TEST_TMP) / ("sparse-collider-" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto asset = format::readAsset(fs::path(SLUICE_SOURCE_DIR) /
                                   "tests/fuzz/corpus/asset_reader/sphere-sparse.slc");
    EXPECT_TRUE(asset.ok()) << asset.error().message();
    if (withMass) {
        const double r = 0.2, volume = 4.0 / 3.0 * 3.141592653589793 * r * r * r;
        asset->meta.meshMass = format::MassProperties{
            volume, glm::dvec3(0.0), glm::dmat3(0.4 * volume * r * r)};
    }
    EXPECT_TRUE(format::writeAsset(dir / "sparse.slc", *asset).ok());
    {
        std::ofstream out(dir / "scene.json");
        out << R"({ "simulation": { "spacing": )" << spacing << R"( },
  "fluid": [ { "box": { "min": [0.3, 0.3, 0.3], "max": [0.5, 0.5, 0.5] } } ],
  "colliders": [ { "asset": "sparse.slc")" << colliderExtra << R"( } ] })";
    }
    auto scene = format::readScene(dir / "scene.json");
    EXPECT_TRUE(scene.ok()) << scene.error().message();
    return scene.ok() ? *scene : format::Scene{};
}

} // namespace

TEST(SparseCollider, ASceneNamingOneLoadsItAsSparse) {
    const format::Scene scene = sceneWithSparseSphere("loads", 0.02);
    auto colliders = rt::loadSceneColliders(scene);
    ASSERT_TRUE(colliders.ok()) << colliders.error().message();
    ASSERT_EQ(colliders->size(), 1u);
    EXPECT_TRUE((*colliders)[0].sparse());
    EXPECT_FALSE((*colliders)[0].grid.empty());
}

TEST(SparseCollider, ABandNarrowerThanTheParticleRadiusNeedsIsRefusedWithTheBandToUse) {
    // r = 0.05 m: distances up to r + sqrt(3) voxels, 2.7 voxels of 0.05 m, past the band of 2.
    EXPECT_NEAR(format::requiredBandVoxels(0.05, 0.05), 1.0 + std::sqrt(3.0), 1e-12);
    const format::Scene scene = sceneWithSparseSphere("narrow", 0.1);
    auto colliders = rt::loadSceneColliders(scene);
    ASSERT_FALSE(colliders.ok());
    EXPECT_EQ(colliders.error().code, ErrorCode::InvalidArgument);
    const std::string& detail = colliders.error().detail;
    EXPECT_NE(detail.find("colliders[0]"), std::string::npos) << detail;
    EXPECT_NE(detail.find("band of 2 voxels"), std::string::npos) << detail;
    EXPECT_NE(detail.find("--sparse --band 3"), std::string::npos) << detail;
}

TEST(SparseCollider, ADynamicBodyNeedsItsBandToReachTheKernelRadius) {
    // Static at 2 cm spacing the band suffices (r = 1 cm); as a body the boundary term reads
    // phi up to h + the surface offset (4.3 cm): 2.6 voxels.
    const format::Scene scene =
        sceneWithSparseSphere("dynamic", 0.02, R"(, "dynamic": { "density": 500 })", true);
    auto colliders = rt::loadSceneColliders(scene);
    ASSERT_FALSE(colliders.ok());
    EXPECT_NE(colliders.error().detail.find("a dynamic body"), std::string::npos)
        << colliders.error().detail;
    EXPECT_NE(colliders.error().detail.find("--band 3"), std::string::npos)
        << colliders.error().detail;
}
