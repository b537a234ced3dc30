// The viewer's live changes: parameters applied without moving a particle or refused without a
// change, emitters off and on, reset and reload, and a body picked and pulled by the mouse.
#include <algorithm>
#include <fstream>
#include <optional>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "render/RenderTestSupport.h"
#include "viewer/ViewerPick.h"
#include "viewer/ViewerSession.h"
#include "viewer/ViewerTestScene.h"

namespace sluice::rt {
namespace {

using namespace test;

class ViewerSessionTest : public gpu::test::GpuTest {};

std::vector<ParticleState> byId(std::vector<ParticleState> particles) {
    std::sort(particles.begin(), particles.end(),
              [](const ParticleState& a, const ParticleState& b) { return a.id < b.id; });
    return particles;
}

TEST_F(ViewerSessionTest, ApplyingParametersKeepsEveryParticleAndTheClock) {
    auto session = ViewerSession::open((kAssets / "dam-break.json").string(), true, {64, 48});
    ASSERT_TRUE(session) << session.error().message();
    for (int i = 0; i < 3; ++i)
        session->step();
    const auto before = byId(session->simulation().downloadParticles());
    const double time = session->time();
    format::SimulationParams params = session->scene().simulation;
    params.xsph = 0.1f;
    params.maxIterations = 4;
    ASSERT_TRUE(session->applyParameters(params));
    EXPECT_FLOAT_EQ(session->simulation().parameters().xsph, 0.1f);
    EXPECT_EQ(session->simulation().parameters().maxIterations, 4u);
    EXPECT_FLOAT_EQ(session->scene().simulation.xsph, 0.1f); // reset keeps the edit
    const auto after = byId(session->simulation().downloadParticles());
    ASSERT_EQ(after.size(), before.size());
    for (std::size_t i = 0; i < before.size(); ++i) {
        EXPECT_EQ(after[i].id, before[i].id);
        EXPECT_EQ(after[i].position, before[i].position) << "particle " << i;
        EXPECT_EQ(after[i].velocity, before[i].velocity) << "particle " << i;
    }
    EXPECT_EQ(session->steps(), 3u);
    EXPECT_DOUBLE_EQ(session->time(), time);
    session->step();
    EXPECT_EQ(session->steps(), 4u);
    EXPECT_EQ(session->simulation().readStats().nonFinite, 0u);
}

TEST_F(ViewerSessionTest, RefusedParametersChangeNothing) {
    auto session = ViewerSession::open((kAssets / "drop.json").string(), false, {64, 48});
    ASSERT_TRUE(session) << session.error().message();
    const format::SimulationParams before = session->scene().simulation;
    format::SimulationParams bad = before;
    bad.xsph = 0.3f;
    bad.scorrDeltaQ = bad.kernelRadius; // must stay below h
    const auto refused = session->applyParameters(bad);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().code, ErrorCode::InvalidArgument);
    EXPECT_FLOAT_EQ(session->scene().simulation.xsph, before.xsph);
    EXPECT_FLOAT_EQ(session->simulation().parameters().xsph, before.xsph);
    session->step();
    EXPECT_EQ(session->simulation().readStats().nonFinite, 0u);
}

TEST_F(ViewerSessionTest, EmittersOffStopNewParticlesAndOnStartThemAgain) {
    auto session = ViewerSession::open((kAssets / "funnel.json").string(), false, {64, 48});
    ASSERT_TRUE(session) << session.error().message();
    for (int i = 0; i < 6; ++i)
        session->step();
    const std::uint32_t running = session->simulation().particleCount();
    EXPECT_GT(running, 0u);
    session->setEmittersEnabled(false);
    for (int i = 0; i < 6; ++i)
        session->step();
    EXPECT_EQ(session->simulation().particleCount(), running);
    session->setEmittersEnabled(true);
    for (int i = 0; i < 6; ++i)
        session->step();
    EXPECT_GT(session->simulation().particleCount(), running);
}

TEST_F(ViewerSessionTest, ResetAndReloadStartTheSceneAgain) {
    auto session = ViewerSession::open((kAssets / "drop.json").string(), false, {64, 48});
    ASSERT_TRUE(session) << session.error().message();
    const std::uint32_t initial = session->simulation().particleCount();
    for (int i = 0; i < 3; ++i)
        session->step();
    ASSERT_TRUE(session->reset());
    EXPECT_EQ(session->steps(), 0u);
    EXPECT_EQ(session->simulation().particleCount(), initial);
    session->step();
    ASSERT_TRUE(session->reload());
    EXPECT_EQ(session->steps(), 0u);
    EXPECT_EQ(session->renderer().size(), glm::uvec2(64, 48));
}

TEST_F(ViewerSessionTest, ReloadOfABrokenSceneKeepsTheSessionAndSaysWhy) {
    const fs::path dir = tempDir("reload");
    const fs::path file = dir / "scene.json";
    const std::string json =
        R"({ "fluid": [ { "box": { "min": [0, 0, 0], "max": [0.1, 0.1, 0.1] } } ] })";
    std::ofstream(file) << json;
    auto session = ViewerSession::open(file.string(), false, {64, 48});
    ASSERT_TRUE(session) << session.error().message();
    std::ofstream(file, std::ios::trunc) << "{ \"fluid\": [ ";
    const auto reloaded = session->reload();
    ASSERT_FALSE(reloaded);
    EXPECT_NE(reloaded.error().detail.find("scene.json"), std::string::npos);
    EXPECT_GT(session->simulation().particleCount(), 0u);
    session->step();
}

// The floating-box scene with the camera sluice-play gives it in a window of `size`.
struct BoxView {
    std::optional<ViewerSession> session;
    OrbitCamera camera;
    glm::dvec2 window{320.0, 240.0};

