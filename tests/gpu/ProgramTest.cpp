// Program: source assembly, compile and link errors with logs, uniforms, dispatch and chunking.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/GpuShaders.h"
#include "sluice/gpu/Program.h"

namespace sluice::gpu {
namespace {

using ComputeProgram = test::GpuTest;
using GraphicsProgram = test::GpuTest;

/// Whether a driver info log points at `line` of source string 0: Mesa writes "0:7(12): error",
/// NVIDIA "0(7) : error".
bool logNamesLine(const std::string& log, int line) {
    const std::string n = std::to_string(line);
    for (const std::string& form : {"0:" + n + "(", "0:" + n + ":", "0(" + n + ")"})
        if (log.find(form) != std::string::npos)
            return true;
    return false;
}

TEST(ShaderSource, AddsVersionDefinesAndALineDirectiveWhenTheSourceHasNoVersion) {
    const std::vector<ShaderDefine> defines{{"COUNT", "3"}, {"SCALE", "0.5"}};
    EXPECT_EQ(assembleShaderSource("void main() {}\n", defines),
              "#version 450 core\n#define COUNT 3\n#define SCALE 0.5\n#line 1\nvoid main() {}\n");
}

TEST(ShaderSource, InsertsDefinesAfterTheSourcesOwnVersionLine) {
    const std::vector<ShaderDefine> defines{{"COUNT", "3"}};
    EXPECT_EQ(assembleShaderSource("// header\n  #version 460 core\nvoid main() {}", defines),
              "// header\n  #version 460 core\n#define COUNT 3\n#line 3\nvoid main() {}");
}

TEST(ShaderSource, RejectsADefineThatIsNotAnIdentifier) {
    const std::vector<ShaderDefine> defines{{"1BAD", "3"}};
    EXPECT_THROW(assembleShaderSource("void main() {}", defines), std::runtime_error);
}

TEST(GroupCount, RoundsUpToWholeGroups) {
    EXPECT_EQ(groupCount(0, 64), 0u);
    EXPECT_EQ(groupCount(1, 64), 1u);
    EXPECT_EQ(groupCount(64, 64), 1u);
    EXPECT_EQ(groupCount(65, 64), 2u);
    EXPECT_EQ(groupCount(100000, 256), 391u);
    EXPECT_EQ(groupCount(glm::uvec3(37, 29, 11), glm::uvec3(4)), glm::uvec3(10, 8, 3));
    EXPECT_THROW(groupCount(10, 0), std::runtime_error);
}

TEST_F(ComputeProgram, SaxpyOver100kElementsMatchesTheCpu) {
    auto program = Program::compute("saxpy.comp", R"(
        layout(local_size_x = 256) in;
        layout(std430, binding = 0) readonly buffer X { float x[]; };
        layout(std430, binding = 1) writeonly buffer Y { float y[]; };
        uniform float a;
        uniform float b;
        uniform uint n;
        void main() {
            uint i = gl_GlobalInvocationID.x;
            if (i < n)
                y[i] = a * x[i] + b;
        }
    )");
    ASSERT_TRUE(program) << program.error().message();

    constexpr std::uint32_t kCount = 100000;
    std::vector<float> x(kCount);
    for (std::uint32_t i = 0; i < kCount; ++i)
        x[i] = 100.0f * std::sin(0.001f * static_cast<float>(i)) + 0.25f;
    auto input = Buffer::createFrom(x, "x");
    auto output = Buffer::create(kCount * sizeof(float), "y");
    ASSERT_TRUE(input && output);
    input->bindStorage(0);
    output->bindStorage(1);
    const float a = 2.5f;
    const float b = -1.25f;
    program->set("a", a);
    program->set("b", b);
    program->set("n", kCount);
    program->dispatch(groupCount(kCount, program->localSize().x));

    const std::vector<float> y = output->download<float>();
    ASSERT_EQ(y.size(), kCount);
    for (std::uint32_t i = 0; i < kCount; ++i) {
        // The GPU may fuse a * x + b; both roundings lie within a few ulp of the exact value.
        const float expected = a * x[i] + b;
        ASSERT_NEAR(y[i], expected, 1e-6f * std::max(1.0f, std::abs(expected))) << "at " << i;
    }
}

TEST_F(ComputeProgram, ReportsASyntaxErrorWithItsNameAndLine) {
    auto program = Program::compute("broken.comp", "layout(local_size_x = 1) in;\n"
                                                   "void main() {\n"
                                                   "    float ok = 1.0;\n"
                                                   "    float broken = ok +* ;\n"
                                                   "}\n");
    ASSERT_FALSE(program);
    EXPECT_EQ(program.error().code, ErrorCode::ShaderCompile);
    const std::string& detail = program.error().detail;
    EXPECT_NE(detail.find("broken.comp"), std::string::npos) << detail;
    EXPECT_TRUE(logNamesLine(detail, 4)) << detail;
}

TEST_F(ComputeProgram, KeepsLineNumbersWhenTheSourceHasItsOwnVersionAndDefines) {
    const std::vector<ShaderDefine> defines{{"ONE", "1"}, {"TWO", "2"}};
    auto program = Program::compute("versioned.comp",
                                    "#version 450 core\n"
                                    "layout(local_size_x = 1) in;\n"
                                    "void main() {\n"
                                    "    int fine = ONE + TWO;\n"
                                    "    int broken = undeclared;\n"
                                    "}\n",
                                    defines);
    ASSERT_FALSE(program);
    EXPECT_EQ(program.error().code, ErrorCode::ShaderCompile);
    EXPECT_TRUE(logNamesLine(program.error().detail, 5)) << program.error().detail;
}

TEST_F(ComputeProgram, ReportsAMissingMainAsShaderLink) {
    auto program = Program::compute("nomain.comp", "layout(local_size_x = 1) in;\n"
                                                   "void helper() {}\n");
    ASSERT_FALSE(program);
    EXPECT_EQ(program.error().code, ErrorCode::ShaderLink) << program.error().message();
    EXPECT_NE(program.error().detail.find("nomain.comp"), std::string::npos);
}

TEST_F(ComputeProgram, UsesInjectedDefinesAndReportsItsLocalSize) {
    const std::vector<ShaderDefine> defines{{"VALUE", "41u"}, {"STEP", "1u"}};
    auto program = Program::compute("defines.comp", R"(
        layout(local_size_x = 8, local_size_y = 4, local_size_z = 2) in;
        layout(std430, binding = 0) writeonly buffer Out { uint values[]; };
        void main() { values[gl_LocalInvocationIndex] = VALUE + STEP; }
    )",
                                    defines);
    ASSERT_TRUE(program) << program.error().message();
    EXPECT_EQ(program->localSize(), glm::uvec3(8, 4, 2));
    auto output = Buffer::create(64 * sizeof(std::uint32_t));
    ASSERT_TRUE(output);
    output->clear();
    output->bindStorage(0);
    program->dispatch(1);
    EXPECT_EQ(output->download<std::uint32_t>(), std::vector<std::uint32_t>(64, 42u));
}

TEST_F(ComputeProgram, KnowsWhichUniformsAreActive) {
    auto program = Program::compute("uniforms.comp", R"(
        layout(local_size_x = 1) in;
        layout(std430, binding = 0) writeonly buffer Out { float values[]; };
        uniform float scale;
        uniform float weights[3];
        uniform float unused;
        void main() { values[0] = scale * weights[2]; }
    )");
    ASSERT_TRUE(program) << program.error().message();
    EXPECT_TRUE(program->hasUniform("scale"));
    EXPECT_TRUE(program->hasUniform("weights"));
    EXPECT_TRUE(program->hasUniform("weights[0]"));
    EXPECT_FALSE(program->hasUniform("unused")); // optimized away
    EXPECT_FALSE(program->hasUniform("nope"));
    program->set("unused", 1.0f); // ignored, as GL ignores location -1
}

TEST_F(ComputeProgram, ChunkedDispatchCoversEveryInvocationOnceLikeOneDispatch) {
    // The shared header's GLSL (embedded by the gpu library) provides SLUICE_GLOBAL_ID.
    const std::string source = std::string(shaders::shaderSource("ChunkedDispatch.h")) + R"(
        layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
        layout(std430, binding = 0) writeonly buffer Values { uint values[]; };
        layout(std430, binding = 1) buffer Visits { uint visits[]; };
        uniform uvec3 dims;
        void main() {
            uvec3 p = SLUICE_GLOBAL_ID;
            if (any(greaterThanEqual(p, dims)))
                return;
            uint index = p.x + dims.x * (p.y + dims.y * p.z);
            values[index] = index * 3u + p.z;
            atomicAdd(visits[index], 1u);
        }
    )";
    auto program = Program::compute("grid.comp", source);
    ASSERT_TRUE(program) << program.error().message();

