// The viewer window under Xvfb (skipped where xvfb-run is missing): a fixed number of frames and
// a clean exit, its screenshot against the headless render of the same step, its --frames
// capture, screenshots with the panel, and the message and exit code when there is no display
// at all.
#include <algorithm>
#include <cstdlib>

#include <gtest/gtest.h>

#include "CaptureFrames.h"
#include "RenderTestSupport.h"
#include "ViewerPanel.h"

namespace sluice::rt {
namespace {

using namespace test;
using testrun::quote;

bool haveXvfb() {
    return std::system("command -v xvfb-run >/dev/null 2>&1") == 0;
}

// Runs `args` of sluice-play in `dir` (the working folder) under a new Xvfb server whose screen
// is `screen` (WIDTHxHEIGHT) pixels.
testrun::RunResult playInWindow(const fs::path& dir, const std::vector<std::string>& args,
                                const std::string& screen = "640x480") {
    std::string command =
        "cd " + quote(dir.string()) + " && xvfb-run -a -s '-screen 0 " + screen + "x24' ";
    if (!glDriverPreload().empty())
        command += "env " + quote("LD_PRELOAD=" + glDriverPreload()) + " ";
    command += quote(SLUICE_PLAY_EXE);
    for (const std::string& arg : args)
        command += " " + quote(arg);
    command += " >stdout.txt 2>stderr.txt";
    const int status = std::system(command.c_str());
    testrun::RunResult run;
    run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = testrun::readText(dir / "stdout.txt");
    run.err = testrun::readText(dir / "stderr.txt");
    return run;
}

TEST(ViewerWindow, RunsForMaxFramesUnderXvfbAndExitsCleanly) {
    if (!haveXvfb())
        GTEST_SKIP() << "xvfb-run is not installed (Debian: apt-get install xvfb)";
    const fs::path dir = tempDir("window");
    const auto run = playInWindow(dir, {(kAssets / "wave-sphere.json").string(), "--max-frames",
                                        "6", "--size", "320x240", "--no-vsync", "--frames",
                                        (dir / "f").string(), "--every", "2"});
    ASSERT_EQ(run.code, 0) << testrun::shown(run);
    EXPECT_NE(run.out.find("6 frames"), std::string::npos) << run.out;
    // Frames 0..5 show steps 0..5: the captures are steps 0, 2 and 4, at the window's size.
    for (std::uint64_t step : {0u, 2u, 4u}) {
        const Image image = readPng(dir / "f" / pngFrameName(step));
        EXPECT_EQ(image.width, 320u) << step;
        EXPECT_EQ(image.height, 240u) << step;
    }
    EXPECT_FALSE(fs::exists(dir / "f" / pngFrameName(6)));
}

TEST(ViewerWindow, ScreenshotMatchesTheHeadlessRenderOfTheSameStep) {
    if (!haveXvfb())
        GTEST_SKIP() << "xvfb-run is not installed (Debian: apt-get install xvfb)";
    const fs::path dir = tempDir("screenshot");
    const std::string scene = (kAssets / "wave-sphere.json").string();
    for (const char* surface : {"spheres", "fluid"}) {
        const auto window =
            playInWindow(dir, {scene, "--max-frames", "5", "--size", "320x240", "--no-vsync",
                               "--deterministic", "--surface", surface, "--screenshot-at", "3"});
        ASSERT_EQ(window.code, 0) << testrun::shown(window);
        const fs::path shot = dir / "wave-sphere-000003.png";
        const Image viewer = readPng(shot);
        fs::remove(shot);
        ASSERT_FALSE(viewer.empty()) << "no screenshot\n" << testrun::shown(window);

        const auto headless =
            runPlay(dir, {scene, "--headless", "--steps", "3", "--deterministic", "--surface",
                          surface, "--frames", (dir / "headless").string(), "--every", "3",
                          "--size", "320x240", "--quiet"});
        ASSERT_EQ(headless.code, 0) << testrun::shown(headless);
        const Image reference = readPng(dir / "headless" / pngFrameName(3));
        const ImageDiff diff = compareImages(viewer, reference);
        // The same GL driver behind GLX and EGL: at most rounding differences.
        EXPECT_LE(diff.meanChannel, 0.5) << surface;
        EXPECT_LE(diff.maxChannel, 16) << surface;
    }
}

TEST(ViewerWindow, ScreenshotWithThePanelDiffersFromThePlainOneOnlyInsideThePanel) {
    if (!haveXvfb())
        GTEST_SKIP() << "xvfb-run is not installed (Debian: apt-get install xvfb)";
    const fs::path dir = tempDir("panel-screenshot");
    const std::string scene = (kAssets / "martin-moyce.json").string();
    Image shots[2];
    for (int panel = 0; panel < 2; ++panel) {
        std::vector<std::string> args = {scene,
                                         "--max-frames",
                                         "3",
                                         "--size",
                                         "960x540",
                                         "--no-vsync",
                                         "--deterministic",
                                         "--screenshot-at",
                                         "1",
                                         "--shots",
                                         panel ? "with" : "without"};
        if (panel)
            args.push_back("--screenshot-panel");
        const auto run = playInWindow(dir, args, "1024x768");
        ASSERT_EQ(run.code, 0) << testrun::shown(run);
        shots[panel] = readPng(dir / (panel ? "with" : "without") / "martin-moyce-000001.png");
        ASSERT_EQ(shots[panel].width, 960u) << testrun::shown(run);
        ASSERT_EQ(shots[panel].height, 540u);
    }
    // The differing pixels: the panel, 10 pixels from the top-left corner, at most 30 % of the
    // window's width wide.
    glm::uvec2 lo{960, 540}, hi{0, 0};
    std::size_t differing = 0;
    for (std::uint32_t y = 0; y < 540; ++y)
        for (std::uint32_t x = 0; x < 960; ++x)
            if (pixelDiffers(shots[0], shots[1], x, y)) {
                lo = glm::min(lo, glm::uvec2(x, y));
                hi = glm::max(hi, glm::uvec2(x, y));
                ++differing;
            }
    ASSERT_GT(differing, 20000u) << "the panel is missing from the screenshot";
    EXPECT_GE(lo.x, 10u);
    EXPECT_GE(lo.y, 10u);
    EXPECT_LT(hi.x, 10u + std::uint32_t(kPanelMaxWidthFraction * 960.0f));
    EXPECT_LE(hi.x - lo.x + 1, std::uint32_t(kPanelMaxWidthFraction * 960.0f));
    EXPECT_GT(hi.x - lo.x + 1, 200u); // the labels and sliders fit
}

TEST(ViewerWindow, WithoutADisplayItSaysHowToRunHeadlessAndExitsThree) {
    const fs::path dir = tempDir("no-display");
    const std::string command = "env -u DISPLAY -u WAYLAND_DISPLAY " + quote(SLUICE_PLAY_EXE) +
                                " " + quote((kAssets / "drop.json").string()) + " >" +
                                quote((dir / "out.txt").string()) + " 2>" +
                                quote((dir / "err.txt").string());
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 3);
    const std::string err = testrun::readText(dir / "err.txt");
    EXPECT_NE(err.find("cannot open a window"), std::string::npos) << err;
    EXPECT_NE(err.find("--headless"), std::string::npos) << err;
}

} // namespace
} // namespace sluice::rt
