// OpenVDB interchange: export round trip, level-set import against an analytic sphere, bad files.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "interop/VdbHeaders.h"
#include "TestMeshes.h"
#include "sluice/bake/interop/VdbIO.h"
#include "sluice/format/support/Hash.h"

namespace fs = std::filesystem;
using namespace sluice;

namespace {

// A sphere of radius 12 voxels whose centre sits between grid points, on a grid whose three
// dimensions differ so that any axis mix-up shows.
constexpr double kVoxel = 0.05;                    // [world units]
constexpr double kRadius = 12.0 * kVoxel;          // [world units]
const glm::uvec3 kDims{37, 39, 41};                // [grid points]
const glm::dvec3 kOrigin{-1.013, 0.4217, -0.9981}; // [world units]
const glm::dvec3 kCentre = kOrigin + glm::dvec3(18.3, 19.1, 20.45) * kVoxel;

format::ColliderAsset sphereAsset() {
    return testmesh::assetFromSdf(kDims, kOrigin, kVoxel,
                     [](const glm::dvec3& p) { return testmesh::sphereSdf(p, kCentre, kRadius); });
}

std::vector<char> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const char* data, std::size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(data, std::streamsize(size));
}

std::vector<std::string> folderEntries(const fs::path& folder) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder))
        names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Writes grids with the plain OpenVDB API, as a third-party tool would.
void writeWithOpenVdb(const fs::path& path, const openvdb::GridPtrVec& grids) {
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.write(grids);
    file.close();
}

openvdb::FloatGrid::Ptr sphereFloatGrid(openvdb::GridClass gridClass, float shift = 0.0f) {
    auto grid = openvdb::FloatGrid::create(float(kRadius));
    grid->setTransform(openvdb::math::Transform::createLinearTransform(kVoxel));
    grid->setGridClass(gridClass);
    grid->setName("density");
    auto accessor = grid->getAccessor();
    for (int k = -16; k <= 16; ++k)
        for (int j = -16; j <= 16; ++j)
            for (int i = -16; i <= 16; ++i)
                accessor.setValue(openvdb::Coord(i, j, k),
                                  float(glm::length(glm::dvec3(i, j, k)) * kVoxel - kRadius) +
                                      shift);
    return grid;
}

} // namespace

TEST(VdbIO, RoundTripReproducesEveryDistanceBitwise) {
    const fs::path dir = testmesh::tempDir("vdb-roundtrip");
    const format::ColliderAsset asset = sphereAsset();
    ASSERT_TRUE(bake::exportVdb(asset, dir / "sphere.vdb"));
    EXPECT_EQ(folderEntries(dir), std::vector<std::string>{"sphere.vdb"}) << "temp file left";

    auto back = bake::readVdbDense(dir / "sphere.vdb");
    ASSERT_TRUE(back) << back.error().message();
    EXPECT_EQ(back->meta.dims, asset.meta.dims);
    EXPECT_EQ(back->meta.origin, asset.meta.origin);
    EXPECT_EQ(back->meta.voxelSize, asset.meta.voxelSize);
    ASSERT_EQ(back->distances.size(), asset.distances.size());
    EXPECT_EQ(std::memcmp(back->distances.data(), asset.distances.data(),
                          asset.distances.size() * sizeof(float)),
              0);
    // Provenance travels as grid metadata.
    EXPECT_EQ(back->meta.sourceFile, "analytic.obj");
    EXPECT_EQ(back->meta.sourceHash, "0123456789abcdef");
    EXPECT_EQ(back->meta.toolVersion, "sluice-bake 0.1.0");
    EXPECT_EQ(back->meta.bake.backend, "analytic");
}

