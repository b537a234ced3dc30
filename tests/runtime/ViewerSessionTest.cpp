// The viewer's live changes: parameters applied without moving a particle or refused without a
// change, emitters off and on, reset and reload.
#include <algorithm>
#include <fstream>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RenderTestSupport.h"
#include "ViewerSession.h"

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

} // namespace
} // namespace sluice::rt
