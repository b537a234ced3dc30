// Particle frames to level sets as a library: the PLY particle reader on hostile and foreign
// files and header radii, per-vertex radii, the sign of OpenVDB's offset, a lattice block's
// flat faces, and what the union of spheres does between lattice neighbours.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "LevelSetProbe.h"
#include "ProgramRun.h"
#include "TestParticles.h"
#include "interop/ParticlePly.h"
#include "interop/VdbHeaders.h"
#include "sluice/bake/interop/ParticleLevelSet.h"

SLUICE_VDB_WARNINGS_OFF
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/LevelSetSphere.h>
SLUICE_VDB_WARNINGS_ON

namespace fs = std::filesystem;
using namespace sluice;
using namespace sluice::testparticles;

namespace {

using sluice::testlevelset::sample;
using sluice::testlevelset::zeroCrossing;

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

TEST(ParticlePly, ReadsTheHeadersParticleRadiusAmongCommentsAnywhere) {
    const fs::path dir = tempDir("header-radius");
    const std::vector<glm::dvec3> points = {{0.5, -0.25, 2.0}, {1.5, 7.0, -3.5}};
    // As sluice-play writes it (%.9g), right after its first comment.
    writeBytes(dir / "play.ply", sluicePlayPly(points, "0.00999999978"));
    Result<bake::detail::ParticleFrame> play = bake::detail::readParticlePly(dir / "play.ply");
    ASSERT_TRUE(play) << play.error().message();
    ASSERT_TRUE(play->headerRadius);
    EXPECT_EQ(*play->headerRadius, 0.00999999978);
    EXPECT_EQ(play->positions.size(), 2u);
    // Comments before "format", between elements and between properties are still skipped, and
    // the radius is found wherever it is; other comments that start alike are not it.
    std::string text = asciiPlyWithRadius(points, {0.25, 0.125});
    text.replace(text.find("format"), 0, "comment particle_radiusX 5\n");
    text.replace(text.find("element vertex"), 0, "comment between elements\n");
    text.replace(text.find("property double y"), 0, "comment particle_radius  0.5 \n");
    text.replace(text.find("end_header"), 0, "obj_info and a comment\ncomment\n");
    writeBytes(dir / "anywhere.ply", text);
    Result<bake::detail::ParticleFrame> anywhere =
        bake::detail::readParticlePly(dir / "anywhere.ply");
    ASSERT_TRUE(anywhere) << anywhere.error().message();
    ASSERT_TRUE(anywhere->headerRadius);
    EXPECT_EQ(*anywhere->headerRadius, 0.5);
    EXPECT_EQ(anywhere->radii, (std::vector<double>{0.25, 0.125}));
    writeBytes(dir / "none.ply", sluicePlayPly(points));
    Result<bake::detail::ParticleFrame> none = bake::detail::readParticlePly(dir / "none.ply");
    ASSERT_TRUE(none) << none.error().message();
    EXPECT_FALSE(none->headerRadius);

    // A bad value names the file and the line: malformed (" ": no value), non-finite, not > 0,
    // given twice.
    const std::pair<std::string, ErrorCode> bad[] = {
        {"abc", ErrorCode::MeshImport},
        {"0.01x", ErrorCode::MeshImport},
        {"0.01 0.02", ErrorCode::MeshImport},
        {" ", ErrorCode::MeshImport},
        {"nan", ErrorCode::NonFinite},
        {"inf", ErrorCode::NonFinite},
        {"1e999", ErrorCode::NonFinite},
        {"0", ErrorCode::InvalidArgument},
        {"-0.01", ErrorCode::InvalidArgument},
        {"0.01\ncomment particle_radius 0.01", ErrorCode::MeshImport}};
    for (const auto& [value, code] : bad) {
        writeBytes(dir / "bad.ply", sluicePlayPly(points, value));
        Result<bake::detail::ParticleFrame> frame = bake::detail::readParticlePly(dir / "bad.ply");
        ASSERT_FALSE(frame) << value;
        EXPECT_EQ(frame.error().code, code) << value;
        EXPECT_NE(frame.error().detail.find("bad.ply': line "), std::string::npos)
            << frame.error().detail;
    }
}

TEST(ParticleLevelSet, APositiveOffsetErodesTheLevelSet) {
    // What erode() relies on: LevelSetFilter::offset(+d) moves the zero crossing d inwards,
    // and keeps a band of signed distances around it.
    bake::initOpenVdb();
    const double voxel = 0.005;
    openvdb::FloatGrid::Ptr ball = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        0.05f, openvdb::Vec3f(0.0f), float(voxel), 3.0f);
    openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*ball);
    filter.offset(0.01f);
    for (const double distance : {0.03, 0.035, 0.04, 0.045, 0.05}) {
        // A signed distance to the sphere of radius 0.04 now.
        EXPECT_NEAR(sample(*ball, {distance, 0, 0}), distance - 0.04, 0.1 * voxel) << distance;
        EXPECT_NEAR(sample(*ball, {0, 0, -distance}), distance - 0.04, 0.1 * voxel) << distance;
    }
}

