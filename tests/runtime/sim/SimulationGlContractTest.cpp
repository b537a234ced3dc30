// What a game sees of Sluice's GL (docs/embedding.md): the bodies' forces read without waiting,
// and the GL state a step changes, exactly the documented list.
#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "bodies/BodyTank.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

class SimulationGlContract : public GpuTest {};

// A pool with a box standing in it, so every kind of binding a step makes is made.
format::Scene sceneWithCollider(std::vector<format::ColliderAsset>& assets) {
    format::Scene scene = testscene::smallScene({8, 6, 8}, 0.02f, 2);
    assets.push_back(testscene::boxColliderAsset({-0.02, -0.05, -0.05}, {0.02, 0.05, 0.05}, 0.01));
    format::SceneCollider box;
    box.asset = "box.slc";
    box.translation = glm::vec3(0.04f, 0.06f, 0.08f);
    scene.colliders.push_back(box);
    return scene;
}

// ---------------------------------------------------------------------------------------------
// Forces read without waiting

TEST_F(SimulationGlContract, LatestBodiesAreACompletedStepsBodiesReadWithoutWaiting) {
    format::Scene scene = bodytest::tankScene({0.24f, 0.24f}, 0.1f, 0.3f, 2);
    scene.colliders.push_back(bodytest::cubeBody({0.12f, 0.12f, 0.12f}, 0.5f));
    auto sim = Simulation::create(scene, {bodytest::cubeAsset(0.08f)});
    ASSERT_TRUE(sim) << sim.error().message();
    EXPECT_FALSE(sim->latestBodies()) << "no step has completed";
    for (int i = 0; i < 4; ++i) {
        sim->step();
        // Whatever it returns is a step that has run, never a later one.
        if (auto reading = sim->latestBodies()) {
            EXPECT_LE(reading->step, sim->steps());
        }
    }
    glFinish(); // the test waits so the newest copy is done; a game never needs to
    auto reading = sim->latestBodies();
    ASSERT_TRUE(reading);
    EXPECT_EQ(reading->step, sim->steps());
    EXPECT_DOUBLE_EQ(reading->time, sim->time());
    const std::vector<BodyState> now = sim->bodies();
    ASSERT_EQ(reading->bodies.size(), 1u);
    EXPECT_EQ(reading->bodies[0].force, now[0].force);
    EXPECT_EQ(reading->bodies[0].torque, now[0].torque);
    EXPECT_EQ(reading->bodies[0].position, now[0].position);
    EXPECT_GT(reading->bodies[0].force.y, 0.0f) << "the water holds the falling cube up";
}

TEST_F(SimulationGlContract, LatestBodiesIsEmptyWithoutBodies) {
    auto sim = Simulation::create(testscene::smallScene({4, 4, 4}), {});
    ASSERT_TRUE(sim) << sim.error().message();
    sim->step();
    glFinish();
    EXPECT_FALSE(sim->latestBodies());
}

// ---------------------------------------------------------------------------------------------
// GL citizenship: step() changes only the state docs/embedding.md lists

struct GlState {
    std::vector<GLint> storage, uniform, bufferTextures, textures2d;
    GLint program = 0, indirect = 0, array = 0, vertexArray = 0, framebuffer = 0, active = 0;
    GLint pack = 0, unpack = 0, genericStorage = 0, genericUniform = 0;
};

GlState readGlState() {
    GlState s;
    GLint storage = 0, uniform = 0, units = 0;
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &storage);
    glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &uniform);
    glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &units);
    for (GLint i = 0; i < storage; ++i)
        glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, GLuint(i), &s.storage.emplace_back());
    for (GLint i = 0; i < uniform; ++i)
        glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, GLuint(i), &s.uniform.emplace_back());
    glGetIntegerv(GL_ACTIVE_TEXTURE, &s.active);
    for (GLint u = 0; u < std::min(units, 32); ++u) {
        glActiveTexture(GLenum(GL_TEXTURE0 + u));
        glGetIntegerv(GL_TEXTURE_BINDING_BUFFER, &s.bufferTextures.emplace_back());
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &s.textures2d.emplace_back());
    }
    glActiveTexture(GLenum(s.active));
    glGetIntegerv(GL_CURRENT_PROGRAM, &s.program);
    glGetIntegerv(GL_DISPATCH_INDIRECT_BUFFER_BINDING, &s.indirect);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &s.array);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &s.vertexArray);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s.framebuffer);
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &s.pack);
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &s.unpack);
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_BINDING, &s.genericStorage);
    glGetIntegerv(GL_UNIFORM_BUFFER_BINDING, &s.genericUniform);
    return s;
}

