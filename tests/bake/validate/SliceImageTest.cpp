// Slice pictures: argument parsing, what a sphere slice shows where, and the PNG file.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include "TestMeshes.h"
#include "sluice/bake/validate/SliceImage.h"

namespace fs = std::filesystem;
using namespace sluice;
using bake::Axis;

namespace {

// A sphere of radius 12 voxels centred on grid point (20, 18, 16) of a 41 x 37 x 33 grid.
constexpr double kVoxel = 0.1;              // [world units]
constexpr double kRadius = 12.0 * kVoxel;   // [world units]
const glm::uvec3 kDims{41, 37, 33};         // [grid points]
const glm::dvec3 kOrigin{-2.0, -1.8, -1.6}; // [world units]
const glm::dvec3 kCentreIndex{20, 18, 16};  // [voxels]
const glm::dvec3 kCentre = kOrigin + kCentreIndex * kVoxel;

format::ColliderAsset sphereAsset() {
    return testmesh::assetFromSdf(kDims, kOrigin, kVoxel, [](const glm::dvec3& p) {
        return testmesh::sphereSdf(p, kCentre, kRadius);
    });
}

struct Rgb {
    int r, g, b;
};

Rgb pixel(const bake::Image& image, int x, int y) {
    const std::size_t at = (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 3;
    return {image.rgb[at], image.rgb[at + 1], image.rgb[at + 2]};
}

// The pixel of the distance half (right = false) or gradient half showing grid coordinates
// (u, v) of the slice plane [voxels].
Rgb at(const bake::Image& image, const bake::SliceLayout& layout, double u, double v,
       bool right = false) {
    const int x =
        int(std::lround(u * layout.pixelsPerVoxel)) + (right ? layout.halfWidth + layout.gap : 0);
    const int y = layout.height - 1 - int(std::lround(v * layout.pixelsPerVoxel));
    return pixel(image, x, y);
}

bool isContour(const Rgb& c) {
    return std::max({c.r, c.g, c.b}) < 60;
}

/// Expects every contour pixel of the distance half within `tolerancePx` of the circle of
/// `radiusVoxels` around the sphere's centre, and about as many of them as a thin digital circle
/// has (4 * sqrt(2) * r, 8-connected). The circle's radius [px].
double expectContourOnCircle(const bake::Image& image, const bake::SliceLayout& layout,
                             double radiusVoxels, double tolerancePx) {
    const double cx = kCentreIndex.x * layout.pixelsPerVoxel;
    const double cy = layout.height - 1 - kCentreIndex.y * layout.pixelsPerVoxel;
    const double radiusPx = radiusVoxels * layout.pixelsPerVoxel;
    int contourPixels = 0;
    for (int y = 0; y < layout.height; ++y) // the field, above the legend
        for (int x = 0; x < layout.halfWidth; ++x)
            if (isContour(pixel(image, x, y))) {
                ++contourPixels;
                EXPECT_NEAR(std::hypot(x - cx, y - cy), radiusPx, tolerancePx) << x << ", " << y;
            }
    EXPECT_GT(contourPixels, int(5.0 * radiusPx));
    return radiusPx;
}

} // namespace

TEST(SliceImage, ParsesAxisAndFraction) {
    for (const auto& [text, axis, fraction] :
         {std::tuple<const char*, Axis, double>{"x=0", Axis::X, 0.0},
          {"y=0.5", Axis::Y, 0.5},
          {"z=1", Axis::Z, 1.0},
          {"Z=0.25", Axis::Z, 0.25}}) {
        auto slice = bake::parseSlice(text);
        ASSERT_TRUE(slice) << text;
        EXPECT_EQ(slice->axis, axis) << text;
        EXPECT_EQ(slice->fraction, fraction) << text;
    }
}

TEST(SliceImage, RejectsMalformedSlices) {
    for (const char* text : {"w=0.5", "x=1.5", "x=", "x=nan", "x=inf", "x=-0.1", "x=0.5y", "x", "",
                             "=0.5", "x:0.5", "xy=0.5", "x= 0.5"}) {
        auto slice = bake::parseSlice(text);
        ASSERT_FALSE(slice) << text;
        EXPECT_EQ(slice.error().code, ErrorCode::InvalidArgument) << text;
        EXPECT_NE(slice.error().detail.find(std::string("'") + text + "'"), std::string::npos)
            << slice.error().detail;
    }
}

TEST(SliceImage, LayoutUpscalesSmallGridsAndMapsAxes) {
    const format::ColliderAsset asset = sphereAsset();
    const auto z = bake::sliceLayout(asset.meta, {Axis::Z, 0.5});
    EXPECT_EQ(z.uAxis, Axis::X);
    EXPECT_EQ(z.vAxis, Axis::Y);
    EXPECT_EQ(z.pixelsPerVoxel, 13.0); // ceil(511 / 40)
    EXPECT_EQ(z.halfWidth, 40 * 13 + 1);
    EXPECT_EQ(z.height, 36 * 13 + 1);
    EXPECT_EQ(z.planeIndex, 16.0);
    const auto x = bake::sliceLayout(asset.meta, {Axis::X, 1.0});
    EXPECT_EQ(x.uAxis, Axis::Y);
    EXPECT_EQ(x.vAxis, Axis::Z);
    EXPECT_EQ(x.planeIndex, 40.0);
    EXPECT_GE(std::max(x.halfWidth, x.height), 512);
    const auto y = bake::sliceLayout(asset.meta, {Axis::Y, 0.0});
    EXPECT_EQ(y.uAxis, Axis::X);
    EXPECT_EQ(y.vAxis, Axis::Z);

    format::ColliderMeta big;
    big.dims = {4001, 3001, 2};
    big.voxelSize = 1.0;
    const auto large = bake::sliceLayout(big, {Axis::Z, 0.5});
    EXPECT_EQ(large.halfWidth, 2048);
    EXPECT_EQ(large.height, 1536);
}

TEST(SliceImage, SphereSliceShowsInsideOutsideAndTheZeroContour) {
    const format::ColliderAsset asset = sphereAsset();
    const bake::SliceSpec slice{Axis::Z, 0.5};
    const bake::SliceLayout layout = bake::sliceLayout(asset.meta, slice);
    const bake::Image image = bake::renderSlice(asset, slice);
    ASSERT_EQ(int(image.width), 2 * layout.halfWidth + layout.gap);
    ASSERT_EQ(int(image.height), layout.height + layout.legendHeight);
    ASSERT_EQ(image.rgb.size(), std::size_t(image.width) * image.height * 3);

    const Rgb centre = at(image, layout, kCentreIndex.x, kCentreIndex.y);
    EXPECT_GT(centre.b, centre.r + 100) << "inside is blue";
    EXPECT_GT(centre.b, centre.g + 50);
    for (auto [u, v] : {std::pair{0.0, 0.0}, std::pair{40.0, 36.0}}) {
        const Rgb corner = at(image, layout, u, v);
        EXPECT_GT(corner.r, corner.g + 100) << "outside is red";
        EXPECT_GT(corner.r, corner.b + 100);
    }
    // Just inside and outside the surface the map is nearly white, not the contour colour.
    const Rgb nearIn = at(image, layout, kCentreIndex.x + 11.0, kCentreIndex.y);
    const Rgb nearOut = at(image, layout, kCentreIndex.x + 13.0, kCentreIndex.y);
    EXPECT_GT(nearIn.b, nearIn.r);
    EXPECT_GT(nearOut.r, nearOut.b);
    EXPECT_FALSE(isContour(nearIn));
    EXPECT_FALSE(isContour(nearOut));

    // Every contour pixel lies on the circle of 12 voxels (156 px), and the circle is drawn all
    // the way round.
    const double radiusPx = expectContourOnCircle(image, layout, 12.0, 1.5);
    const double cx = kCentreIndex.x * layout.pixelsPerVoxel;
    const double cy = layout.height - 1 - kCentreIndex.y * layout.pixelsPerVoxel;
    for (int degree = 0; degree < 360; ++degree) {
        const double angle = degree * std::numbers::pi / 180.0;
        const int x = int(std::lround(cx + radiusPx * std::cos(angle)));
        const int y = int(std::lround(cy - radiusPx * std::sin(angle)));
        bool found = false;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                found = found || isContour(pixel(image, x + dx, y + dy));
        EXPECT_TRUE(found) << "no contour near " << degree << " degrees";
    }
}

TEST(SliceImage, GradientHalfMapsTheNormalToRgb) {
    const format::ColliderAsset asset = sphereAsset();
    const bake::SliceSpec slice{Axis::Z, 0.5};
    const bake::SliceLayout layout = bake::sliceLayout(asset.meta, slice);
    const bake::Image image = bake::renderSlice(asset, slice);
    const double cu = kCentreIndex.x, cv = kCentreIndex.y;
    // The normal points away from the centre: +x red, +y green; z = 0 in this plane, so blue
    // stays at the middle (128) and the other channel at 128 too.
    for (double offset : {6.0, 15.0}) { // inside and outside the sphere [voxels]
        const Rgb east = at(image, layout, cu + offset, cv, true);
        EXPECT_GT(east.r, 240);
        EXPECT_NEAR(east.g, 128, 3);
        EXPECT_NEAR(east.b, 128, 3);
        const Rgb west = at(image, layout, cu - offset, cv, true);
        EXPECT_LT(west.r, 15);
        EXPECT_NEAR(west.g, 128, 3);
        const Rgb north = at(image, layout, cu, cv + offset, true);
        EXPECT_GT(north.g, 240);
        EXPECT_NEAR(north.r, 128, 3);
        const Rgb south = at(image, layout, cu, cv - offset, true);
        EXPECT_LT(south.g, 15);
        EXPECT_NEAR(south.b, 128, 3);
    }
    // Diagonal: (1, 1, 0) / sqrt(2) -> r = g = 128 + 127 * 0.707.
    const Rgb northEast = at(image, layout, cu + 8.0, cv + 8.0, true);
    EXPECT_NEAR(northEast.r, 218, 4);
    EXPECT_NEAR(northEast.g, 218, 4);
    EXPECT_NEAR(northEast.b, 128, 3);
}

TEST(SliceImage, XSliceShowsYAcrossAndZUp) {
    const format::ColliderAsset asset = sphereAsset();
    const bake::SliceSpec slice{Axis::X, 0.5}; // plane i = 20, through the centre
    const bake::SliceLayout layout = bake::sliceLayout(asset.meta, slice);
    const bake::Image image = bake::renderSlice(asset, slice);
    const double cu = kCentreIndex.y, cv = kCentreIndex.z;
    const Rgb up = at(image, layout, cu, cv + 10.0, true);
    EXPECT_GT(up.b, 240) << "+z is up and blue";
    const Rgb right = at(image, layout, cu + 10.0, cv, true);
    EXPECT_GT(right.g, 240) << "+y is to the right and green";
    const Rgb inside = at(image, layout, cu, cv);
    EXPECT_GT(inside.b, inside.r + 100);
}

TEST(SliceImage, OffCentreSliceShowsTheSmallerCircle) {
    const format::ColliderAsset asset = sphereAsset();
    // z index 16 + 7.2 = 23.2: a circle of radius sqrt(12^2 - 7.2^2) = 9.6 voxels.
    const bake::SliceSpec slice{Axis::Z, 23.2 / 32.0};
    const bake::SliceLayout layout = bake::sliceLayout(asset.meta, slice);
    const bake::Image image = bake::renderSlice(asset, slice);
    // Trilinear interpolation of the sphere SDF between planes 23 and 24 bends the zero set by
    // well under a tenth of a voxel (1.3 px) at this radius.
    expectContourOnCircle(image, layout, 9.6, 1.5 + 1.3);
    // Above the plane, the normal tilts towards +z: blue above the middle at the centre.
    EXPECT_GT(at(image, layout, kCentreIndex.x, kCentreIndex.y, true).b, 240);
}

TEST(SliceImage, LegendUnderTheFieldHasAxisNamesAndAColourBar) {
    const format::ColliderAsset asset = sphereAsset();
    const bake::SliceSpec slice{Axis::X, 0.5};
    const bake::SliceLayout layout = bake::sliceLayout(asset.meta, slice);
    const bake::Image image = bake::renderSlice(asset, slice);
    ASSERT_GE(layout.legendHeight, 40);
    ASSERT_EQ(int(image.height), layout.height + layout.legendHeight);

    // Text: dark pixels on the light strip, under both halves; none in the last field row's
    // place, which still shows the field (outside: red at the corners).
    auto darkPixels = [&](int x0, int x1) {
        int count = 0;
        for (int y = layout.height; y < int(image.height); ++y)
            for (int x = x0; x < x1; ++x)
                count += isContour(pixel(image, x, y)) ? 1 : 0;
        return count;
    };
    EXPECT_GT(darkPixels(0, layout.halfWidth), 200) << "axis names and numbers";
    EXPECT_GT(darkPixels(layout.halfWidth + layout.gap, int(image.width)), 200) << "gradient key";
    const Rgb corner = at(image, layout, 0.0, 0.0);
    EXPECT_GT(corner.r, corner.b + 100) << "the field's bottom row is unchanged";

    // The colour bar: a row of the strip that is blue at the left end, white-ish with the dark
    // zero mark in the middle, red at the right end, as the field's colours are.
    int barRow = -1;
    for (int y = layout.height; y < int(image.height) && barRow < 0; ++y) {
        const Rgb left = pixel(image, 8, y);
        if (left.b > left.r + 100)
            barRow = y;
    }
    ASSERT_GE(barRow, 0) << "no colour bar";
    const Rgb leftEnd = pixel(image, 8, barRow);
    const Rgb rightEnd = pixel(image, layout.halfWidth - 8, barRow);
    EXPECT_GT(leftEnd.b, leftEnd.r + 100) << "inside end is blue";
    EXPECT_GT(rightEnd.r, rightEnd.b + 100) << "outside end is red";
    int zeroMarks = 0;
    for (int x = 0; x < layout.halfWidth; ++x)
        zeroMarks += isContour(pixel(image, x, barRow)) ? 1 : 0;
    EXPECT_EQ(zeroMarks, 1) << "one dark mark at zero";
    // The ends are the map's end colours, which the field's most inside and outside points
    // take: (0.08, 0.24, 0.70) and (0.75, 0.08, 0.08) in 8 bits.
    EXPECT_NEAR(leftEnd.r, 20, 2);
    EXPECT_NEAR(leftEnd.g, 61, 2);
    EXPECT_NEAR(leftEnd.b, 179, 2);
    EXPECT_NEAR(rightEnd.r, 191, 6);
    EXPECT_NEAR(rightEnd.g, 20, 6);
    EXPECT_NEAR(rightEnd.b, 20, 6);
}

TEST(SliceImage, WritesAPngThatDecodesToTheSamePixels) {
    const fs::path dir = testmesh::tempDir("slice-png");
    const format::ColliderAsset asset = sphereAsset();
    const bake::Image image = bake::renderSlice(asset, {Axis::Z, 0.5});
    ASSERT_TRUE(format::writePng(dir / "sphere.png", image));

    std::ifstream in(dir / "sphere.png", std::ios::binary);
    const std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in),
                                           std::istreambuf_iterator<char>()};
    ASSERT_GT(bytes.size(), 33u);
    const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    EXPECT_EQ(std::memcmp(bytes.data(), signature, 8), 0);

    int width = 0, height = 0, channels = 0;
    unsigned char* decoded =
        stbi_load_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels, 3);
    ASSERT_NE(decoded, nullptr) << stbi_failure_reason();
    EXPECT_EQ(width, int(image.width));
    EXPECT_EQ(height, int(image.height));
    EXPECT_EQ(channels, 3);
    EXPECT_EQ(std::memcmp(decoded, image.rgb.data(), image.rgb.size()), 0) << "PNG is lossless";
    stbi_image_free(decoded);

    // Nothing but the picture in the folder: the temporary file was renamed.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(SliceImage, WritePngReportsBadImagesAndFolders) {
    const fs::path dir = testmesh::tempDir("slice-png-bad");
    bake::Image image;
    image.width = 4;
    image.height = 3;
    image.rgb.assign(4 * 3 * 3, 200);
    auto missing = format::writePng(dir / "no-such-folder" / "a.png", image);
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, ErrorCode::Io);

    image.rgb.pop_back();
    auto malformed = format::writePng(dir / "b.png", image);
    ASSERT_FALSE(malformed);
    EXPECT_EQ(malformed.error().code, ErrorCode::InvalidArgument);
    EXPECT_TRUE(fs::is_empty(dir));
}

// Not a check but a picture to look at: a torus cut across its ring, to eyeball the colours.
TEST(SliceImage, WritesATorusPictureForInspection) {
    const fs::path dir = testmesh::tempDir("slice-torus");
    const auto torus =
        testmesh::assetFromSdf({61, 61, 25}, {-1.5, -1.5, -0.6}, 0.05, [](const glm::dvec3& p) {
            return testmesh::torusSdf(p, {0.0, 0.0, 0.0}, 1.0, 0.35);
        });
    for (const char* spec : {"z=0.5", "y=0.5"}) {
        auto slice = bake::parseSlice(spec);
        ASSERT_TRUE(slice);
        const std::string name = std::string("torus_") + spec[0] + ".png";
        ASSERT_TRUE(format::writePng(dir / name, bake::renderSlice(torus, *slice)));
    }
}
