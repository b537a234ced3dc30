// Headless renders on whatever GL 4.5 is there (llvmpipe without a GPU): particles cover the
// screen region of their block, colliders show where they project, depth orders particles and
// colliders both ways, glass walls reveal the fluid in a tank, colour modes map speed, and a
// deterministic run renders the same bytes twice. The compute passes for small spheres against the
// impostors are in RenderComputeSpheresTest.cpp.
#include <random>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RenderStage.h"
#include "render/RenderTestSupport.h"
#include "sluice/rt/render/FluidStatsProbe.h"
#include "sluice/rt/render/FrameReadback.h"

namespace sluice::rt {
namespace {

using namespace test;
using namespace renderstage;

// The pixel rectangle that holds the projection of a box grown by `margin` [m] on every side.
struct PixelRect {
    glm::vec2 lo{1e9f};
    glm::vec2 hi{-1e9f};
    bool contains(std::uint32_t x, std::uint32_t y, float slack) const {
        return float(x) + 0.5f >= lo.x - slack && float(x) + 0.5f <= hi.x + slack &&
               float(y) + 0.5f >= lo.y - slack && float(y) + 0.5f <= hi.y + slack;
    }
};

PixelRect projectBox(const OrbitCamera& camera, glm::vec3 lo, glm::vec3 hi, float margin) {
    PixelRect rect;
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? hi.x + margin : lo.x - margin,
                               (c & 2) ? hi.y + margin : lo.y - margin,
                               (c & 4) ? hi.z + margin : lo.z - margin);
        const glm::vec2 p(camera.project(corner, kSize));
        rect.lo = glm::min(rect.lo, p);
        rect.hi = glm::max(rect.hi, p);
    }
    return rect;
}

// Counts the pixels that differ between two renders, inside and outside `rect` (+ slack).
struct Coverage {
    std::size_t inside = 0;
    std::size_t outside = 0;
    std::size_t rectPixels = 0;
};

Coverage coverage(const Image& with, const Image& without, const PixelRect& rect) {
    Coverage c;
    for (std::uint32_t y = 0; y < with.height; ++y)
        for (std::uint32_t x = 0; x < with.width; ++x) {
            const bool in = rect.contains(x, y, 0.0f);
            c.rectPixels += in ? 1 : 0;
            if (!pixelDiffers(with, without, x, y))
                continue;
            if (in)
                ++c.inside;
            else if (!rect.contains(x, y, 1.0f))
                ++c.outside;
        }
    return c;
}

// The particles' pixels (`with` against `without` them) fill most of `rect` (a box projects to
// a hexagon that fills most of its bounding rectangle) and none lie outside it.
void expectCoversOnly(const Image& with, const Image& without, const PixelRect& rect) {
    const Coverage c = coverage(with, without, rect);
    EXPECT_GT(double(c.inside), 0.6 * double(c.rectPixels)) << c.inside << " of " << c.rectPixels;
    EXPECT_EQ(c.outside, 0u);
}

// Water is blue: the pixel of `image` where the block's centre (0, 0.1, 0) projects.
void expectWaterColouredAtTheBlocksCentre(const Stage& stage, const Image& image) {
    const glm::vec3 centre = stage.camera.project({0.0f, 0.1f, 0.0f}, kSize);
    const glm::ivec3 water(image.at(std::uint32_t(centre.x), std::uint32_t(centre.y)));
    EXPECT_GT(water.b, water.r + 40) << water.r << " " << water.g << " " << water.b;
}

TEST_F(RenderTest, ParticlesCoverTheScreenRegionOfTheirBlockAndNothingElse) {
    Stage stage(kBlockScene);
    ASSERT_TRUE(stage.ok());
    const Image with = stage.draw();
    const Image without = stage.drawWithoutParticles();
    ASSERT_EQ(with.width, kSize.x);
    ASSERT_EQ(with.height, kSize.y);
    // Spheres of radius r around lattice points inside the block stay inside the block.
    expectCoversOnly(with, without,
                     projectBox(stage.camera, {-0.1f, 0.0f, -0.1f}, {0.1f, 0.2f, 0.1f}, 0.0f));
    expectWaterColouredAtTheBlocksCentre(stage, with);
}

TEST_F(RenderTest, FluidSurfaceCoversTheBlockRegionToo) {
    Stage stage(kBlockScene);
    ASSERT_TRUE(stage.ok());
    RenderSettings fluid;
    fluid.surface = SurfaceMode::Fluid;
    const Image with = stage.draw(fluid);
    const Image without = stage.drawWithoutParticles(fluid);
    // The fluid's spheres are fluidSphereScale times the particles' (radius 1 cm).
    const float margin = (fluid.fluidSphereScale - 1.0f) * 0.01f;
    expectCoversOnly(with, without,
                     projectBox(stage.camera, {-0.1f, 0.0f, -0.1f}, {0.1f, 0.2f, 0.1f}, margin));
}

