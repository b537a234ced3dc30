// Hostile meshes through `sluice-bake bake`: each exits 2 with a message naming the file, writes
// no output, leaves a previous output byte for byte as it was and no temporary file behind.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ProgramRun.h"
#include "ReliabilityTest.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::reliability {
namespace {

using testrun::runProgram;
using testrun::RunResult;
using testrun::shown;

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;

RunResult bake(const fs::path& dir, const std::vector<std::string>& args) {
    std::vector<std::string> all = {"bake"};
    all.insert(all.end(), args.begin(), args.end());
    return runProgram(SLUICE_BAKE_EXE, dir, all);
}

/// Bakes `mesh` twice into `dir`/out/collider.slc, first with no output there and then over a
/// previous one, and checks the rejection contract both times. `named` must appear in stderr.
void expectRejected(const fs::path& dir, const fs::path& mesh, const std::string& named,
                    const std::vector<std::string>& extra = {}) {
    SCOPED_TRACE(mesh.string());
    const fs::path outDir = dir / "out";
    fs::remove_all(outDir);
    fs::create_directories(outDir);
    const fs::path output = outDir / "collider.slc";
    std::vector<std::string> args = {mesh.string(), "-o", output.string(), "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());

    RunResult run = bake(dir, args);
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_NE(run.err.find(named), std::string::npos) << "the message names " << named << "\n"
                                                      << run.err;
    EXPECT_TRUE(listDir(outDir).empty()) << "nothing is written";

    const std::string previous = "previous asset bytes \x89SLC\r\n\x1a\n";
    writeText(output, previous);
    run = bake(dir, args);
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_EQ(readBytes(output), previous) << "the previous output is untouched";
    EXPECT_EQ(listDir(outDir), std::set<std::string>{"collider.slc"}) << "no temporary file";
}

TEST(HostileMesh, EveryFileInAssimpsInvalidFolderExitsTwoAndWritesNothing) {
    const fs::path invalid = fs::path(SLUICE_ASSIMP_MODELS) / "invalid";
    if (!fs::is_directory(invalid))
        GTEST_SKIP() << invalid << " is missing (Debian package assimp-testmodels)";
    const fs::path dir = freshDir("hostile-invalid");
    int rejected = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(invalid)) {
        const std::string name = entry.path().filename().string();
        if (name == "readme.txt")
            continue; // describes the folder
        if (name == "malformed2.obj") {
            // Its only flaw is a material that does not exist, which geometry import does not
            // use: five faces of a cube, a valid open mesh (tests/bake/import/MeshImportTest.cpp).
            const fs::path output = dir / "malformed2.slc";
            const RunResult run =
                bake(dir, {entry.path().string(), "-o", output.string(), "--resolution", "8"});
            EXPECT_EQ(run.code, kExitOk) << shown(run);
            EXPECT_TRUE(format::readAsset(output).ok());
            continue;
        }
        expectRejected(dir, entry.path(), name);
        ++rejected;
    }
    EXPECT_EQ(rejected, 13); // 10 empty files, emptyIrrMesh.xml, OutOfMemory.off, malformed.obj
}

TEST(HostileMesh, EmptyFilesOfEveryExtensionExitTwo) {
    const fs::path dir = freshDir("hostile-empty");
    for (const char* ext : {"obj", "off", "ply", "stl", "fbx", "gltf", "dae", "3ds"}) {
        const fs::path mesh = dir / (std::string("empty.") + ext);
        writeText(mesh, "");
        expectRejected(dir, mesh, mesh.filename().string());
    }
}

TEST(HostileMesh, NaNAndInfiniteCoordinatesExitTwo) {
    const fs::path dir = freshDir("hostile-nonfinite");
    const std::vector<std::pair<std::string, std::string>> meshes = {
        {"nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n"},
        {"inf.obj", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"},
        {"minus-inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 -inf\nf 1 2 3\n"},
        {"overflow.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n"}, // beyond float: inf
        {"nan.off", "OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n"},
    };
    for (const auto& [name, text] : meshes) {
        const fs::path mesh = dir / name;
        writeText(mesh, text);
        expectRejected(dir, mesh, name);
    }
    // Finite in the file, infinite once scaled.
    const fs::path big = dir / "big.obj";
    writeText(big, "v 0 0 0\nv 3e38 0 0\nv 0 1 0\nf 1 2 3\n");
    expectRejected(dir, big, "big.obj", {"--scale", "1e300"});
}

TEST(HostileMesh, OnlyDegenerateTrianglesExitTwo) {
    const fs::path dir = freshDir("hostile-degenerate");
    const std::vector<std::pair<std::string, std::string>> meshes = {
        // Collinear corners: zero area, a box of zero extent on two axes.
        {"collinear.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 3 2 1\n"},
        // Repeated corners.
        {"repeated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\nf 2 3 3\nf 1 3 1\n"},
        // Every corner at one point.
        {"point.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n"},
        // Zero-area triangles spanning a real box.
        {"flat-box.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nv 0 1 0\nv 0 2 0\nf 1 2 3\nf 1 4 5\n"},
    };
    for (const auto& [name, text] : meshes) {
        const fs::path mesh = dir / name;
        writeText(mesh, text);
        expectRejected(dir, mesh, name);
    }
}

TEST(HostileMesh, GridsTooLargeForTheLimitExitTwoBeforeBaking) {
    const fs::path dir = freshDir("hostile-grid");
    const fs::path mesh = dir / "tetra.obj";
    writeText(mesh, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    // 1e-6 voxels: 1e6 points per axis, far beyond 2^28 points in all.
    expectRejected(dir, mesh, "tetra.obj", {"--voxel-size", "1e-6"});
    // 700^3 points: each axis fits, the product does not (2^28 = 268 M points).
    expectRejected(dir, mesh, "tetra.obj", {"--voxel-size", "0.001436"});
    // A huge padding instead.
    expectRejected(dir, mesh, "tetra.obj", {"--padding", "1e9"});
}

TEST(HostileMesh, HeadersDeclaringBillionsOfElementsExitTwoAtOnce) {
    const fs::path dir = freshDir("hostile-headers");
    const std::vector<std::pair<std::string, std::string>> meshes = {
        {"huge.off", "OFF\n4000000000 4000000000 0\n0 0 0\n"},
        {"huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                     "property float x\nproperty float y\nproperty float z\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n"},
        {"huge-ascii.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 900000000\n"
                           "property list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
    };
    for (const auto& [name, text] : meshes) {
        const fs::path mesh = dir / name;
        writeText(mesh, text);
        const auto start = std::chrono::steady_clock::now();
        expectRejected(dir, mesh, name);
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                  60.0);
    }
    // A binary STL whose triangle count claims more than the file holds.
    std::string stl(80, ' ');
    const unsigned count = 100'000'000;
    stl.append(reinterpret_cast<const char*>(&count), 4);
    stl.append(50, '\0');
    writeText(dir / "huge.stl", stl);
    expectRejected(dir, dir / "huge.stl", "huge.stl");
}

TEST(HostileMesh, APlyFileCutShortInItsHeaderExitsTwoAtOnce) {
    // assimp loops forever on a PLY header without end_header (tests/fuzz found it); the import
    // would have ended only at the isolation time limit (10 minutes).
    const fs::path dir = freshDir("hostile-ply-cut");
    const fs::path mesh = dir / "cut.ply";
    writeText(mesh, "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty flo");
    const auto start = std::chrono::steady_clock::now();
    expectRejected(dir, mesh, "cut.ply");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              60.0);
}

TEST(HostileMesh, CrashesInsideAssimpExitTwo) {
    // Files on which assimp 5.2.5 itself crashes, found by tests/fuzz (run.sh keeps them apart).
    // The OFF ones are now refused before assimp reads them (checkOffBody); any other would be
    // contained by the child process sluice-bake imports in. Either way: exit 2, the file named.
    const fs::path crashes = fs::path(SLUICE_SOURCE_DIR) / "tests/reliability/assimp-crashes";
    const fs::path dir = freshDir("hostile-assimp-crashes");
    int baked = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(crashes)) {
        expectRejected(dir, entry.path(), entry.path().filename().string());
        ++baked;
    }
    EXPECT_GT(baked, 0);
}

TEST(HostileMesh, MissingFoldersAndNonFilesExitTwo) {
    const fs::path dir = freshDir("hostile-paths");
    expectRejected(dir, dir / "no-such-mesh.obj", "no-such-mesh.obj");
    fs::create_directories(dir / "folder.obj");
    expectRejected(dir, dir / "folder.obj", "folder.obj");
}

} // namespace
} // namespace sluice::reliability