TEST(VdbIO, ExportedFileIsAPlainOpenVdbLevelSet) {
    const fs::path dir = testmesh::tempDir("vdb-plain");
    const format::ColliderAsset asset = sphereAsset();
    ASSERT_TRUE(bake::exportVdb(asset, dir / "sphere.vdb"));

    openvdb::initialize();
    openvdb::io::File file((dir / "sphere.vdb").string());
    file.open(false);
    openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();
    ASSERT_EQ(grids->size(), 1u);
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(grids->front());
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getName(), "sdf");
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_TRUE(grid->transform().isLinear());
    EXPECT_EQ(grid->transform().voxelSize(), openvdb::Vec3d(kVoxel));
    EXPECT_EQ(grid->activeVoxelCount(), asset.pointCount());
    EXPECT_EQ(grid->evalActiveVoxelBoundingBox(),
              openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(36, 38, 40)));
    float largest = 0.0f;
    for (float d : asset.distances)
        largest = std::max(largest, std::abs(d));
    EXPECT_EQ(grid->background(), largest);

    // Index (i, j, k) is the world point origin + (i, j, k) * voxelSize, holding that distance.
    const openvdb::Vec3d world = grid->transform().indexToWorld(openvdb::Coord(5, 7, 11));
    const glm::dvec3 expected = asset.pointPosition(5, 7, 11);
    EXPECT_NEAR(world.x(), expected.x, 1e-12);
    EXPECT_NEAR(world.y(), expected.y, 1e-12);
    EXPECT_NEAR(world.z(), expected.z, 1e-12);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(5, 7, 11)),
              asset.distances[asset.index(5, 7, 11)]);

    auto source = grid->getMetadata<openvdb::StringMetadata>("sluice_source_file");
    ASSERT_TRUE(source);
    EXPECT_EQ(source->value(), "analytic.obj");
    auto hash = grid->getMetadata<openvdb::StringMetadata>("sluice_source_hash");
    ASSERT_TRUE(hash);
    EXPECT_EQ(hash->value(), "0123456789abcdef");
    auto tool = grid->getMetadata<openvdb::StringMetadata>("sluice_tool_version");
    ASSERT_TRUE(tool);
    EXPECT_EQ(tool->value(), "sluice-bake 0.1.0");
}

TEST(VdbIO, ExportReplacesAnExistingFile) {
    const fs::path dir = testmesh::tempDir("vdb-replace");
    writeBytes(dir / "sphere.vdb", "old", 3);
    ASSERT_TRUE(bake::exportVdb(sphereAsset(), dir / "sphere.vdb"));
    EXPECT_EQ(folderEntries(dir), std::vector<std::string>{"sphere.vdb"});
    EXPECT_TRUE(bake::readVdbDense(dir / "sphere.vdb"));
}

TEST(VdbIO, ExportToAMissingFolderFailsWithIoAndWritesNothing) {
    const fs::path dir = testmesh::tempDir("vdb-missing-folder");
    auto written = bake::exportVdb(sphereAsset(), dir / "no-such-folder" / "sphere.vdb");
    ASSERT_FALSE(written);
    EXPECT_EQ(written.error().code, ErrorCode::Io);
    EXPECT_NE(written.error().detail.find("no-such-folder"), std::string::npos);
    EXPECT_TRUE(folderEntries(dir).empty());
}

TEST(VdbIO, ExportRejectsAnInconsistentOrNonFiniteAsset) {
    const fs::path dir = testmesh::tempDir("vdb-bad-asset");
    format::ColliderAsset shortAsset = sphereAsset();
    shortAsset.distances.pop_back();
    auto wrongSize = bake::exportVdb(shortAsset, dir / "a.vdb");
    ASSERT_FALSE(wrongSize);
    EXPECT_EQ(wrongSize.error().code, ErrorCode::InvalidArgument);

    format::ColliderAsset nanAsset = sphereAsset();
    nanAsset.distances[1234] = std::nanf("");
    auto nonFinite = bake::exportVdb(nanAsset, dir / "b.vdb");
    ASSERT_FALSE(nonFinite);
    EXPECT_EQ(nonFinite.error().code, ErrorCode::NonFinite);
    EXPECT_TRUE(folderEntries(dir).empty());
}

