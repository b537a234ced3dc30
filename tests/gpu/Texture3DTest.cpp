// Texture3D (R32F): round trip, trilinear sampling in a compute shader, size limits.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"
#include "sluice/gpu/Texture3D.h"

namespace sluice::gpu {
namespace {

using Texture3DTest = test::GpuTest;

TEST_F(Texture3DTest, RoundTripsR32fTexelsInXFastestOrder) {
    const glm::uvec3 dims(5, 4, 3);
    std::vector<float> texels(60);
    for (std::size_t i = 0; i < texels.size(); ++i)
        texels[i] = 0.5f * static_cast<float>(i) - 7.25f;
    auto texture = Texture3D::createR32F(dims, "sdf");
    ASSERT_TRUE(texture) << texture.error().message();
    EXPECT_EQ(texture->dims(), dims);
    texture->upload(texels);
    EXPECT_EQ(texture->download(), texels);
}

TEST_F(Texture3DTest, SamplesTrilinearlyAndClampsAtTheEdges) {
    // 2x2x2 texels with value x + 2y + 4z: trilinear interpolation reproduces a linear function.
    std::vector<float> texels(8);
    for (int i = 0; i < 8; ++i)
        texels[static_cast<std::size_t>(i)] = static_cast<float>(i);
    auto texture = Texture3D::createR32F(glm::uvec3(2), "ramp");
    ASSERT_TRUE(texture);
    texture->upload(texels);

    auto program = Program::compute("sample.comp", R"(
        layout(local_size_x = 1) in;
        layout(binding = 0) uniform sampler3D field;
        layout(std430, binding = 0) writeonly buffer Out { float values[]; };
        void main() {
            values[0] = texture(field, vec3(0.5)).r;                // centre: mean of all
            values[1] = texture(field, vec3(0.25, 0.25, 0.75)).r;   // texel centres (0,0,1)
            values[2] = texture(field, vec3(0.5, 0.25, 0.25)).r;    // between x texels
            values[3] = texture(field, vec3(-1.0, 2.0, 0.25)).r;    // clamped to (0,1,0)
        }
    )");
    ASSERT_TRUE(program) << program.error().message();
    auto output = Buffer::create(4 * sizeof(float));
    ASSERT_TRUE(output);
    output->bindStorage(0);
    texture->bindTexture(0);
    program->dispatch(1);
    const std::vector<float> values = output->download<float>();
    // Filtering hardware may use 8-bit fractional weights: 1/256 of the range 7.
    constexpr float kTolerance = 7.0f / 256.0f;
    EXPECT_NEAR(values[0], 3.5f, kTolerance);
    EXPECT_NEAR(values[1], 4.0f, kTolerance);
    EXPECT_NEAR(values[2], 0.5f, kTolerance);
    EXPECT_NEAR(values[3], 2.0f, kTolerance);
}

TEST_F(Texture3DTest, RejectsSizesAboveTheGlLimitAndZero) {
    const std::uint32_t limit = context().info().max3DTextureSize;
    auto tooBig = Texture3D::createR32F(glm::uvec3(limit + 1, 1, 1));
    ASSERT_FALSE(tooBig);
    EXPECT_EQ(tooBig.error().code, ErrorCode::SizeOverflow);
    auto empty = Texture3D::createR32F(glm::uvec3(4, 0, 4));
    ASSERT_FALSE(empty);
    EXPECT_EQ(empty.error().code, ErrorCode::InvalidArgument);
}

} // namespace
} // namespace sluice::gpu