TEST(ParticleLevelSet, ALatticeBlockEndsHalfASpacingBeyondItsOuterParticles) {
    // 8^3 particles of sluice-play's radius (half the spacing), off the voxel grid.
    const fs::path dir = tempDir("block");
    const double spacing = 0.02, voxel = 0.005;
    const glm::dvec3 corner(0.0123, -0.0071, 0.0042);
    writeBytes(dir / "block.ply", sluicePlayPly(latticeBlock(corner, 8, spacing)));
    bake::SurfaceOptions options;
    options.radius = 0.01;
    Result<bake::SurfaceReport> report =
        bake::writeParticleSurfaces({dir / "block.ply"}, dir / "block.vdb", options);
    ASSERT_TRUE(report) << report.error().message();
    EXPECT_DOUBLE_EQ(report->voxelSize, voxel);
    const openvdb::FloatGrid::Ptr grid = readOnlyGrid(dir / "block.vdb");
    ASSERT_TRUE(grid);
    EXPECT_NEAR(grid->background(), 3 * voxel, 1e-7);

    // The +x face, from the middle of the block, at points (a, b) of a lattice cell across it:
    // (0, 0) over a particle's centre, (0.5, 0.5) between four. Over the centres the face is
    // where the block ends; between them the eroded union of spheres dips in (an exact
    // erosion's dip is (1 - 1/sqrt 2) spacing = 1.17 voxels deep between four particles).
    const double face = corner.x + 7.5 * spacing;
    double overCentres = 0.0, deepest = 0.0;
    for (const double a : {0.0, 0.25, 0.5})
        for (const double b : {0.0, 0.25, 0.5}) {
            const glm::dvec3 from(corner.x + 3.5 * spacing, corner.y + (3 + a) * spacing,
                                  corner.z + (3 + b) * spacing);
            const double x = from.x + zeroCrossing(*grid, from, {1, 0, 0}, 0.2, voxel);
            ASSERT_FALSE(std::isnan(x)) << a << " " << b;
            EXPECT_LE(x - face, 0.1 * voxel) << a << " " << b; // never beyond the block
            deepest = std::max(deepest, face - x);
            if (a == 0.0 && b == 0.0)
                overCentres = x - face;
        }
    std::printf("block face: %.3f voxel from the block's face over a particle, %.3f voxel at "
                "most inside it between particles\n",
                overCentres / voxel, deepest / voxel);
    EXPECT_LE(std::abs(overCentres), 0.25 * voxel);
    EXPECT_LE(deepest, 1.25 * voxel);

    // The band after the erosion: signed distances 2 voxels either side of the face.
    const glm::dvec3 onFace(face, corner.y + 3 * spacing, corner.z + 3 * spacing);
    for (const double d : {-2.0, 2.0}) {
        const double value = sample(*grid, onFace + glm::dvec3(d * voxel, 0, 0));
        EXPECT_TRUE(std::isfinite(value));
        EXPECT_LT(std::abs(value), 0.9 * grid->background()) << d;
        EXPECT_NEAR(value, d * voxel, 0.5 * voxel) << d;
    }
    // No pockets: every particle centre and every lattice cube's centre is inside.
    double largest = -1.0;
    for (int k = 0; k < 8; ++k)
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 8; ++i) {
                const glm::dvec3 p = corner + glm::dvec3(i, j, k) * spacing;
                largest = std::max(largest, sample(*grid, p));
                if (i < 7 && j < 7 && k < 7)
                    largest = std::max(largest, sample(*grid, p + glm::dvec3(spacing / 2)));
            }
    EXPECT_LT(largest, 0.0) << "a pocket";
    // Outside beyond the band.
    EXPECT_GT(sample(*grid, onFace + glm::dvec3(0.1, 0, 0)), 0.0);
}