// volumeToMesh places one vertex per surface cell: the mean of the linearly interpolated edge
// crossings. On a sphere of radius R voxels the exact SDF is linear along an edge to within
// ~1/(8R) voxel, and averaging crossings that lie on the sphere moves the vertex inwards by the
// sagitta of a chord up to ~1.7 voxels long: 1.7^2 / (8R) ~ 0.03 voxel at R = 12. Measured:
// 0.030 voxel worst vertex, bounds 0.028 voxel inside the sphere's box. The 0.05 voxel bound
// leaves room for that and still fails on a half-voxel shift or a wrong origin.
TEST(VdbIO, ImportedLevelSetLiesOnTheAnalyticSphere) {
    const fs::path dir = testmesh::tempDir("vdb-import");
    ASSERT_TRUE(bake::exportVdb(sphereAsset(), dir / "sphere.vdb"));
    auto mesh = bake::importVdbLevelSet(dir / "sphere.vdb");
    ASSERT_TRUE(mesh) << mesh.error().message();

    const bake::TriangleSoup& soup = mesh->soup;
    ASSERT_GT(soup.triangles.size(), 1000u);
    EXPECT_TRUE(mesh->diagnostics.closed);
    EXPECT_EQ(mesh->diagnostics.boundaryEdges, 0u);
    EXPECT_EQ(mesh->diagnostics.nonManifoldEdges, 0u);
    EXPECT_EQ(mesh->diagnostics.triangles, soup.triangles.size());
    EXPECT_EQ(mesh->diagnostics.vertices, soup.positions.size());

    double worst = 0.0; // [voxels]
    for (const glm::dvec3& p : soup.positions)
        worst = std::max(worst, std::abs(glm::length(p - kCentre) - kRadius) / kVoxel);
    EXPECT_LT(worst, 0.05) << "worst vertex off the sphere [voxels]";

    const bake::Box box = soup.bounds();
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(box.lo[a], kCentre[a] - kRadius, 0.05 * kVoxel) << "axis " << a;
        EXPECT_NEAR(box.hi[a], kCentre[a] + kRadius, 0.05 * kVoxel) << "axis " << a;
    }
    // Outward triangles: positive enclosed volume, within the polyhedron's ~1 % shortfall.
    const double sphereVolume = 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);
    EXPECT_NEAR(testmesh::signedVolume(soup) / sphereVolume, 1.0, 0.01);

    EXPECT_EQ(mesh->sourceFile, "sphere.vdb");
    auto hash = format::hashFileHex(dir / "sphere.vdb");
    ASSERT_TRUE(hash);
    EXPECT_EQ(mesh->sourceHash, *hash);
}

TEST(VdbIO, ImportScalesTheSurface) {
    const fs::path dir = testmesh::tempDir("vdb-import-scale");
    ASSERT_TRUE(bake::exportVdb(sphereAsset(), dir / "sphere.vdb"));
    auto unit = bake::importVdbLevelSet(dir / "sphere.vdb");
    auto doubled = bake::importVdbLevelSet(dir / "sphere.vdb", 2.0);
    ASSERT_TRUE(unit);
    ASSERT_TRUE(doubled);
    EXPECT_EQ(doubled->soup.bounds().lo, 2.0 * unit->soup.bounds().lo);
    EXPECT_EQ(doubled->soup.bounds().hi, 2.0 * unit->soup.bounds().hi);
    auto bad = bake::importVdbLevelSet(dir / "sphere.vdb", -1.0);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, ErrorCode::InvalidArgument);
}

TEST(VdbIO, ImportReadsAFloatGridThatIsNotALevelSet) {
    const fs::path dir = testmesh::tempDir("vdb-fog");
    writeWithOpenVdb(dir / "fog.vdb", {sphereFloatGrid(openvdb::GRID_FOG_VOLUME)});
    auto mesh = bake::importVdbLevelSet(dir / "fog.vdb");
    ASSERT_TRUE(mesh) << mesh.error().message();
    EXPECT_TRUE(mesh->diagnostics.closed);
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(mesh->soup.bounds().hi[a], kRadius, 0.1 * kVoxel);
}

