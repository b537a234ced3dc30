// `sluice-bake surface`: particle frames to OpenVDB level sets on the command line, read back
// with OpenVDB; one grid per frame; bad input exits 2 and writes nothing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "CliRun.h"
#include "LevelSetProbe.h"
#include "TestParticles.h"
#include "interop/VdbHeaders.h"

SLUICE_VDB_WARNINGS_OFF
#include <openvdb/tools/Interpolation.h>
SLUICE_VDB_WARNINGS_ON

namespace fs = std::filesystem;
using namespace sluice;
using namespace sluice::bake::clirun;
using namespace sluice::testparticles;

namespace {

using sluice::testlevelset::sample;
using sluice::testlevelset::zeroCrossing;

// A ball of particles on a lattice, centred off the voxel grid so that the crossings are not
// voxel centres. sluice-play's particle radius is half its spacing.
constexpr double kSpacing = 0.02;      // [world units]
constexpr double kRadius = 0.01;       // [world units] of a particle
constexpr double kBall = 0.1;          // [world units] radius of the ball of particle centres
constexpr double kVoxel = kRadius / 2; // [world units] the default voxel size
const glm::dvec3 kCentre{0.0123, -0.0071, 0.0042};

/// Every grid of a .vdb file, read with OpenVDB itself.
openvdb::GridPtrVecPtr readGrids(const fs::path& path) {
    bake::initOpenVdb();
    openvdb::io::File file(path.string());
    file.open();
    openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();
    return grids;
}

fs::path surfaceDir(const std::string& name) {
    return testrun::tempDir("cli-surface-" + name);
}

/// The one level-set grid of `output`, named `name`.
openvdb::FloatGrid::Ptr readOneGrid(const fs::path& output, const std::string& name) {
    const openvdb::GridPtrVecPtr grids = readGrids(output);
    EXPECT_EQ(grids->size(), 1u);
    if (grids->empty())
        return nullptr;
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[0]);
    EXPECT_TRUE(grid);
    if (!grid)
        return nullptr;
    EXPECT_EQ(grid->getName(), name);
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_NEAR(grid->voxelSize()[0], kVoxel, 1e-9);   // kVoxel, or half the float radius
    EXPECT_NEAR(grid->background(), 3 * kVoxel, 1e-7); // OpenVDB's half-width, 3 voxels
    return grid;
}

/// [world units] The largest distance between the zero crossings along the six axis directions
/// from `kCentre` and `expected`, starting from the outermost particle on each axis.
double worstAxisCrossing(const openvdb::FloatGrid& grid, double expected) {
    double worst = 0.0;
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) {
            glm::dvec3 along(0.0);
            along[axis] = sign;
            const double t =
                kBall + zeroCrossing(grid, kCentre + along * kBall, along, 0.05, kVoxel);
            EXPECT_FALSE(std::isnan(t)) << "no crossing along axis " << axis;
            worst = std::max(worst, std::isnan(t) ? HUGE_VAL : std::abs(t - expected));
        }
    return worst;
}

