// sluice-play --surface-mesh end to end: the meshes it writes, the field's options, what it
// reports and the options it refuses.
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "ProgramRun.h"
#include "render/RenderTestSupport.h"

namespace sluice::rt {
namespace {

namespace fs = std::filesystem;
using testrun::shown;
using testrun::tempDir;

// Runs that render need the GL driver preloaded under ASan: test::runPlay does that.
using test::kAssets;
using test::runPlay;

/// A binary little-endian PLY mesh as --surface-mesh writes it: its vertices and triangles,
/// each face checked to be a triangle of existing vertices, the size checked against the header.
struct PlyMesh {
    std::vector<glm::vec3> vertices;
    std::vector<glm::uvec3> triangles;
};

PlyMesh readPlyMesh(const fs::path& path) {
    const std::string bytes = testrun::readText(path);
    PlyMesh mesh;
    const std::size_t end = bytes.find("end_header\n");
    if (end == std::string::npos) {
        ADD_FAILURE() << path << ": no end_header";
        return mesh;
    }
    std::istringstream header(bytes.substr(0, end));
    std::size_t vertices = 0, faces = 0;
    for (std::string line; std::getline(header, line);) {
        std::istringstream words(line);
        std::string a, b;
        words >> a >> b;
        if (a == "element" && b == "vertex")
            words >> vertices;
        if (a == "element" && b == "face")
            words >> faces;
    }
    const std::size_t body = end + 11;
    EXPECT_EQ(bytes.size(), body + vertices * 24 + faces * 13) << path;
    if (bytes.size() != body + vertices * 24 + faces * 13)
        return mesh;
    for (std::size_t v = 0; v < vertices; ++v) {
        float xyz[3];
        std::memcpy(xyz, bytes.data() + body + v * 24, sizeof xyz);
        mesh.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
    }
    for (std::size_t f = 0; f < faces; ++f) {
        const char* at = bytes.data() + body + vertices * 24 + f * 13;
        EXPECT_EQ(at[0], 3);
        std::uint32_t index[3];
        std::memcpy(index, at + 1, sizeof index);
        for (std::uint32_t i : index)
            EXPECT_LT(i, vertices);
        mesh.triangles.emplace_back(index[0], index[1], index[2]);
    }
    return mesh;
}

double enclosedVolume(const PlyMesh& mesh) {
    double volume = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        volume +=
            glm::dot(glm::dvec3(mesh.vertices[t.x]),
                     glm::cross(glm::dvec3(mesh.vertices[t.y]), glm::dvec3(mesh.vertices[t.z]))) /
            6.0;
    return volume;
}

// --surface-mesh writes one mesh per requested step (step 0 and every --surface-every) and
// nothing else; each encloses the water's volume.
TEST(SluicePlaySurface, WritesOneClosedMeshPerRequestedStep) {
    const fs::path dir = tempDir("surface");
    const fs::path meshes = dir / "meshes";
    const auto result = runPlay(dir, {(kAssets / "martin-moyce.json").string(), "--headless",
                                      "--steps", "4", "--deterministic", "--quiet",
                                      "--surface-mesh", meshes.string(), "--surface-every", "2"});
    ASSERT_EQ(result.code, 0) << shown(result);
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(meshes))
        names.insert(entry.path().filename().string());
    EXPECT_EQ(names, (std::set<std::string>{"surface_000000.ply", "surface_000002.ply",
                                            "surface_000004.ply"}));
    // 2000 particles at 2 cm: 16 L of water, in a 0.2 x 0.4 x 0.2 m column at step 0; the
    // column's edges are rounded over a kernel radius (4 cm), which costs a few per cent.
    for (const char* name : {"surface_000000.ply", "surface_000004.ply"}) {
        const PlyMesh mesh = readPlyMesh(meshes / name);
        EXPECT_GT(mesh.triangles.size(), 1000u) << name;
        EXPECT_NEAR(enclosedVolume(mesh) / 0.016, 1.0, 0.05) << name;
    }
}

// The isotropic field is density-normalised unless --no-surface-normalised says otherwise; of
// the two flags, the last one given wins.
TEST(SluicePlaySurface, NormalisesTheFieldUnlessToldAndTheLastFlagWins) {
    const fs::path dir = tempDir("surface-normalised");
    const auto meshOf = [&](const char* tag, std::vector<std::string> flags) {
        std::vector<std::string> args = {(kAssets / "martin-moyce.json").string(),
                                         "--headless",
                                         "--steps",
                                         "1",
                                         "--deterministic",
                                         "--quiet",
                                         "--surface-mesh",
                                         (dir / tag).string()};
        args.insert(args.end(), flags.begin(), flags.end());
        const auto run = runPlay(dir, args);
        EXPECT_EQ(run.code, 0) << tag << ": " << shown(run);
        return testrun::readText(dir / tag / "surface_000001.ply");
    };
    const std::string normalised = meshOf("default", {});
    const std::string plain = meshOf("plain", {"--no-surface-normalised"});
    EXPECT_NE(normalised, plain);
    EXPECT_EQ(meshOf("asked", {"--surface-normalised"}), normalised);
    EXPECT_EQ(meshOf("last-no", {"--surface-normalised", "--no-surface-normalised"}), plain);
    EXPECT_EQ(meshOf("last-yes", {"--no-surface-normalised", "--surface-normalised"}), normalised);
}

// Without --quiet the summary says what a mesh cost, stage by stage, and so does the statistics
// file (timings are left out of a --deterministic one).
TEST(SluicePlaySurface, ReportsWhatAMeshCostStageByStage) {
    const fs::path dir = tempDir("surface-timed");
    const fs::path stats = dir / "stats.json";
    const auto timed =
        runPlay(dir, {(kAssets / "martin-moyce.json").string(), "--headless", "--steps", "2",
                      "--surface-mesh", (dir / "timed").string(), "--stats-json", stats.string()});
    ASSERT_EQ(timed.code, 0) << shown(timed);
    EXPECT_NE(timed.out.find("surface meshes: 3, median "), std::string::npos) << timed.out;
    EXPECT_NE(timed.out.find("surface stages, median ms:  bounds "), std::string::npos)
        << timed.out;
    const auto doc = nlohmann::json::parse(testrun::readText(stats));
    const auto& surface = doc["timing"]["surfaceMeshMs"];
    EXPECT_EQ(surface["count"].get<int>(), 3);
    double stages = 0.0;
    for (const auto& [stage, ms] : surface["stagesMedian"].items()) {
        EXPECT_GE(ms.get<double>(), 0.0) << stage;
        stages += ms.get<double>();
    }
    EXPECT_EQ(surface["stagesMedian"].size(), 6u);
    // The stages lie inside the whole call (medians of each, so allow for their spread).
    EXPECT_GT(surface["median"].get<double>(), 0.0);
    EXPECT_LE(stages, 2.0 * surface["median"].get<double>());
}

// A cell wider than the smoothing radius, or an unknown kernel: exit 2 naming the option, before
// anything is created.
TEST(SluicePlaySurface, RefusesBadSurfaceOptionsWritingNothing) {
    const fs::path dir = tempDir("surface-bad");
    const fs::path bad = dir / "bad";
    const auto refused =
        runPlay(dir, {(kAssets / "martin-moyce.json").string(), "--headless", "--steps", "1",
                      "--surface-mesh", bad.string(), "--surface-cell", "0.5"});
    EXPECT_EQ(refused.code, 2) << shown(refused);
    EXPECT_NE(refused.err.find("--surface-cell 0.5"), std::string::npos) << refused.err;
    EXPECT_NE(refused.err.find("larger than the smoothing radius"), std::string::npos)
        << refused.err;
    EXPECT_FALSE(fs::exists(bad));
    // A kernel that is not gaussian or poly6: exit 2 naming the option, nothing written.
    const auto unknown =
        runPlay(dir, {(kAssets / "martin-moyce.json").string(), "--headless", "--steps", "1",
                      "--surface-mesh", bad.string(), "--surface-kernel", "cubic"});
    EXPECT_EQ(unknown.code, 2) << shown(unknown);
    EXPECT_NE(unknown.err.find("--surface-kernel cubic"), std::string::npos) << unknown.err;
    EXPECT_FALSE(fs::exists(bad));
}

} // namespace
} // namespace sluice::rt