TEST(VdbIO, ImportPrefersTheLevelSetOverOtherGrids) {
    const fs::path dir = testmesh::tempDir("vdb-mixed");
    auto fog = sphereFloatGrid(openvdb::GRID_FOG_VOLUME, float(-5 * kVoxel)); // radius 17 voxels
    fog->setName("a_fog");
    auto levelSet = sphereFloatGrid(openvdb::GRID_LEVEL_SET);
    levelSet->setName("b_surface");
    auto velocity = openvdb::Vec3SGrid::create();
    velocity->setName("0_velocity");
    velocity->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 0, 0));
    writeWithOpenVdb(dir / "mixed.vdb", {velocity, fog, levelSet});
    auto mesh = bake::importVdbLevelSet(dir / "mixed.vdb");
    ASSERT_TRUE(mesh) << mesh.error().message();
    for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(mesh->soup.bounds().hi[a], kRadius, 0.1 * kVoxel);
}

TEST(VdbIO, GridsWithoutASurfaceAreEmptyMeshErrors) {
    const fs::path dir = testmesh::tempDir("vdb-empty");
    auto empty = openvdb::FloatGrid::create(1.0f);
    empty->setGridClass(openvdb::GRID_LEVEL_SET);
    writeWithOpenVdb(dir / "empty.vdb", {empty});
    auto noVoxels = bake::importVdbLevelSet(dir / "empty.vdb");
    ASSERT_FALSE(noVoxels);
    EXPECT_EQ(noVoxels.error().code, ErrorCode::EmptyMesh);
    EXPECT_NE(noVoxels.error().detail.find("empty.vdb"), std::string::npos);
    auto dense = bake::readVdbDense(dir / "empty.vdb");
    ASSERT_FALSE(dense);
    EXPECT_EQ(dense.error().code, ErrorCode::EmptyMesh);

    // Every value positive: active voxels but no zero crossing.
    writeWithOpenVdb(dir / "outside.vdb",
                     {sphereFloatGrid(openvdb::GRID_LEVEL_SET, float(100 * kRadius))});
    auto noCrossing = bake::importVdbLevelSet(dir / "outside.vdb");
    ASSERT_FALSE(noCrossing);
    EXPECT_EQ(noCrossing.error().code, ErrorCode::EmptyMesh);
}

TEST(VdbIO, ATextFileIsNotAVdb) {
    const fs::path dir = testmesh::tempDir("vdb-text");
    const std::string text = "solid cube\n  facet normal 0 0 1\n";
    writeBytes(dir / "cube.vdb", text.data(), text.size());
    for (const auto& error : {bake::importVdbLevelSet(dir / "cube.vdb").error(),
                              bake::readVdbDense(dir / "cube.vdb").error()}) {
        EXPECT_EQ(error.code, ErrorCode::MeshImport);
        EXPECT_NE(error.detail.find("cube.vdb"), std::string::npos);
    }
    writeBytes(dir / "zero.vdb", "", 0);
    EXPECT_EQ(bake::readVdbDense(dir / "zero.vdb").error().code, ErrorCode::MeshImport);
}

TEST(VdbIO, AMissingFileIsAnIoError) {
    const fs::path dir = testmesh::tempDir("vdb-missing");
    auto mesh = bake::importVdbLevelSet(dir / "nothing.vdb");
    ASSERT_FALSE(mesh);
    EXPECT_EQ(mesh.error().code, ErrorCode::Io);
    EXPECT_NE(mesh.error().detail.find("nothing.vdb"), std::string::npos);
    auto dense = bake::readVdbDense(dir / "nothing.vdb");
    ASSERT_FALSE(dense);
    EXPECT_EQ(dense.error().code, ErrorCode::Io);
    EXPECT_EQ(bake::readVdbDense(dir).error().code, ErrorCode::Io) << "a folder";
}