// The reconstructed mesh (--surface mesh) covers the block's region too: a closed surface at
// the block's faces (its particles' centres are half a spacing inside them), nothing outside,
// and it is water-coloured.
TEST_F(RenderTest, SurfaceMeshCoversTheBlockRegionAndNothingElse) {
    Stage stage(kBlockScene);
    ASSERT_TRUE(stage.ok());
    RenderSettings mesh;
    mesh.surface = SurfaceMode::Mesh;
    const Image with = stage.draw(mesh);
    EXPECT_EQ(stage.renderer->meshError(), "");
    const Image without = stage.drawWithoutParticles(mesh);
    expectCoversOnly(with, without,
                     projectBox(stage.camera, {-0.1f, 0.0f, -0.1f}, {0.1f, 0.2f, 0.1f}, 0.0025f));
    expectWaterColouredAtTheBlocksCentre(stage, with);
}

const char* kSphereScene = R"({
    "simulation": { "spacing": 0.02 },
    "fluid": [ { "box": { "min": [%X0%, 0.05, %Z0%], "max": [%X1%, 0.15, %Z1%] } } ],
    "colliders": [ { "asset": "sphere.slc", "translation": [0.0, 0.1, 0.0], "scale": 0.4 } ],
    "camera": { "position": [0.0, 0.1, 0.9], "target": [0.0, 0.1, 0.0], "fov": 40 }
})";

// The sphere scene with its block at x in [x0, x1], y in [0.05, 0.15], z in [z0, z1].
std::string sphereScene(float x0, float x1, float z0, float z1) {
    std::string json = kSphereScene;
    const auto put = [&](const std::string& key, float v) {
        json.replace(json.find(key), key.size(), std::to_string(v));
    };
    put("%X0%", x0);
    put("%X1%", x1);
    put("%Z0%", z0);
    put("%Z1%", z1);
    return json;
}

TEST_F(RenderTest, ColliderIsVisibleExactlyWhereItsSphereProjects) {
    // Particles off to the side, so they do not touch the sphere's disc.
    Stage stage(sphereScene(0.3f, 0.4f, -0.04f, 0.04f));
    ASSERT_TRUE(stage.ok());
    const Image with = stage.draw();
    RenderSettings noColliders;
    noColliders.drawColliders = false;
    const Image without = stage.draw(noColliders);
    // Sphere of radius 0.1 m at (0, 0.1, 0), seen head-on from 0.9 m.
    const glm::vec3 centre = stage.camera.project({0.0f, 0.1f, 0.0f}, kSize);
    const float radius = stage.camera.project({0.1f, 0.1f, 0.0f}, kSize).x - centre.x;
    ASSERT_GT(radius, 20.0f);
    std::size_t inner = 0, innerHit = 0, outerHit = 0;
    for (std::uint32_t y = 0; y < kSize.y; ++y)
        for (std::uint32_t x = 0; x < kSize.x; ++x) {
            const float d =
                glm::length(glm::vec2(float(x) + 0.5f, float(y) + 0.5f) - glm::vec2(centre));
            const bool differs = pixelDiffers(with, without, x, y);
            if (d < 0.9f * radius) {
                ++inner;
                innerHit += differs ? 1 : 0;
            } else if (d > 1.1f * radius && differs) {
                ++outerHit;
            }
        }
    EXPECT_EQ(innerHit, inner);
    EXPECT_EQ(outerHit, 0u);
    // Shaded in its palette colour (lit from above: the top half brighter than the bottom).
    const glm::vec3 albedo = colliderColour(0);
    const glm::ivec3 top(with.at(std::uint32_t(centre.x), std::uint32_t(centre.y - 0.5f * radius)));
    const glm::ivec3 bottom(
        with.at(std::uint32_t(centre.x), std::uint32_t(centre.y + 0.5f * radius)));
    EXPECT_GT(top.r + top.g + top.b, bottom.r + bottom.g + bottom.b);
    EXPECT_EQ(top.r >= top.b, albedo.r >= albedo.b);
}

// What the full frame shows at the pixel of the sphere's centre (0, 0.1, 0): the particles'
// colour (as in the frame without colliders), the collider's (as without particles), or neither.
struct CentrePixel {
    bool particles = false;
    bool collider = false;
};

