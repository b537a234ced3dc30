// BufferTexture (texel views of a Buffer): exact fetches in each format, a shader's writes seen
// after the fetch barrier, and what it refuses.
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/BufferTexture.h"
#include "sluice/gpu/Program.h"

namespace sluice::gpu {
namespace {

using BufferTextureTest = test::GpuTest;

// Copies texel i of the view on unit 0 to out[i], for i below uCount.
Result<Program> copyProgram() {
    return Program::compute("fetch.comp", R"(
        layout(local_size_x = 64) in;
        layout(binding = 0) uniform samplerBuffer view;
        layout(std430, binding = 1) writeonly buffer Out { float values[]; };
        uniform uint uCount;
        void main() {
            uint i = gl_GlobalInvocationID.x;
            if (i < uCount)
                values[i] = texelFetch(view, int(i)).x;
        }
    )");
}

std::vector<float> fetchAll(const BufferTexture& view, std::size_t count) {
    auto program = copyProgram();
    EXPECT_TRUE(program) << program.error().message();
    auto out = Buffer::create(count * sizeof(float), "fetched");
    EXPECT_TRUE(out);
    if (!program || !out)
        return {};
    view.bindTexture(0);
    out->bindStorage(1);
    program->use();
    program->set("uCount", std::uint32_t(count));
    program->dispatch(std::uint32_t((count + 63) / 64));
    return out->download<float>();
}

TEST_F(BufferTextureTest, FetchesEveryFloatOfTheBufferBitForBit) {
    std::vector<float> values(1000);
    for (std::size_t i = 0; i < values.size(); ++i)
        values[i] = (float(i) - 500.0f) * 0.37f;
    values[1] = -0.0f;
    values[2] = std::numeric_limits<float>::denorm_min();
    values[3] = std::numeric_limits<float>::max();
    values[4] = -std::numeric_limits<float>::infinity();
    auto buffer = Buffer::createFrom(values, "values");
    ASSERT_TRUE(buffer);
    auto view = BufferTexture::createR32F(*buffer, "values as texels");
    ASSERT_TRUE(view) << view.error().message();
    const std::vector<float> fetched = fetchAll(*view, values.size());
    ASSERT_EQ(fetched.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i != 2) { // a denormal may be flushed to zero by the texture path
            EXPECT_EQ(std::memcmp(&fetched[i], &values[i], sizeof(float)), 0) << i;
        }
    }
}

// The solver's views: positions as RGBA32F (texel i is the buffer's vec4 i) and neighbour
// masks as R32UI (texel i its uint i, every bit kept).
TEST_F(BufferTextureTest, FetchesFourFloatTexelsAndUintTexelsBitForBit) {
    std::vector<float> values(4 * 100);
    for (std::size_t i = 0; i < values.size(); ++i)
        values[i] = (float(i) - 200.0f) * 0.013f;
    values[5] = -0.0f;
    auto floats = Buffer::createFrom(values, "vec4s");
    ASSERT_TRUE(floats);
    std::vector<std::uint32_t> words(300);
    for (std::size_t i = 0; i < words.size(); ++i)
        words[i] = std::uint32_t(i * 2654435761u) | (i % 2 == 0 ? 0x80000001u : 0u);
    auto uints = Buffer::createFrom(words, "words");
    ASSERT_TRUE(uints);
    auto vec4View = BufferTexture::create(*floats, TexelFormat::RGBA32F, "vec4 texels");
    ASSERT_TRUE(vec4View) << vec4View.error().message();
    auto uintView = BufferTexture::create(*uints, TexelFormat::R32UI, "uint texels");
    ASSERT_TRUE(uintView) << uintView.error().message();
    auto program = Program::compute("fetch4.comp", R"(
        layout(local_size_x = 64) in;
        layout(binding = 0) uniform samplerBuffer quads;
        layout(binding = 1) uniform usamplerBuffer words;
        layout(std430, binding = 1) writeonly buffer Quads { vec4 quadsOut[]; };
        layout(std430, binding = 2) writeonly buffer Words { uint wordsOut[]; };
        void main() {
            uint i = gl_GlobalInvocationID.x;
            if (i < 100u)
                quadsOut[i] = texelFetch(quads, int(i));
            if (i < 300u)
                wordsOut[i] = texelFetch(words, int(i)).x;
        }
    )");
    ASSERT_TRUE(program) << program.error().message();
    auto quadsOut = Buffer::create(values.size() * sizeof(float), "quads out");
    auto wordsOut = Buffer::create(words.size() * sizeof(std::uint32_t), "words out");
    ASSERT_TRUE(quadsOut && wordsOut);
    vec4View->bindTexture(0);
    uintView->bindTexture(1);
    quadsOut->bindStorage(1);
    wordsOut->bindStorage(2);
    program->use();
    program->dispatch(5);
    const std::vector<float> fetched = quadsOut->download<float>();
    ASSERT_EQ(fetched.size(), values.size());
    EXPECT_EQ(std::memcmp(fetched.data(), values.data(), values.size() * sizeof(float)), 0);
    EXPECT_EQ(wordsOut->download<std::uint32_t>(), words);
    EXPECT_EQ(texelBytes(TexelFormat::RGBA32UI), 16u);
    EXPECT_EQ(texelBytes(TexelFormat::R32F), 4u);
}

TEST_F(BufferTextureTest, SeesAShadersWritesAfterTheFetchBarrier) {
    std::vector<float> values(256, 1.0f);
    auto buffer = Buffer::createFrom(values, "values");
    ASSERT_TRUE(buffer);
    auto view = BufferTexture::createR32F(*buffer);
    ASSERT_TRUE(view);
    EXPECT_EQ(fetchAll(*view, values.size()), values); // cached, if the GL caches texels
    auto write = Program::compute("write.comp", R"(
        layout(local_size_x = 64) in;
        layout(std430, binding = 2) buffer Values { float v[]; };
        void main() { v[gl_GlobalInvocationID.x] = float(gl_GlobalInvocationID.x) + 0.5; }
    )");
    ASSERT_TRUE(write) << write.error().message();
    buffer->bindStorage(2);
    write->dispatch(4);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    const std::vector<float> fetched = fetchAll(*view, values.size());
    ASSERT_EQ(fetched.size(), values.size());
    for (std::size_t i = 0; i < fetched.size(); ++i)
        EXPECT_EQ(fetched[i], float(i) + 0.5f) << i;
}

TEST_F(BufferTextureTest, RefusesEmptyAndPartialBuffersAndKnowsItsLimit) {
    const Buffer empty;
    auto none = BufferTexture::createR32F(empty);
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().code, ErrorCode::InvalidArgument);
    auto six = Buffer::create(6, "six bytes");
    ASSERT_TRUE(six);
    auto partial = BufferTexture::createR32F(*six);
    ASSERT_FALSE(partial);
    EXPECT_EQ(partial.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(partial.error().message().find("whole number of 4-byte texels"), std::string::npos);
    // 20 bytes are five floats but not a whole number of four-float texels.
    auto twenty = Buffer::create(20, "twenty bytes");
    ASSERT_TRUE(twenty);
    auto quads = BufferTexture::create(*twenty, TexelFormat::RGBA32F, "quads");
    ASSERT_FALSE(quads);
    EXPECT_EQ(quads.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(quads.error().message().find("'quads'"), std::string::npos);
    EXPECT_NE(quads.error().message().find("16-byte texels"), std::string::npos);
    EXPECT_TRUE(BufferTexture::create(*twenty, TexelFormat::R32UI));
    // GL 4.5 guarantees 65536 texels; say what this GL allows (the solver's fallback to storage
    // reads depends on it: Simulation::Impl::compilePasses).
    EXPECT_GE(BufferTexture::maxTexels(), 65536u);
    std::cout << "GL_MAX_TEXTURE_BUFFER_SIZE: " << BufferTexture::maxTexels() << " texels\n";
}

} // namespace
} // namespace sluice::gpu