TEST(ParticleLevelSet, PerVertexRadiiSizeEachSphereAndTheVoxel) {
    const fs::path dir = tempDir("per-vertex");
    // Two particles far apart, radii 0.01 and 0.02.
    const std::vector<glm::dvec3> points = {{0.0, 0.0, 0.0}, {0.3, 0.0, 0.0}};
    writeBytes(dir / "frame.ply", asciiPlyWithRadius(points, {0.01, 0.02}));
    for (const bool spheres : {true, false}) {
        bake::SurfaceOptions options;
        options.spheres = spheres;
        Result<bake::SurfaceReport> report =
            bake::writeParticleSurfaces({dir / "frame.ply"}, dir / "frame.vdb", options);
        ASSERT_TRUE(report) << report.error().message();
        EXPECT_EQ(report->radius, 0.0);
        EXPECT_DOUBLE_EQ(report->voxelSize, 0.005); // half the smallest radius
        ASSERT_EQ(report->frames.size(), 1u);
        EXPECT_EQ(report->frames[0].ignoredParticles, 0u);
        EXPECT_EQ(report->frames[0].radiusSource, bake::RadiusSource::PerVertex);
        const openvdb::FloatGrid::Ptr grid = readOnlyGrid(dir / "frame.vdb");
        ASSERT_TRUE(grid);
        // Spheres: radii 0.01 and 0.02. Fluid: spheres of 2 r_i eroded by the smallest r_i,
        // 0.01, so radii 0.01 and 0.03.
        const double small = 0.01, large = spheres ? 0.02 : 0.03;
        for (const double d : {0.005, 0.01, 0.015}) {
            EXPECT_NEAR(sample(*grid, points[0] + glm::dvec3(0, d, 0)), d - small, 1e-4) << d;
            EXPECT_NEAR(sample(*grid, points[1] + glm::dvec3(0, 0, large + d - 0.01)), d - 0.01,
                        1e-4)
                << d;
        }
    }
}

TEST(ParticleLevelSet, HalfSpacingSpheresLeavePocketsThatLargerOnesClose) {
    // With --spheres, the union of spheres of radius r around lattice points of spacing s is
    // solid only where r >= s * sqrt(3) / 2: at sluice-play's r = s / 2 the centre of each
    // lattice cube stays outside (a pocket), at r = 0.9 s it is inside. The fluid's surface
    // (the default) has none.
    const fs::path dir = tempDir("pockets");
    const glm::dvec3 centre(0.0, 0.0, 0.0);
    writeBytes(dir / "ball.ply", sluicePlayPly(latticeBall(centre, 0.1, 0.02)));
    const glm::dvec3 cubeCentre = centre + glm::dvec3(0.01, 0.01, 0.01);
    for (const double radius : {0.01, 0.018}) {
        bake::SurfaceOptions options;
        options.radius = radius;
        options.voxelSize = 0.005; // the cube centre on a voxel: no interpolation
        options.spheres = true;
        Result<bake::SurfaceReport> report =
            bake::writeParticleSurfaces({dir / "ball.ply"}, dir / "ball.vdb", options);
        ASSERT_TRUE(report) << report.error().message();
        const openvdb::FloatGrid::Ptr grid = readOnlyGrid(dir / "ball.vdb");
        ASSERT_TRUE(grid);
        // sqrt(3) * 0.01 = 0.0173 from the nearest particles.
        const double expected = std::sqrt(3.0) * 0.01 - radius;
        EXPECT_NEAR(sample(*grid, cubeCentre), expected, 0.1 * options.voxelSize) << radius;
        if (radius == 0.01) {
            options.spheres = false;
            ASSERT_TRUE(bake::writeParticleSurfaces({dir / "ball.ply"}, dir / "ball.vdb", options));
            EXPECT_LT(sample(*readOnlyGrid(dir / "ball.vdb"), cubeCentre), -options.voxelSize);
        }
    }
}

} // namespace