CentrePixel centrePixel(Stage& stage) {
    const Image both = stage.draw();
    RenderSettings noColliders;
    noColliders.drawColliders = false;
    const Image particlesOnly = stage.draw(noColliders);
    const Image colliderOnly = stage.drawWithoutParticles();
    const glm::vec3 c = stage.camera.project({0.0f, 0.1f, 0.0f}, kSize);
    const auto x = std::uint32_t(c.x), y = std::uint32_t(c.y);
    return {!pixelDiffers(both, particlesOnly, x, y), !pixelDiffers(both, colliderOnly, x, y)};
}

TEST_F(RenderTest, ParticlesInFrontOfAColliderHideIt) {
    // Between the eye and the sphere, with a particle on the line of sight through its centre.
    Stage stage(sphereScene(-0.05f, 0.05f, 0.2f, 0.3f));
    ASSERT_TRUE(stage.ok());
    const CentrePixel shown = centrePixel(stage);
    EXPECT_TRUE(shown.particles);
    EXPECT_FALSE(shown.collider);
}

TEST_F(RenderTest, AColliderInFrontOfParticlesHidesThem) {
    Stage stage(sphereScene(-0.05f, 0.05f, -0.3f, -0.2f)); // behind the sphere
    ASSERT_TRUE(stage.ok());
    const CentrePixel shown = centrePixel(stage);
    EXPECT_TRUE(shown.collider);
    EXPECT_FALSE(shown.particles);
}

TEST_F(RenderTest, GlassWallsShowTheWaterInsideTheTank) {
    auto scene = format::readScene(kAssets / "drop.json");
    ASSERT_TRUE(scene) << scene.error().message();
    Stage stage(std::move(*scene));
    ASSERT_TRUE(stage.ok());
    RenderSettings glass;
    RenderSettings opaque;
    opaque.glassWalls = false;
    const auto visibleWater = [&](const RenderSettings& settings) {
        const Image with = stage.draw(settings);
        const Image without = stage.drawWithoutParticles(settings);
        return compareImages(with, without).pixels;
    };
    const std::size_t throughGlass = visibleWater(glass);
    const std::size_t overWalls = visibleWater(opaque);
    EXPECT_GT(overWalls, 0u);
    EXPECT_GT(double(throughGlass), 1.2 * double(overWalls)) << throughGlass << " vs " << overWalls;
}

TEST_F(RenderTest, SpeedColoursFastParticlesWarmAndSlowOnesCool) {
    Stage stage(kBlockScene);
    ASSERT_TRUE(stage.ok());
    ParticleState slow{{-0.05f, 0.1f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0};
    ParticleState fast{{0.05f, 0.1f, 0.0f}, {2.0f, 0.0f, 0.0f}, 1};
    ASSERT_TRUE(stage.sim->setParticles({slow, fast}));
    RenderSettings speed;
    speed.colour = ColourMode::Speed;
    speed.speedRange = 2.0f;
    const Image image = stage.draw(speed);
    const glm::vec3 ps = stage.camera.project(slow.position, kSize);
    const glm::vec3 pf = stage.camera.project(fast.position, kSize);
    const glm::ivec3 cs(image.at(std::uint32_t(ps.x), std::uint32_t(ps.y)));
    const glm::ivec3 cf(image.at(std::uint32_t(pf.x), std::uint32_t(pf.y)));
    EXPECT_GT(cs.b, cs.r + 40) << "slow " << cs.r << " " << cs.g << " " << cs.b;
    EXPECT_GT(cf.r, cf.b + 40) << "fast " << cf.r << " " << cf.g << " " << cf.b;
}

TEST_F(RenderTest, DeterministicRunsRenderIdenticalImages) {
    const format::Scene scene = waveSphere();
    for (const SurfaceMode surface : {SurfaceMode::Spheres, SurfaceMode::Fluid}) {
        RenderSettings settings;
        settings.surface = surface;
        Image images[2];
        for (Image& image : images) {
            Stage stage(scene, true);
            ASSERT_TRUE(stage.ok());
            for (int step = 0; step < 6; ++step)
                stage.sim->step();
            image = stage.draw(settings);
        }
        ASSERT_FALSE(images[0].empty());
        EXPECT_TRUE(images[0].rgb == images[1].rgb)
            << surfaceModeName(surface) << ": " << compareImages(images[0], images[1]).pixels
            << " pixels differ";
    }
}

TEST_F(RenderTest, AsynchronousReadbackGivesTheSamePixelsAsReadPixels) {
    Stage stage(kBlockScene);
    ASSERT_TRUE(stage.ok());
    const Image direct = stage.draw();
    FrameReadback readback(2);
    for (std::uint64_t tag = 0; tag < 3; ++tag) // more than the ring: the oldest is waited for
        readback.request(stage.renderer->outputFramebuffer(), kSize, tag);
    const auto frames = readback.collect(true);
    ASSERT_EQ(frames.size(), 3u);
    for (std::uint64_t tag = 0; tag < 3; ++tag) {
        EXPECT_EQ(frames[tag].tag, tag);
        EXPECT_TRUE(frames[tag].image.rgb == direct.rgb);
    }
    EXPECT_EQ(readback.pending(), 0u);
}

TEST_F(RenderTest, StatisticsProbeAgreesWithTheSolversStatistics) {
    auto scene = format::readScene(kAssets / "dam-break.json");
    ASSERT_TRUE(scene) << scene.error().message();
    Stage stage(std::move(*scene));
    ASSERT_TRUE(stage.ok());
    auto probe = FluidStatsProbe::create(2);
    ASSERT_TRUE(probe) << probe.error().message();
    for (int step = 0; step < 5; ++step)
        stage.sim->step();
    ASSERT_TRUE(probe->record(*stage.sim));
    const auto measured = probe->poll(true);
    ASSERT_TRUE(measured);
    const StepStats stats = stage.sim->readStats();
    EXPECT_EQ(measured->step, 5u);
    EXPECT_EQ(measured->particles, stats.particles);
    EXPECT_NEAR(measured->avgDensityError, stats.avgDensityError, 1e-4);
    EXPECT_NEAR(measured->maxDensityError, stats.maxDensityError, 1e-6);
    EXPECT_NEAR(measured->maxSpeed, stats.maxSpeed, 1e-5);
    EXPECT_GT(measured->maxSpeed, 0.0);
    EXPECT_FALSE(probe->poll()); // nothing new
}

// Pixel distance from (px, py) to the segment a-b (pixel coordinates).
float segmentDistance(glm::vec2 p, glm::vec2 a, glm::vec2 b) {
    const glm::vec2 ab = b - a;
    const float t =
        glm::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-12f), 0.0f, 1.0f);
    return glm::length(p - (a + t * ab));
}

