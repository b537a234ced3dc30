// Particle frames to level sets as a library: the PLY particle reader on hostile and foreign
// files, per-vertex radii, and what the union of spheres does between lattice neighbours.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ProgramRun.h"
#include "TestParticles.h"
#include "interop/ParticlePly.h"
#include "interop/VdbHeaders.h"
#include "sluice/bake/interop/ParticleLevelSet.h"

SLUICE_VDB_WARNINGS_OFF
#include <openvdb/tools/Interpolation.h>
SLUICE_VDB_WARNINGS_ON

namespace fs = std::filesystem;
using namespace sluice;
using namespace sluice::testparticles;

namespace {

fs::path tempDir(const std::string& name) {
    return testrun::tempDir("particle-level-set-" + name);
}

/// The one grid of a .vdb file.
openvdb::FloatGrid::Ptr readOnlyGrid(const fs::path& path) {
    bake::initOpenVdb();
    openvdb::io::File file(path.string());
    file.open();
    openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();
    EXPECT_EQ(grids->size(), 1u);
    return grids->empty() ? nullptr : openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[0]);
}

double sample(const openvdb::FloatGrid& grid, const glm::dvec3& p) {
    return openvdb::tools::BoxSampler::sample(grid.tree(),
                                              grid.worldToIndex(openvdb::Vec3R(p.x, p.y, p.z)));
}

TEST(ParticlePly, ReadsSluicePlaysFramesAndRejectsEveryTruncatedPrefix) {
    const fs::path dir = tempDir("prefixes");
    const std::vector<glm::dvec3> points = {{0.5, -0.25, 2.0}, {1e-3, 7.0, -3.5}, {0, 0, 0}};
    const std::string bytes = sluicePlayPly(points);
    const fs::path whole = dir / "whole.ply";
    writeBytes(whole, bytes);
    Result<bake::detail::ParticleFrame> frame = bake::detail::readParticlePly(whole);
    ASSERT_TRUE(frame) << frame.error().message();
    ASSERT_EQ(frame->positions.size(), points.size());
    for (std::size_t n = 0; n < points.size(); ++n)
        for (int c = 0; c < 3; ++c)
            EXPECT_FLOAT_EQ(float(frame->positions[n][c]), float(points[n][c])) << n;
    EXPECT_TRUE(frame->radii.empty());
    EXPECT_EQ(frame->sourceHash.size(), 16u);

    const fs::path cut = dir / "cut.ply";
    for (std::size_t size = 0; size < bytes.size(); ++size) {
        writeBytes(cut, bytes.substr(0, size));
        Result<bake::detail::ParticleFrame> prefix = bake::detail::readParticlePly(cut);
        ASSERT_FALSE(prefix) << "a prefix of " << size << " bytes was read";
        EXPECT_NE(prefix.error().detail.find("cut.ply"), std::string::npos)
            << prefix.error().detail;
        if (size > bytes.find("end_header\n") + 11) {
            EXPECT_EQ(prefix.error().code, ErrorCode::Truncated) << size;
        }
    }
}