    const glm::uvec3 dims(37, 29, 11);
    const std::size_t count = std::size_t{dims.x} * dims.y * dims.z;
    const glm::uvec3 groups = groupCount(dims, program->localSize());
    ASSERT_EQ(groups, glm::uvec3(10, 8, 3));
    auto values = Buffer::create(count * sizeof(std::uint32_t), "values");
    auto visits = Buffer::create(count * sizeof(std::uint32_t), "visits");
    ASSERT_TRUE(values && visits);
    values->bindStorage(0);
    visits->bindStorage(1);
    program->set("dims", dims);

    auto run = [&](std::uint64_t maxGroups) {
        values->clear();
        visits->clear();
        const std::uint32_t dispatches = program->dispatchChunked(groups, maxGroups);
        return std::make_tuple(dispatches, values->download<std::uint32_t>(),
                               visits->download<std::uint32_t>());
    };
    const auto [oneDispatch, oneValues, oneVisits] = run(groups.x * groups.y * groups.z);
    EXPECT_EQ(oneDispatch, 1u);
    for (std::size_t i = 0; i < count; ++i) {
        const auto z = static_cast<std::uint32_t>(i / (dims.x * dims.y));
        ASSERT_EQ(oneValues[i], static_cast<std::uint32_t>(i) * 3u + z) << "at " << i;
    }
    EXPECT_EQ(oneVisits, std::vector<std::uint32_t>(count, 1u));

