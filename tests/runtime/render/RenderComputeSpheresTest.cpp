// The compute passes for small spheres against every sphere rasterised as an impostor: the
// same pixels and colours to rounding, for spheres apart and touching, and for the screen-space
// surface.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RenderStage.h"
#include "render/RenderTestSupport.h"

namespace sluice::rt {
namespace {

using namespace test;
using namespace renderstage;

// One frame drawn with the compute passes for small spheres and with every sphere rasterised:
// the water's pixels (those the particles change) and how many of them the two draw
// differently by more than rounding (a channel off by more than 2).
struct PathDiff {
    std::size_t water = 0;
    std::size_t changed = 0;
    double meanChannel = 0.0;
};

PathDiff computeAgainstRaster(Stage& stage, RenderSettings settings) {
    settings.computeSmallSpheres = true;
    const Image viaCompute = stage.draw(settings);
    settings.computeSmallSpheres = false;
    const Image viaRaster = stage.draw(settings);
    PathDiff d;
    d.water = compareImages(viaRaster, stage.drawWithoutParticles(settings)).pixels;
    for (std::uint32_t y = 0; y < kSize.y; ++y)
        for (std::uint32_t x = 0; x < kSize.x; ++x)
            d.changed += pixelDiffers(viaCompute, viaRaster, x, y) ? 1 : 0;
    d.meanChannel = compareImages(viaCompute, viaRaster).meanChannel;
    return d;
}

// The compute passes for small spheres solve the impostors' ray-sphere hit at the same pixel
// centres: the same pixels, the same colours to rounding, whether every sphere covers a few
// pixels (all in compute) or tens (most rasterised from its list). Spheres at random positions,
// so no two touch: where touching spheres meet, their depths are equal to 32-bit precision and
// each path resolves the tie its own way (the compute one by the lower particle index).
TEST_F(RenderTest, SmallSpheresInComputeDrawTheSamePixelsAsTheImpostors) {
    Stage stage(kBlockScene);
    ASSERT_TRUE(stage.ok());
    std::mt19937 random(11);
    std::uniform_real_distribution<float> across(-0.1f, 0.1f), up(0.0f, 0.2f);
    std::vector<ParticleState> particles;
    for (std::uint32_t i = 0; i < 600; ++i)
        particles.push_back({{across(random), up(random), across(random)}, {}, i});
    ASSERT_TRUE(stage.sim->setParticles(particles));
    const OrbitCamera camera = stage.camera;
    for (const float zoom : {1.6f, 0.6f, 0.25f}) {
        SCOPED_TRACE("zoom " + std::to_string(zoom));
        stage.camera = camera;
        stage.camera.zoom(zoom);
        const PathDiff d = computeAgainstRaster(stage, {});
        ASSERT_GT(d.water, 800u); // the spheres are in the picture
        EXPECT_LE(double(d.changed), 0.002 * double(d.water)) << d.changed << " of " << d.water;
    }
}

// The screen-space surface takes the same depths and thicknesses from the compute passes
// (the view depth back from the window depth, the thickness in micrometres): the same picture
// to rounding, far and close (measured: no pixel off by more than 2).
TEST_F(RenderTest, SmallSpheresInComputeGiveTheSameFluidSurface) {
    Stage stage(waveSphere(), true);
    ASSERT_TRUE(stage.ok());
    for (int step = 0; step < 6; ++step)
        stage.sim->step();
    RenderSettings fluid;
    fluid.surface = SurfaceMode::Fluid;
    const OrbitCamera camera = stage.camera;
    for (const float zoom : {1.0f, 0.3f}) {
        SCOPED_TRACE("zoom " + std::to_string(zoom));
        stage.camera = camera;
        stage.camera.zoom(zoom);
        const PathDiff d = computeAgainstRaster(stage, fluid);
        ASSERT_GT(d.water, 3000u);
        EXPECT_LE(double(d.changed), 0.002 * double(d.water)) << d.changed << " of " << d.water;
        EXPECT_LT(d.meanChannel, 0.05);
    }
}

// A packed block seen from afar: every sphere a few pixels, touching its neighbours. The two
// paths may differ only where touching spheres tie in depth (measured: no pixel).
TEST_F(RenderTest, SmallSpheresInComputeDrawAPackedBlockAsTheImpostorsDo) {
    Stage stage(waveSphere(), true);
    ASSERT_TRUE(stage.ok());
    const PathDiff d = computeAgainstRaster(stage, {});
    ASSERT_GT(d.water, 3000u);
    EXPECT_LE(double(d.changed), 0.005 * double(d.water)) << d.changed << " of " << d.water;
    EXPECT_LT(d.meanChannel, 0.05);
}

} // namespace
} // namespace sluice::rt
