// The collider record as the GL lays it out, against the C++ struct (shared/Pbf.h, GpuCollider):
// the uniform block every pass reads (std140) and the body pass's storage view (std430), from
// the linked programs' interface queries. The static_asserts in Pbf.h pin only the C++ side.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "RuntimeTestScenes.h"
#include "shared/Bodies.h"
#include "shared/Pbf.h"
#include "sluice/gpu/Program.h"
#include "sluice/gpu/colliders/ColliderRecord.h"
#include "sluice/rt/RuntimeShaders.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {
namespace {

using gpu::test::GpuTest;

class ColliderRecordLayout : public GpuTest {};

using shared::GpuCollider;

// Every member and its byte offset in the C++ struct.
const std::vector<std::pair<std::string, std::size_t>>& members() {
    static const std::vector<std::pair<std::string, std::size_t>> all{
        {"worldToGrid", offsetof(GpuCollider, worldToGrid)},
        {"boundCentre", offsetof(GpuCollider, boundCentre)},
        {"boundRadius", offsetof(GpuCollider, boundRadius)},
        {"motion", offsetof(GpuCollider, motion)},
        {"origin", offsetof(GpuCollider, origin)},
        {"voxelSize", offsetof(GpuCollider, voxelSize)},
        {"boxMax", offsetof(GpuCollider, boxMax)},
        {"scale", offsetof(GpuCollider, scale)},
        {"dims", offsetof(GpuCollider, dims)},
        {"sdfOffset", offsetof(GpuCollider, sdfOffset)},
        {"friction", offsetof(GpuCollider, friction)},
        {"body", offsetof(GpuCollider, body)},
        {"gridKind", offsetof(GpuCollider, gridKind)},
        {"volumeMap", offsetof(GpuCollider, volumeMap)}};
    return all;
}

// One integer property of a named resource of `program`, or -1 when the resource is not there.
GLint property(GLuint program, GLenum interface, const std::string& name, GLenum what) {
    const GLuint index = glGetProgramResourceIndex(program, interface, name.c_str());
    if (index == GL_INVALID_INDEX)
        return -1;
    GLint value = -1;
    glGetProgramResourceiv(program, interface, index, 1, &what, 1, nullptr, &value);
    return value;
}

TEST_F(ColliderRecordLayout, TheUniformBlockHoldsTheCppRecordsMemberForMember) {
    auto stats = gpu::Program::compute("pbf_stats.comp", shaders::shaderSource("pbf_stats.comp"));
    ASSERT_TRUE(stats) << stats.error().message();
    EXPECT_EQ(property(stats->id(), GL_UNIFORM_BLOCK, "CollidersBlock", GL_BUFFER_DATA_SIZE),
              GLint(gpu::kColliderRecordBytes));
    EXPECT_EQ(property(stats->id(), GL_UNIFORM_BLOCK, "CollidersBlock", GL_BUFFER_BINDING),
              GLint(shared::kBindCollidersUniform));
    // Every member of a std140 block is active; record 1 shows the array's stride too.
    for (const auto& [name, offset] : members())
        EXPECT_EQ(property(stats->id(), GL_UNIFORM, "colliders[1]." + name, GL_OFFSET),
                  GLint(sizeof(GpuCollider) + offset))
            << name;
}

TEST_F(ColliderRecordLayout, TheBodyPassWritesTheCppRecordsMemberForMember) {
    const std::vector<gpu::ShaderDefine> lanes{
        {"SLUICE_BODY_LANES", std::to_string(shared::kBodyLanesSoftware)}};
    auto bodies =
        gpu::Program::compute("pbf_bodies.comp", shaders::shaderSource("pbf_bodies.comp"), lanes);
    ASSERT_TRUE(bodies) << bodies.error().message();
    EXPECT_EQ(property(bodies->id(), GL_SHADER_STORAGE_BLOCK, "CollidersOut", GL_BUFFER_BINDING),
              GLint(shared::kBindColliders));
    // What the pass writes (writeCollider); a driver may leave the other members out.
    for (const char* name : {"worldToGrid", "boundCentre", "motion", "scale"}) {
        std::size_t offset = 0;
        for (const auto& m : members())
            if (m.first == name)
                offset = m.second;
        const std::string variable = std::string("colliderRecords[0].") + name;
        EXPECT_EQ(property(bodies->id(), GL_BUFFER_VARIABLE, variable, GL_OFFSET), GLint(offset))
            << name;
        EXPECT_EQ(property(bodies->id(), GL_BUFFER_VARIABLE, variable, GL_TOP_LEVEL_ARRAY_STRIDE),
                  GLint(sizeof(GpuCollider)))
            << name;
    }
}

// The scene reader refuses more than 64 colliders; a scene built in code is refused as well,
// before anything is allocated (the uniform block holds 64 records).
TEST_F(ColliderRecordLayout, ASceneBuiltInCodeWithMoreThan64CollidersIsRefused) {
    format::Scene scene = testscene::emptyScene();
    const format::ColliderAsset box =
        testscene::boxColliderAsset({0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}, 0.02);
    for (std::uint32_t n : {64u, 65u}) {
        scene.colliders.assign(n, format::SceneCollider{});
        for (format::SceneCollider& c : scene.colliders)
            c.asset = "box.slc";
        auto sim = Simulation::create(scene, std::vector<format::ColliderAsset>(n, box));
        if (n == 64) {
            EXPECT_TRUE(sim) << sim.error().message();
            continue;
        }
        ASSERT_FALSE(sim);
        EXPECT_EQ(sim.error().code, ErrorCode::InvalidArgument);
        EXPECT_NE(sim.error().message().find("more than the limit 64"), std::string::npos)
            << sim.error().message();
    }
}

} // namespace
} // namespace sluice::rt