TEST(ParticlePly, ReadsBigEndianAndAsciiFilesWithPerVertexRadii) {
    const fs::path dir = tempDir("encodings");
    // Big-endian: sluice-play's layout with every 4-byte value reversed.
    const std::vector<glm::dvec3> points = {{0.5, -0.25, 2.0}, {1.5, 7.0, -3.5}};
    std::string bytes = sluicePlayPly(points);
    const std::size_t body = bytes.find("end_header\n") + 11;
    for (std::size_t at = body; at < bytes.size(); at += 4)
        std::reverse(bytes.begin() + std::ptrdiff_t(at), bytes.begin() + std::ptrdiff_t(at + 4));
    bytes.replace(bytes.find("binary_little_endian"), 20, "binary_big_endian");
    writeBytes(dir / "big.ply", bytes);
    Result<bake::detail::ParticleFrame> big = bake::detail::readParticlePly(dir / "big.ply");
    ASSERT_TRUE(big) << big.error().message();
    ASSERT_EQ(big->positions.size(), 2u);
    EXPECT_EQ(big->positions[1], glm::dvec3(1.5, 7.0, -3.5));

    writeBytes(dir / "ascii.ply", asciiPlyWithRadius(points, {0.25, 0.125}));
    Result<bake::detail::ParticleFrame> ascii = bake::detail::readParticlePly(dir / "ascii.ply");
    ASSERT_TRUE(ascii) << ascii.error().message();
    EXPECT_EQ(ascii->positions, points);
    EXPECT_EQ(ascii->radii, (std::vector<double>{0.25, 0.125}));

    // A radius that is zero, or a word that is not a number, names the file and the vertex.
    writeBytes(dir / "zero.ply", asciiPlyWithRadius(points, {0.25, 0.0}));
    Result<bake::detail::ParticleFrame> zero = bake::detail::readParticlePly(dir / "zero.ply");
    ASSERT_FALSE(zero);
    EXPECT_EQ(zero.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(zero.error().detail.find("zero.ply': vertex 2"), std::string::npos)
        << zero.error().detail;
    std::string word = asciiPlyWithRadius(points, {0.25, 0.125});
    word.replace(word.rfind("0.125"), 5, "0.1x5");
    writeBytes(dir / "word.ply", word);
    Result<bake::detail::ParticleFrame> bad = bake::detail::readParticlePly(dir / "word.ply");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().detail.find("\"0.1x5\" is not a number"), std::string::npos)
        << bad.error().detail;
}

TEST(ParticleLevelSet, PerVertexRadiiSizeEachSphereAndTheVoxel) {
    const fs::path dir = tempDir("per-vertex");
    // Two particles far apart, radii 0.01 and 0.02.
    const std::vector<glm::dvec3> points = {{0.0, 0.0, 0.0}, {0.3, 0.0, 0.0}};
    writeBytes(dir / "frame.ply", asciiPlyWithRadius(points, {0.01, 0.02}));
    Result<bake::SurfaceReport> report =
        bake::writeParticleSurfaces({dir / "frame.ply"}, dir / "frame.vdb", {});
    ASSERT_TRUE(report) << report.error().message();
    EXPECT_EQ(report->radius, 0.0);
    EXPECT_DOUBLE_EQ(report->voxelSize, 0.005); // half the smallest radius
    ASSERT_EQ(report->frames.size(), 1u);
    EXPECT_EQ(report->frames[0].ignoredParticles, 0u);
    const openvdb::FloatGrid::Ptr grid = readOnlyGrid(dir / "frame.vdb");
    ASSERT_TRUE(grid);
    // 0.015 from each centre: outside the small sphere, inside the large one, by 0.005.
    EXPECT_NEAR(sample(*grid, points[0] + glm::dvec3(0, 0.015, 0)), 0.005, 1e-4);
    EXPECT_NEAR(sample(*grid, points[1] + glm::dvec3(0, 0.015, 0)), -0.005, 1e-4);
}

TEST(ParticleLevelSet, HalfSpacingSpheresLeavePocketsThatLargerOnesClose) {
    // The union of spheres of radius r around lattice points of spacing s is solid only where
    // r >= s * sqrt(3) / 2: at sluice-play's r = s / 2 the centre of each lattice cube stays
    // outside (a pocket), at r = 0.9 s it is inside.
    const fs::path dir = tempDir("pockets");
    const glm::dvec3 centre(0.0, 0.0, 0.0);
    writeBytes(dir / "ball.ply", sluicePlayPly(latticeBall(centre, 0.1, 0.02)));
    const glm::dvec3 cubeCentre = centre + glm::dvec3(0.01, 0.01, 0.01);
    for (const double radius : {0.01, 0.018}) {
        bake::SurfaceOptions options;
        options.radius = radius;
        options.voxelSize = 0.005; // the cube centre on a voxel: no interpolation
        Result<bake::SurfaceReport> report =
            bake::writeParticleSurfaces({dir / "ball.ply"}, dir / "ball.vdb", options);
        ASSERT_TRUE(report) << report.error().message();
        const openvdb::FloatGrid::Ptr grid = readOnlyGrid(dir / "ball.vdb");
        ASSERT_TRUE(grid);
        // sqrt(3) * 0.01 = 0.0173 from the nearest particles.
        const double expected = std::sqrt(3.0) * 0.01 - radius;
        EXPECT_NEAR(sample(*grid, cubeCentre), expected, 0.1 * options.voxelSize) << radius;
    }
}

} // namespace