TEST(CliSurface, ABallOfParticlesBecomesTheFluidsSurfaceWithTheRadiusFromTheHeader) {
    const fs::path dir = surfaceDir("ball");
    const fs::path ply = dir / "frame_000015.ply";
    const std::vector<glm::dvec3> particles = latticeBall(kCentre, kBall, kSpacing);
    // As sluice-play records its radius: %.9g of the float 0.01.
    writeBytes(ply, sluicePlayPly(particles, "0.00999999978"));
    const fs::path output = dir / "out" / "ball.vdb";
    const RunResult run = runBake(dir, {"surface", ply.string(), "-o", output.string()});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("fluid surface"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("frame_000015  515 particles, radius 0.01 (header)"), std::string::npos)
        << run.out;
    const openvdb::FloatGrid::Ptr grid = readOneGrid(output, "frame_000015");
    ASSERT_TRUE(grid);

    // Inside at the centre, outside well beyond the ball.
    EXPECT_LT(sample(*grid, kCentre), -kVoxel);
    EXPECT_GT(sample(*grid, kCentre + glm::dvec3(0.3, 0, 0)), 0.0);
    EXPECT_GT(sample(*grid, kCentre + glm::dvec3(0, -0.2, 0.2)), 0.0);

    // No pockets: every particle's centre and the centre of every lattice cube of 8 particles
    // is inside.
    double largest = -HUGE_VAL;
    auto isParticle = [&](const glm::dvec3& offset) {
        return glm::length(offset) <= kBall * (1.0 + 1e-9);
    };
    for (const glm::dvec3& p : particles) {
        largest = std::max(largest, sample(*grid, p));
        bool cube = true;
        for (int corner = 0; corner < 8; ++corner)
            cube = cube && isParticle(p - kCentre +
                                      glm::dvec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1) *
                                          kSpacing);
        if (cube)
            largest = std::max(largest, sample(*grid, p + glm::dvec3(kSpacing / 2)));
    }
    EXPECT_LT(largest, 0.0) << "a pocket";

    // Along each axis the outermost particle sits on the ball of centres (5 spacings out) and
    // the fluid it samples ends half a spacing beyond it, as a lattice block does.
    const double worst = worstAxisCrossing(*grid, kBall + kSpacing / 2);
    std::printf("surface: zero crossing within %.3g voxel of the fluid's surface (ball + s / 2); "
                "largest value at particle and cube centres %.3g voxels\n",
                worst / kVoxel, largest / kVoxel);
    EXPECT_LE(worst, 0.25 * kVoxel + 0.05 * kVoxel);
}

