// GpuTimer: elapsed times that grow with the work, nesting, and a ring that loses nothing.
#include <cstdint>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include <gtest/gtest.h>

#include "GpuTest.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"

namespace sluice::gpu {
namespace {

class GpuTimerTest : public test::GpuTest {
protected:
    void SetUp() override {
        test::GpuTest::SetUp();
        if (HasFatalFailure())
            return;
        auto program = Program::compute("busy.comp", R"(
            layout(local_size_x = 64) in;
            layout(std430, binding = 0) buffer Data { float data[]; };
            uniform uint iterations;
            void main() {
                float v = data[gl_GlobalInvocationID.x];
                for (uint i = 0u; i < iterations; ++i)
                    v = sin(v) * 0.5 + cos(v * 1.0001) * 0.5;
                data[gl_GlobalInvocationID.x] = v;
            }
        )");
        ASSERT_TRUE(program) << program.error().message();
        m_program = std::move(*program);
        auto data = Buffer::create(kItems * sizeof(float), "busy data");
        ASSERT_TRUE(data);
        m_data = std::move(*data);
        m_data.clear();
        m_data.bindStorage(0);
    }

    void TearDown() override {
        m_program = Program();
        m_data = Buffer();
        test::GpuTest::TearDown();
    }

    /// Roughly `iterations` * 16k transcendental pairs of GPU work.
    void work(std::uint32_t iterations) {
        m_program.set("iterations", iterations);
        m_program.dispatch(groupCount(kItems, 64));
    }

    static constexpr std::uint32_t kItems = 16384;
    Program m_program;
    Buffer m_data;
};

TEST_F(GpuTimerTest, MeasuresAPositiveTimeForANonTrivialDispatch) {
    GpuTimer timer;
    {
        GpuTimer::Scope scope(timer);
        work(200);
    }
    const std::uint64_t ns = timer.elapsedNs();
    std::printf("busy dispatch: %.3f ms on the GPU\n", static_cast<double>(ns) * 1e-6);
    EXPECT_GT(ns, 0u);
    EXPECT_LT(ns, std::uint64_t{30'000'000'000}); // [ns]: not garbage
    EXPECT_EQ(timer.completed(), 1u);
    EXPECT_EQ(timer.pending(), 0u);
}

TEST_F(GpuTimerTest, MoreWorkTakesLonger) {
    work(1); // the first dispatch may include compiling the shader (llvmpipe's JIT)
    glFinish();
    GpuTimer timer;
    timer.begin();
    work(1);
    timer.end();
    const std::uint64_t little = timer.elapsedNs();
    timer.begin();
    work(400);
    timer.end();
    const std::uint64_t much = timer.elapsedNs();
    EXPECT_GT(much, little) << "1 iteration: " << little << " ns, 400: " << much << " ns";
}

TEST_F(GpuTimerTest, NestedTimersEachMeasureTheirOwnSpan) {
    work(1);
    glFinish();
    GpuTimer frame;
    GpuTimer pass;
    frame.begin();
    work(1);
    pass.begin();
    work(200);
    pass.end();
    work(200);
    frame.end();
    const std::uint64_t passNs = pass.elapsedNs();
    const std::uint64_t frameNs = frame.elapsedNs();
    EXPECT_GT(passNs, 0u);
    EXPECT_GT(frameNs, passNs) << "frame " << frameNs << " ns, pass " << passNs << " ns";
}

TEST_F(GpuTimerTest, PollCollectsEveryMeasurementOfAFullRing) {
    GpuTimer timer(3);
    EXPECT_FALSE(timer.poll().has_value());
    // Five passes through a ring of three: begin() waits for the oldest only when it is full.
    for (int pass = 0; pass < 5; ++pass) {
        timer.begin();
        work(10);
        timer.end();
        EXPECT_LE(timer.pending(), 3u);
    }
    glFinish();
    const std::optional<std::uint64_t> newest = timer.poll();
    ASSERT_TRUE(newest.has_value());
    EXPECT_GT(*newest, 0u);
    EXPECT_EQ(timer.pending(), 0u);
    EXPECT_EQ(timer.completed(), 5u);
    EXPECT_GE(timer.totalNs(), *newest);
    EXPECT_FALSE(timer.poll().has_value()); // nothing new since
}

TEST_F(GpuTimerTest, MisuseIsABrokenContract) {
    GpuTimer timer;
    EXPECT_THROW(timer.end(), std::runtime_error);
    EXPECT_THROW((void)timer.elapsedNs(), std::runtime_error);
    timer.begin();
    EXPECT_THROW(timer.begin(), std::runtime_error);
    timer.end();
}

} // namespace
} // namespace sluice::gpu