// The domain box's edges: drawn where the scene has a box, on the projections of its twelve
// edges and nowhere else; a scene without a box draws nothing more.
TEST_F(RenderTest, DomainBoxEdgesAreDrawnOnTheProjectedEdgesOnly) {
    const glm::vec3 lo{-0.15f, 0.0f, -0.15f};
    const glm::vec3 hi{0.15f, 0.3f, 0.15f};
    Stage stage(R"({
        "simulation": { "spacing": 0.02 },
        "fluid": [ { "box": { "min": [-0.04, 0.0, -0.04], "max": [0.04, 0.08, 0.04] } } ],
        "domain": { "min": [-0.15, 0.0, -0.15], "max": [0.15, 0.3, 0.15] },
        "camera": { "position": [0.7, 0.5, 0.8], "target": [0.0, 0.12, 0.0], "fov": 45 }
    })");
    ASSERT_TRUE(stage.ok());
    RenderSettings off;
    off.drawDomainBox = false;
    const Image with = stage.draw();
    const Image without = stage.draw(off);
    std::vector<std::pair<glm::vec2, glm::vec2>> edges;
    float length = 0.0f;
    for (int axis = 0; axis < 3; ++axis)
        for (int which = 0; which < 4; ++which) {
            glm::vec3 a, b;
            for (int k = 0; k < 3; ++k) {
                const int bit = k == (axis + 1) % 3   ? (which & 1)
                                : k == (axis + 2) % 3 ? (which >> 1) & 1
                                                      : 0;
                a[k] = bit ? hi[k] : lo[k];
                b[k] = k == axis ? hi[k] : a[k];
            }
            const glm::vec2 pa(stage.camera.project(a, kSize));
            const glm::vec2 pb(stage.camera.project(b, kSize));
            edges.emplace_back(pa, pb);
            length += glm::length(pb - pa);
        }
    std::size_t drawn = 0;
    std::size_t astray = 0;
    for (std::uint32_t y = 0; y < kSize.y; ++y)
        for (std::uint32_t x = 0; x < kSize.x; ++x) {
            if (!pixelDiffers(with, without, x, y))
                continue;
            ++drawn;
            float nearest = 1e9f;
            for (const auto& [a, b] : edges)
                nearest = std::min(nearest, segmentDistance({x + 0.5f, y + 0.5f}, a, b));
            astray += nearest > 1.5f;
        }
    // The near edges are all in view; the bottom ones lie on the floor and the far ones partly
    // behind the water, so at least a third of the total length shows.
    EXPECT_GT(double(drawn), 0.33 * double(length)) << drawn << " pixels for " << length;
    EXPECT_EQ(astray, 0u) << "of " << drawn;

    Stage open(kBlockScene); // no domain box: nothing to draw
    ASSERT_TRUE(open.ok());
    const ImageDiff same = compareImages(open.draw(), open.draw(off));
    EXPECT_EQ(same.maxChannel, 0);
}

} // namespace
} // namespace sluice::rt