TEST(CliSurface, SpheresGiveTheUnionOfParticleSpheres) {
    const fs::path dir = surfaceDir("spheres");
    const fs::path ply = dir / "frame_000015.ply";
    // The header's radius is overridden by --radius.
    writeBytes(ply, sluicePlayPly(latticeBall(kCentre, kBall, kSpacing), "0.5"));
    const fs::path output = dir / "ball.vdb";
    const RunResult run = runBake(dir, {"surface", ply.string(), "-o", output.string(), "--radius",
                                        std::to_string(kRadius), "--spheres"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("union of particle spheres"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("515 particles, radius 0.01 (--radius)"), std::string::npos) << run.out;
    const openvdb::FloatGrid::Ptr grid = readOneGrid(output, "frame_000015");
    ASSERT_TRUE(grid);
    // Inside at the centre (a particle's centre: about -radius), outside well beyond the ball.
    EXPECT_LT(sample(*grid, kCentre), -0.5 * kRadius);
    EXPECT_GT(sample(*grid, kCentre + glm::dvec3(0.3, 0, 0)), 0.0);
    // The union of spheres crosses zero one particle radius beyond the ball of centres.
    const double worst = worstAxisCrossing(*grid, kBall + kRadius);
    std::printf("surface --spheres: zero crossing within %.3g voxel of the union of spheres\n",
                worst / kVoxel);
    EXPECT_LE(worst, 0.25 * kVoxel);
    // The union's pocket at the centre of a lattice cube.
    EXPECT_GT(sample(*grid, kCentre + glm::dvec3(kSpacing / 2)), 0.0);
}

TEST(CliSurface, AFolderOfFramesGivesOneGridPerFrameInNameOrder) {
    const fs::path dir = surfaceDir("folder");
    const fs::path frames = dir / "frames";
    fs::create_directories(frames);
    // Written out of order; the bodies file and a note beside them are not frames.
    writeBytes(frames / "frame_000010.ply",
               sluicePlayPly(latticeBall(kCentre + glm::dvec3(0, -0.05, 0), 0.06, kSpacing)));
    writeBytes(frames / "frame_000000.ply", sluicePlayPly(latticeBall(kCentre, 0.06, kSpacing)));
    writeBytes(frames / "frame_000000.bodies.json", "{\"step\": 0, \"bodies\": []}");
    writeBytes(frames / "notes.txt", "not a frame");
    const fs::path output = dir / "frames.vdb";
    const RunResult run =
        runBake(dir, {"surface", frames.string(), "-o", output.string(), "--radius", "0.01"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);

    const openvdb::GridPtrVecPtr grids = readGrids(output);
    ASSERT_EQ(grids->size(), 2u);
    EXPECT_EQ((*grids)[0]->getName(), "frame_000000");
    EXPECT_EQ((*grids)[1]->getName(), "frame_000010");
    for (int n = 0; n < 2; ++n) {
        const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[std::size_t(n)]);
        ASSERT_TRUE(grid);
        EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
        // Each frame is its own ball: the second one fell by 0.05.
        const glm::dvec3 centre = kCentre + glm::dvec3(0, n == 0 ? 0.0 : -0.05, 0);
        EXPECT_LT(sample(*grid, centre), 0.0) << n;
        EXPECT_GT(sample(*grid, centre + glm::dvec3(0, n == 0 ? -0.1 : 0.1, 0)), 0.0) << n;
    }
}

/// A bad-input run of `surface PARTICLES -o OUT [extra]`, first without OUT, then over an
/// existing OUT, which must stay as it was.
void expectSurfaceRejected(const fs::path& dir, const fs::path& particles,
                           const std::vector<std::string>& extra, const std::string& named) {
    const fs::path output = dir / "out" / "surface.vdb";
    fs::remove_all(output.parent_path());
    std::vector<std::string> args = {"surface", particles.string(), "-o", output.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    SCOPED_TRACE(particles.filename().string() + " " + named);
    expectRejected(dir, args, named, output);
    fs::create_directories(output.parent_path());
    writeBytes(output, "previous level sets");
    expectRejected(dir, args, named, output);
}

TEST(CliSurface, BadInputExitsTwoNamingTheFileAndWritesNothing) {
    const fs::path dir = surfaceDir("bad-input");
    const std::vector<std::string> radius = {"--radius", "0.01"};
    const std::string good = sluicePlayPly(latticeBall(kCentre, 0.04, kSpacing));
    auto file = [&](const std::string& name, const std::string& bytes) {
        writeBytes(dir / name, bytes);
        return dir / name;
    };
    expectSurfaceRejected(dir, dir / "missing.ply", radius, "missing.ply");
    expectSurfaceRejected(dir, file("text.ply", "solid cube\nfacet normal 0 0 1\n"), radius,
                          "text.ply");
    expectSurfaceRejected(dir, file("cut.ply", good.substr(0, good.size() - 13)), radius,
                          "cut.ply");
    expectSurfaceRejected(dir, file("header-only.ply", good.substr(0, good.find("end_header"))),
                          radius, "header-only.ply");
    expectSurfaceRejected(dir, file("empty.ply", sluicePlayPly({})), radius, "empty.ply");
    expectSurfaceRejected(dir, file("nan.ply", sluicePlayPly({{0, 0, 0}, {NAN, 0, 0}})), radius,
                          "nan.ply");
    expectSurfaceRejected(dir, file("inf.ply", sluicePlayPly({{0, 0, 0}, {0, 0, INFINITY}})),
                          radius, "inf.ply");
    // A file recording no particle size: without --radius, the file and the option.
    const fs::path ball = file("ball.ply", good);
    expectSurfaceRejected(dir, ball, {}, "ball.ply");
    expectSurfaceRejected(dir, ball, {}, "--radius");
    // A header radius that is malformed, not finite or not > 0.
    const std::vector<glm::dvec3> points = latticeBall(kCentre, 0.04, kSpacing);
    for (const char* value : {"abc", "0.01x", "nan", "inf", "0", "-0.01"}) {
        expectSurfaceRejected(dir, file("bad-radius.ply", sluicePlayPly(points, value)), {},
                              "bad-radius.ply");
    }
    // A folder with no PLY files in it (only what sluice-play writes beside them).
    fs::create_directories(dir / "no-frames");
    writeBytes(dir / "no-frames" / "frame_000000.bodies.json", "{}");
    expectSurfaceRejected(dir, dir / "no-frames", radius, "no-frames");
    // A folder with one bad frame among good ones writes none of them.
    fs::create_directories(dir / "one-bad");
    writeBytes(dir / "one-bad" / "frame_000000.ply", good);
    writeBytes(dir / "one-bad" / "frame_000001.ply", good.substr(0, good.size() / 2));
    expectSurfaceRejected(dir, dir / "one-bad", radius, "frame_000001.ply");
}

TEST(CliSurface, BadSizesAndOutputsExitTwoAndWriteNothing) {
    const fs::path dir = surfaceDir("bad-sizes");
    const fs::path ball = dir / "ball.ply";
    writeBytes(ball, sluicePlayPly(latticeBall(kCentre, 0.04, kSpacing)));
    for (const char* value : {"0", "-0.01", "nan", "inf", "abc"}) {
        expectSurfaceRejected(dir, ball, {"--radius", value}, "--radius");
        expectSurfaceRejected(dir, ball, {"--radius", "0.01", "--voxel-size", value},
                              "--voxel-size");
    }
    // OpenVDB rasterises spheres of 1.5 to 100 voxels only.
    // Spheres of the radius (--spheres) or of twice the radius (the fluid's surface).
    expectSurfaceRejected(dir, ball, {"--radius", "0.01", "--voxel-size", "0.01", "--spheres"},
                          "--voxel-size");
    expectSurfaceRejected(dir, ball, {"--radius", "0.01", "--voxel-size", "0.02"}, "--voxel-size");
    expectSurfaceRejected(dir, ball, {"--radius", "0.01", "--voxel-size", "0.00005"},
                          "--voxel-size");

    // Outputs that cannot be written: not .vdb, under a file, a folder.
    const std::vector<std::string> args = {"surface", ball.string(), "--radius", "0.01", "-o"};
    auto with = [&](const fs::path& out) {
        std::vector<std::string> all = args;
        all.push_back(out.string());
        return all;
    };
    expectRejected(dir, with(dir / "surface.slc"), "surface.slc", dir / "surface.slc");
    writeBytes(dir / "a-file", "not a folder");
    expectRejected(dir, with(dir / "a-file" / "x.vdb"), "a-file", dir / "a-file" / "x.vdb");
    fs::create_directories(dir / "folder.vdb");
    const RunResult run = runBake(dir, with(dir / "folder.vdb"));
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_NE(run.err.find("folder.vdb"), std::string::npos) << run.err;
    EXPECT_TRUE(fs::is_directory(dir / "folder.vdb"));
}

TEST(CliSurface, VdbPrintReadsTheOutputWhenInstalled) {
    if (std::system("command -v vdb_print > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "vdb_print (Debian's openvdb-tools) is not installed";
    const fs::path dir = surfaceDir("vdb-print");
    writeBytes(dir / "frame_000001.ply", sluicePlayPly(latticeBall(kCentre, 0.04, kSpacing)));
    const fs::path output = dir / "frames.vdb";
    ASSERT_EQ(runBake(dir, {"surface", (dir / "frame_000001.ply").string(), "-o", output.string(),
                            "--radius", "0.01"})
                  .code,
              kExitOk);
    const fs::path listing = dir / "listing.txt";
    ASSERT_EQ(std::system(("vdb_print -l " + quote(output.string()) + " > " +
                           quote(listing.string()) + " 2>&1")
                              .c_str()),
              0);
    const std::string text = readText(listing);
    EXPECT_NE(text.find("frame_000001"), std::string::npos) << text;
    EXPECT_NE(text.find("level set"), std::string::npos) << text;
}

} // namespace