    explicit BoxView(const std::string& name) {
        auto opened = ViewerSession::open(writeFloatingBoxScene(tempDir(name)).string(), false,
                                          glm::uvec2(window));
        EXPECT_TRUE(opened) << opened.error().message();
        if (!opened)
            return;
        session.emplace(std::move(*opened));
        camera =
            sceneCamera(session->scene(), session->renderer().bounds(), float(window.x / window.y));
    }

    BodyState body() const { return session->simulation().bodies().at(0); }
    // The ray through the pixel where `world` appears.
    Ray rayTo(glm::vec3 world) const {
        const glm::vec3 pixel = camera.project(world, glm::uvec2(window));
        return cursorRay(camera, glm::dvec2(pixel.x, pixel.y), window);
    }
};

TEST_F(ViewerSessionTest, ARayThroughABodysCentrePixelGrabsItAndOneBesideItGrabsNothing) {
    BoxView view("grab");
    ASSERT_TRUE(view.session);
    ASSERT_TRUE(view.session->hasBodies());
    const BodyState body = view.body();
    const auto hit = view.session->grabBody(view.rayTo(body.position));
    ASSERT_TRUE(hit) << "the ray through the box's centre pixel missed it";
    EXPECT_EQ(hit->body, 0u);
    // The point is on the box's surface facing the camera: in its frame, on a face.
    const glm::vec3 local = glm::abs(hit->anchor);
    const float half = 0.5f * kFloatingBoxSide;
    EXPECT_NEAR(std::max({local.x, local.y, local.z}), half, 0.004f);
    EXPECT_LT(glm::distance(view.camera.eye(), hit->point),
              glm::distance(view.camera.eye(), body.position));
    ASSERT_TRUE(view.session->grab());
    EXPECT_EQ(view.session->grab()->body, 0u);
    EXPECT_NEAR(view.session->grab()->distance, glm::distance(view.camera.eye(), hit->point),
                1e-4f);
    EXPECT_LT(glm::distance(view.session->grab()->target, hit->point), 1e-5f);

    // Dragging moves the target along the new ray at the grab distance.
    const Ray up = view.rayTo(body.position + glm::vec3(0.0f, 0.05f, 0.0f));
    view.session->dragBody(up);
    EXPECT_LT(glm::distance(view.session->grab()->target, up.at(hit->distance)), 1e-5f);

    // A ray past the box's corner (above the water, well clear of it) grabs nothing and lets go.
    const auto missed =
        view.session->grabBody(view.rayTo(body.position + glm::vec3(0.0f, 0.15f, 0.0f)));
    EXPECT_FALSE(missed);
    EXPECT_FALSE(view.session->grab());
}

TEST_F(ViewerSessionTest, ABodyPulledUpRisesAndFallsBackWhenLetGo) {
    BoxView view("lift");
    ASSERT_TRUE(view.session);
    ViewerSession& session = *view.session;
    for (int i = 0; i < 10; ++i)
        session.step();
    const glm::vec3 start = view.body().position;
    ASSERT_TRUE(session.grabBody(view.rayTo(start)));
    // The target rises 0.15 m over a third of a second, then holds.
    for (int i = 1; i <= 45; ++i) {
        const float lift = 0.15f * std::min(1.0f, float(i) / 20.0f);
        session.dragBody(view.rayTo(start + glm::vec3(0.0f, lift, 0.0f)));
        session.step();
    }
    const glm::vec3 lifted = view.body().position;
    session.releaseBody();
    for (int i = 0; i < 45; ++i)
        session.step();
    const glm::vec3 after = view.body().position;
    // The 3 Hz spring lifts the box most of the way (it sags by g / omega^2 = 2.8 cm under the
    // box's whole weight); let go, it drops back into the water and bobs about its draft.
    EXPECT_GT(lifted.y, start.y + 0.05f) << "start " << start.y;
    EXPECT_LT(after.y, lifted.y - 0.05f);
    EXPECT_NEAR(after.y, start.y, 0.02f);
    EXPECT_EQ(session.simulation().readStats().nonFinite, 0u);
}

TEST_F(ViewerSessionTest, ResetAndReloadLetGoOfAHeldBody) {
    BoxView view("let-go");
    ASSERT_TRUE(view.session);
    ViewerSession& session = *view.session;
    ASSERT_TRUE(session.grabBody(view.rayTo(view.body().position)));
    session.step();
    ASSERT_TRUE(session.reset());
    EXPECT_FALSE(session.grab());
    ASSERT_TRUE(session.grabBody(view.rayTo(view.body().position)));
    ASSERT_TRUE(session.reload());
    EXPECT_FALSE(session.grab());
    // Dragging without a grab is a no-op, and the scene runs on.
    session.dragBody(view.rayTo(glm::vec3(0.0f, 0.3f, 0.0f)));
    session.releaseBody();
    for (int i = 0; i < 3; ++i)
        session.step();
    EXPECT_EQ(session.simulation().readStats().nonFinite, 0u);
}

} // namespace
} // namespace sluice::rt