TEST_F(SimulationGlContract, StepChangesOnlyTheGlStateItDocuments) {
    std::vector<format::ColliderAsset> assets;
    const format::Scene scene = sceneWithCollider(assets);
    auto sim = Simulation::create(scene, assets);
    ASSERT_TRUE(sim) << sim.error().message();
    // A game's state: a sentinel buffer everywhere Sluice might bind one, a texture on every unit.
    GLuint buffer = 0, texture = 0, bufferTexture = 0, vao = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferData(buffer, 256, nullptr, GL_STATIC_DRAW);
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, GL_RGBA8, 4, 4);
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &bufferTexture);
    glTextureBuffer(bufferTexture, GL_R32F, buffer);
    glCreateVertexArrays(1, &vao);
    const GlState before = [&] {
        GlState probe = readGlState();
        for (std::size_t i = 0; i < probe.storage.size(); ++i)
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(i), buffer);
        for (std::size_t i = 0; i < probe.uniform.size(); ++i)
            glBindBufferBase(GL_UNIFORM_BUFFER, GLuint(i), buffer);
        for (std::size_t u = 0; u < probe.textures2d.size(); ++u) {
            glBindTextureUnit(GLuint(u), texture);
            glBindTextureUnit(GLuint(u), bufferTexture);
        }
        glActiveTexture(GL_TEXTURE3);
        glBindVertexArray(vao);
        glBindBuffer(GL_ARRAY_BUFFER, buffer);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buffer);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, buffer);
        return readGlState();
    }();
    ASSERT_EQ(before.storage.back(), GLint(buffer));
    sim->step();
    const GlState after = readGlState();
    // Documented as changed: storage bindings 0 to 27 and the generic one, uniform bindings 0 and
    // 1 and the generic one, buffer textures on units 0 to 6, the program, the indirect buffer.
    for (std::size_t i = 28; i < before.storage.size(); ++i)
        EXPECT_EQ(after.storage[i], before.storage[i]) << "storage binding " << i;
    for (std::size_t i = 2; i < before.uniform.size(); ++i)
        EXPECT_EQ(after.uniform[i], before.uniform[i]) << "uniform binding " << i;
    for (std::size_t u = 0; u < before.textures2d.size(); ++u) {
        EXPECT_EQ(after.textures2d[u], before.textures2d[u]) << "2D texture on unit " << u;
        if (u >= 7) {
            EXPECT_EQ(after.bufferTextures[u], before.bufferTextures[u]) << "unit " << u;
        }
    }
    EXPECT_EQ(after.active, before.active);
    EXPECT_EQ(after.array, before.array);
    EXPECT_EQ(after.vertexArray, before.vertexArray);
    EXPECT_EQ(after.framebuffer, before.framebuffer);
    EXPECT_EQ(after.pack, before.pack);
    EXPECT_EQ(after.unpack, before.unpack);
    // The list is not longer than what changes: these did change.
    EXPECT_NE(after.program, before.program);
    EXPECT_NE(after.indirect, before.indirect);
    EXPECT_NE(after.storage[0], before.storage[0]);
    EXPECT_NE(after.uniform[0], before.uniform[0]);
    EXPECT_NE(after.bufferTextures[0], before.bufferTextures[0]);
    glBindVertexArray(0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glDeleteVertexArrays(1, &vao);
    glDeleteTextures(1, &bufferTexture);
    glDeleteTextures(1, &texture);
    glDeleteBuffers(1, &buffer);
}

} // namespace
} // namespace sluice::rt