TEST(VdbIO, RejectsTruncatedFiles) {
    const fs::path dir = testmesh::tempDir("vdb-truncated");
    // Small, with two leaves so that cuts also fall between nodes (11 KB, mostly node masks).
    const auto small = testmesh::assetFromSdf({12, 5, 4}, {0.0, 0.0, 0.0}, 0.25, [](const glm::dvec3& p) {
        return testmesh::sphereSdf(p, {1.4, 0.5, 0.4}, 0.6);
    });
    ASSERT_TRUE(bake::exportVdb(small, dir / "whole.vdb"));
    const std::vector<char> bytes = readBytes(dir / "whole.vdb");
    ASSERT_GT(bytes.size(), 200u);
    const fs::path cut = dir / "cut.vdb";
    // Every prefix through the header, metadata, transform and grid descriptor, then every
    // 11th byte through the node masks and values, then every prefix of the last 128 bytes.
    std::vector<std::size_t> sizes;
    for (std::size_t size = 1; size < bytes.size(); ++size)
        if (size < 1024 || size % 11 == 0 || size + 128 > bytes.size())
            sizes.push_back(size);
    for (std::size_t size : sizes) {
        writeBytes(cut, bytes.data(), size);
        auto dense = bake::readVdbDense(cut);
        ASSERT_FALSE(dense) << "prefix of " << size << " bytes read as a whole grid";
        EXPECT_EQ(dense.error().code, ErrorCode::Truncated)
            << size << ": " << dense.error().message();
        EXPECT_NE(dense.error().detail.find("cut.vdb"), std::string::npos);
    }
    // And through the import path, at a few cuts.
    for (std::size_t size : {std::size_t(5), std::size_t(64), bytes.size() / 2, bytes.size() - 1}) {
        writeBytes(cut, bytes.data(), size);
        auto mesh = bake::importVdbLevelSet(cut);
        ASSERT_FALSE(mesh);
        EXPECT_EQ(mesh.error().code, ErrorCode::Truncated) << size;
    }
}

TEST(VdbIO, ReadsAVdbWrittenAsAStreamWithoutGridOffsets) {
    const fs::path dir = testmesh::tempDir("vdb-stream");
    {
        openvdb::initialize();
        std::ofstream out(dir / "stream.vdb", std::ios::binary);
        openvdb::io::Stream(out).write(
            openvdb::GridCPtrVec{sphereFloatGrid(openvdb::GRID_LEVEL_SET)});
    }
    auto dense = bake::readVdbDense(dir / "stream.vdb");
    ASSERT_TRUE(dense) << dense.error().message();
    EXPECT_EQ(dense->meta.dims, glm::uvec3(33));
    EXPECT_EQ(dense->meta.origin, glm::dvec3(-16 * kVoxel));
    EXPECT_EQ(dense->meta.sourceFile, "stream.vdb") << "a foreign file is its own source";
    EXPECT_EQ(dense->meta.bake.signUsed, format::SignMethod::Level);
    auto mesh = bake::importVdbLevelSet(dir / "stream.vdb");
    ASSERT_TRUE(mesh) << mesh.error().message();
    EXPECT_TRUE(mesh->diagnostics.closed);
}

TEST(VdbIO, AVdbWithOnlyAVectorGridIsUnsupported) {
    const fs::path dir = testmesh::tempDir("vdb-vec3");
    auto velocity = openvdb::Vec3SGrid::create();
    velocity->setName("velocity");
    velocity->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 0, 0));
    writeWithOpenVdb(dir / "velocity.vdb", {velocity});
    for (const auto& error : {bake::importVdbLevelSet(dir / "velocity.vdb").error(),
                              bake::readVdbDense(dir / "velocity.vdb").error()}) {
        EXPECT_EQ(error.code, ErrorCode::Unsupported);
        EXPECT_NE(error.detail.find("velocity.vdb"), std::string::npos);
        EXPECT_NE(error.detail.find("vec3s"), std::string::npos) << error.detail;
    }
}

TEST(VdbIO, DenseReadRejectsARotatedGrid) {
    const fs::path dir = testmesh::tempDir("vdb-rotated");
    auto grid = sphereFloatGrid(openvdb::GRID_LEVEL_SET);
    auto transform = openvdb::math::Transform::createLinearTransform(kVoxel);
    transform->preRotate(0.3, openvdb::math::Z_AXIS);
    grid->setTransform(transform);
    writeWithOpenVdb(dir / "rotated.vdb", {grid});
    auto dense = bake::readVdbDense(dir / "rotated.vdb");
    ASSERT_FALSE(dense);
    EXPECT_EQ(dense.error().code, ErrorCode::Unsupported);
    // The mesh path works in world space, so a rotated level set still imports.
    auto mesh = bake::importVdbLevelSet(dir / "rotated.vdb");
    ASSERT_TRUE(mesh) << mesh.error().message();
    EXPECT_TRUE(mesh->diagnostics.closed);
}