    // 7 groups: partial x rows -> ceil(10 / 7) * 8 * 3 dispatches. 25: 2-row slabs -> 4 * 3.
    for (auto [maxGroups, expectedDispatches] : {std::pair<std::uint64_t, std::uint32_t>{7, 48},
                                                 std::pair<std::uint64_t, std::uint32_t>{25, 12},
                                                 std::pair<std::uint64_t, std::uint32_t>{1, 240}}) {
        const auto [dispatches, chunkValues, chunkVisits] = run(maxGroups);
        EXPECT_EQ(dispatches, expectedDispatches) << "max " << maxGroups;
        EXPECT_EQ(chunkValues, oneValues) << "max " << maxGroups;
        EXPECT_EQ(chunkVisits, oneVisits) << "max " << maxGroups;
    }
}

TEST_F(ComputeProgram, RefusesToSplitAShaderWithoutTheGroupOffset) {
    auto program = Program::compute("plain.comp", R"(
        layout(local_size_x = 1) in;
        layout(std430, binding = 0) writeonly buffer Out { uint values[]; };
        void main() { values[gl_GlobalInvocationID.x] = 1u; }
    )");
    ASSERT_TRUE(program) << program.error().message();
    EXPECT_THROW(program->dispatchChunked(glm::uvec3(4, 1, 1), 2), std::runtime_error);
}

TEST_F(GraphicsProgram, LinksAVertexFragmentPairThatCannotBeDispatched) {
    auto program = Program::graphics("tint", R"(
        layout(location = 0) in vec3 position;
        out vec3 color;
        void main() { color = position; gl_Position = vec4(position, 1.0); }
    )",
                                     R"(
        in vec3 color;
        out vec4 fragColor;
        uniform vec4 tint;
        void main() { fragColor = vec4(color, 1.0) * tint; }
    )");
    ASSERT_TRUE(program) << program.error().message();
    EXPECT_EQ(program->localSize(), glm::uvec3(0));
    EXPECT_TRUE(program->hasUniform("tint"));
    EXPECT_THROW(program->dispatch(1), std::runtime_error);
}

TEST_F(GraphicsProgram, ReportsMismatchedStageInterfacesAsShaderLink) {
    auto program = Program::graphics("mismatch", R"(
        out vec4 color;
        void main() { color = vec4(1.0); gl_Position = vec4(0.0); }
    )",
                                     R"(
        in vec3 color;
        out vec4 fragColor;
        void main() { fragColor = vec4(color, 1.0); }
    )");
    ASSERT_FALSE(program);
    EXPECT_EQ(program.error().code, ErrorCode::ShaderLink) << program.error().message();
    EXPECT_NE(program.error().detail.find("mismatch"), std::string::npos);
}

} // namespace
} // namespace sluice::gpu
