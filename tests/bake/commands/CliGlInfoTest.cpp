// `sluice-bake gl-info` and `bake --backend gpu` on whatever OpenGL 4.5 this machine has (Mesa's
// llvmpipe without a GPU).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "TestMeshes.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;

/// Runs `sluice-bake <args>` (args already shell-safe) and returns its exit code; stdout and
/// stderr go to the given files.
int runBake(const std::string& args, const fs::path& out, const fs::path& err) {
    const std::string command = std::string("'") + SLUICE_BAKE_EXE + "' " + args + " >'" +
                                out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(CliGlInfo, PrintsTheRendererAndComputeLimits) {
    const fs::path dir = testmesh::tempDir("cli-gl-info");
    const fs::path out = dir / "out.txt", err = dir / "err.txt";
    const int code = runBake("gl-info --json", out, err);
    ASSERT_EQ(code, kExitOk) << "this machine should have GL 4.5 (llvmpipe at least)\n"
                             << readText(err);
    const nlohmann::json info = nlohmann::json::parse(readText(out));
    EXPECT_FALSE(info["renderer"].get<std::string>().empty());
    EXPECT_FALSE(info["vendor"].get<std::string>().empty());
    EXPECT_GE(info["glMajor"].get<int>() * 10 + info["glMinor"].get<int>(), 45);
    EXPECT_TRUE(info["platform"] == "device" || info["platform"] == "surfaceless")
        << info["platform"];
    // GL 4.5 guarantees at least 1024 invocations per work group and 65535 groups per axis.
    EXPECT_GE(info["maxWorkGroupInvocations"].get<int>(), 1024);
    EXPECT_GE(info["maxWorkGroupCount"][0].get<long>(), 65535);

    const int textCode = runBake("gl-info --self-test", out, err);
    EXPECT_EQ(textCode, kExitOk) << readText(err);
    EXPECT_NE(readText(out).find(info["renderer"].get<std::string>()), std::string::npos)
        << readText(out);
    EXPECT_NE(readText(out).find("self-test: passed"), std::string::npos) << readText(out);
}

TEST(CliGlInfo, AnUnknownPlatformExitsThree) {
    const fs::path dir = testmesh::tempDir("cli-gl-info-none");
    const fs::path out = dir / "out.txt", err = dir / "err.txt";
    EXPECT_EQ(runBake("gl-info --platform nowhere", out, err), kExitNoGlContext);
    EXPECT_NE(readText(err).find("NoGlContext"), std::string::npos) << readText(err);
}

TEST(CliGpuBake, BakesOnTheGpuAndValidatesAgainstTheReference) {
    const fs::path dir = testmesh::tempDir("cli-gpu-bake");
    const fs::path mesh =
        testmesh::writeTempObj(testmesh::icoSphereSoup({0, 0, 0}, 1.0, 3), "cli-gpu-bake", "s.obj");
    ASSERT_FALSE(mesh.empty());
    const fs::path asset = dir / "s.slc", out = dir / "out.txt", err = dir / "err.txt";
    ASSERT_EQ(runBake("bake '" + mesh.string() + "' -o '" + asset.string() +
                          "' --backend gpu --resolution 16 --profile --json",
                      out, err),
              kExitOk)
        << readText(err);
    const nlohmann::json bake = nlohmann::json::parse(readText(out));
    EXPECT_EQ(bake["asset"]["bake"]["backend"], "gpu");
    EXPECT_EQ(bake["asset"]["bake"]["signUsed"], "parity");
    EXPECT_GT(bake["gpu"]["bvhNodes"].get<int>(), 1);
    EXPECT_GE(bake["gpu"]["distanceSeconds"].get<double>(), 0.0);

    // The default backend (auto) bakes on the GPU where a context opens, as here; the CGAL
    // backend's asset agrees with the GPU one to float precision.
    const fs::path byDefault = dir / "default.slc";
    ASSERT_EQ(runBake("bake '" + mesh.string() + "' -o '" + byDefault.string() +
                          "' --resolution 16 --quiet",
                      out, err),
              kExitOk)
        << readText(err);
    Result<format::ColliderAsset> automatic = format::readAsset(byDefault);
    ASSERT_TRUE(automatic.ok()) << automatic.error().message();
    EXPECT_EQ(automatic->meta.bake.backend, "gpu");
    const fs::path onCpu = dir / "cpu.slc";
    ASSERT_EQ(runBake("bake '" + mesh.string() + "' -o '" + onCpu.string() +
                          "' --resolution 16 --backend cgal --quiet",
                      out, err),
              kExitOk)
        << readText(err);
    Result<format::ColliderAsset> cpu = format::readAsset(onCpu);
    Result<format::ColliderAsset> gpu = format::readAsset(asset);
    ASSERT_TRUE(cpu.ok()) << cpu.error().message();
    ASSERT_TRUE(gpu.ok()) << gpu.error().message();
    EXPECT_EQ(cpu->meta.bake.backend, "cgal");
    ASSERT_EQ(cpu->distances.size(), gpu->distances.size());
    double worst = 0.0; // [voxels]
    for (std::size_t n = 0; n < cpu->distances.size(); ++n)
        worst = std::max(worst, std::abs(double(cpu->distances[n]) - gpu->distances[n]) /
                                    cpu->meta.voxelSize);
    EXPECT_LT(worst, 1e-3) << "GPU and CGAL assets differ by " << worst << " voxels";

    ASSERT_EQ(runBake("validate '" + asset.string() + "' '" + mesh.string() + "' --json", out, err),
              kExitOk)
        << readText(err) << readText(out);
    const nlohmann::json report = nlohmann::json::parse(readText(out));
    EXPECT_LT(report["figures"]["maxError"].get<double>(), 1e-3); // [voxels]
    EXPECT_EQ(report["figures"]["signMismatches"], 0);
}

TEST(CliGpuBake, WithoutAGlContextExitsThreeAndWritesNothing) {
    const fs::path dir = testmesh::tempDir("cli-gpu-none");
    const fs::path mesh =
        testmesh::writeTempObj(testmesh::icoSphereSoup({0, 0, 0}, 1.0, 1), "cli-gpu-none", "s.obj");
    const fs::path out = dir / "out.txt", err = dir / "err.txt";
    const std::string command = std::string("SLUICE_EGL_PLATFORM=nowhere '") + SLUICE_BAKE_EXE +
                                "' bake '" + mesh.string() + "' -o '" + (dir / "x.slc").string() +
                                "' --backend gpu --resolution 8 >'" + out.string() + "' 2>'" +
                                err.string() + "'";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), kExitNoGlContext) << readText(err);
    EXPECT_NE(readText(err).find("NoGlContext"), std::string::npos) << readText(err);
    EXPECT_FALSE(fs::exists(dir / "x.slc"));
}

TEST(CliGpuBake, TheDefaultBakesOnTheCpuWithoutAGlContextAndSaysSo) {
    const fs::path dir = testmesh::tempDir("cli-auto-none");
    const fs::path mesh = testmesh::writeTempObj(testmesh::icoSphereSoup({0, 0, 0}, 1.0, 1),
                                                 "cli-auto-none", "s.obj");
    const fs::path out = dir / "out.txt", err = dir / "err.txt";
    const fs::path asset = dir / "x.slc";
    const std::string command = std::string("SLUICE_EGL_PLATFORM=nowhere '") + SLUICE_BAKE_EXE +
                                "' bake '" + mesh.string() + "' -o '" + asset.string() +
                                "' --resolution 8 --quiet >'" + out.string() + "' 2>'" +
                                err.string() + "'";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_EQ(WEXITSTATUS(status), kExitOk) << readText(err);
    EXPECT_NE(readText(err).find("baking on the CPU with the CGAL backend"), std::string::npos)
        << readText(err);
    Result<format::ColliderAsset> baked = format::readAsset(asset);
    ASSERT_TRUE(baked.ok()) << baked.error().message();
    EXPECT_EQ(baked->meta.bake.backend, "cgal");
}

} // namespace
} // namespace sluice::bake
