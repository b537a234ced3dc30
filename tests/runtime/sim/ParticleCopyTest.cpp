// What a game draws from (docs/embedding.md, "The view and synchronisation"): the view's draw
// command counts the live particles, which lead the slots, and copies in id order fill buffers
// the game owns, live ids with w = 1 and every other entry zero.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

class ParticleCopy : public GpuTest {};

// A buffer the game creates itself, `entries` vec4 of `fill`.
struct GameBuffer {
    GLuint name = 0;
    std::size_t entries = 0;
    GameBuffer(std::size_t n, float fill) : entries(n) {
        glCreateBuffers(1, &name);
        const std::vector<glm::vec4> values(n, glm::vec4(fill));
        glNamedBufferStorage(name, GLsizeiptr(n * sizeof(glm::vec4)), values.data(),
                             GL_DYNAMIC_STORAGE_BIT);
    }
    ~GameBuffer() { glDeleteBuffers(1, &name); }
    GameBuffer(const GameBuffer&) = delete;
    GameBuffer& operator=(const GameBuffer&) = delete;
    std::vector<glm::vec4> read() const {
        std::vector<glm::vec4> out(entries);
        glGetNamedBufferSubData(name, 0, GLsizeiptr(entries * sizeof(glm::vec4)), out.data());
        return out;
    }
};

std::map<std::uint32_t, ParticleState> byId(const std::vector<ParticleState>& particles) {
    std::map<std::uint32_t, ParticleState> out;
    for (const ParticleState& p : particles)
        out[p.id] = p;
    return out;
}

std::vector<std::uint32_t> drawCommand(const Simulation& sim) {
    std::vector<std::uint32_t> command(4);
    glGetNamedBufferSubData(sim.particleView().drawArgs, 0, 16, command.data());
    return command;
}

TEST_F(ParticleCopy, CopiesInIdOrderWithEveryOtherEntryZero) {
    format::Scene scene = testscene::smallScene({4, 4, 4}, 0.02f, 2); // ids 0 to 63
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    sim->step();
    ASSERT_TRUE(sim->removeParticles({3, 10, 40}));
    sim->step();
    const std::map<std::uint32_t, ParticleState> live = byId(sim->downloadParticles());
    ASSERT_EQ(live.size(), 61u);
    // The removed slots are still in use (w = 1) until a fenced count drops them: skipped.
    ASSERT_EQ(sim->particleView().count, 64u);

    // Ids 0 to 69: 64 to 69 were never given out.
    GameBuffer positions(70, 7.0f), velocities(70, 7.0f);
    ASSERT_TRUE(sim->copyParticlesById({positions.name, velocities.name, 0, 70}));
    const std::vector<glm::vec4> p = positions.read(), v = velocities.read();
    for (std::uint32_t id = 0; id < 70; ++id) {
        const auto it = live.find(id);
        if (it == live.end()) {
            EXPECT_EQ(p[id], glm::vec4(0.0f)) << "id " << id;
            EXPECT_EQ(v[id], glm::vec4(0.0f)) << "id " << id;
            continue;
        }
        EXPECT_EQ(p[id], glm::vec4(it->second.position, 1.0f)) << "id " << id;
        EXPECT_EQ(v[id], glm::vec4(it->second.velocity, 1.0f)) << "id " << id;
    }

    // A page of ten ids, positions only, into a buffer of exactly their size.
    GameBuffer page(10, 7.0f);
    ASSERT_TRUE(sim->copyParticlesById({page.name, 0, 35, 10}));
    const std::vector<glm::vec4> q = page.read();
    for (std::uint32_t k = 0; k < 10; ++k)
        EXPECT_EQ(q[k], k + 35 == 40 ? glm::vec4(0.0f) : glm::vec4(live.at(k + 35).position, 1.0f))
            << "id " << k + 35;
}

TEST_F(ParticleCopy, TheDrawCommandCountsTheLiveParticlesThatLeadTheSlots) {
    format::Scene scene = testscene::smallScene({6, 4, 6}, 0.02f, 2); // 144
    scene.simulation.capacity = 200;
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    EXPECT_EQ(drawCommand(*sim), (std::vector<std::uint32_t>{144, 1, 0, 0}));
    ASSERT_TRUE(sim->addParticles({{0.05f, 0.2f, 0.05f}, {0.07f, 0.2f, 0.05f}}));
    EXPECT_EQ(drawCommand(*sim)[0], 146u);
    sim->step();
    EXPECT_EQ(drawCommand(*sim)[0], 146u);
    // The top layer removed: the command drops at once, the view's count a step or two later.
    ASSERT_TRUE(sim->removeParticlesIn({-1.0f, 0.065f, -1.0f}, {1.0f, 1.0f, 1.0f}));
    sim->step();
    const std::uint32_t live = sim->liveParticleCount();
    EXPECT_LT(live, 146u - 30u);
    EXPECT_EQ(drawCommand(*sim), (std::vector<std::uint32_t>{live, 1, 0, 0}));
    const ParticleView view = sim->particleView();
    std::vector<glm::vec4> slots(view.count);
    glGetNamedBufferSubData(view.positions, 0, GLsizeiptr(view.count * 16), slots.data());
    for (std::uint32_t k = 0; k < view.count; ++k)
        EXPECT_EQ(slots[k].w, k < live ? 0.0f : 1.0f) << "slot " << k;
}

TEST_F(ParticleCopy, RefusesANameThatIsNoBufferAndABufferTooSmallWritingNothing) {
    format::Scene scene = testscene::smallScene({4, 4, 4});
    auto sim = Simulation::create(scene, {});
    ASSERT_TRUE(sim) << sim.error().message();
    GameBuffer small(8, 7.0f);
    auto out = sim->copyParticlesById({small.name, 0, 0, 9});
    ASSERT_FALSE(out);
    EXPECT_EQ(out.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(out.error().message().find("holds 128 bytes; 9 ids need 144"), std::string::npos)
        << out.error().message();
    out = sim->copyParticlesById({small.name, 424242, 0, 8});
    ASSERT_FALSE(out);
    EXPECT_NE(out.error().message().find("velocities buffer 424242 is no GL buffer"),
              std::string::npos)
        << out.error().message();
    EXPECT_EQ(sim->copyParticlesById({0, 0, 0, 8}).error().code, ErrorCode::InvalidArgument);
    for (const glm::vec4& entry : small.read())
        EXPECT_EQ(entry, glm::vec4(7.0f));
    EXPECT_TRUE(sim->copyParticlesById({0, 0, 0, 0})); // nothing to copy
}

} // namespace
} // namespace sluice::rt
