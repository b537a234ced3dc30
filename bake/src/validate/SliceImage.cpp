// Slice pictures of a collider: distance colour map with the zero contour, beside the gradient.
#include "sluice/bake/validate/SliceImage.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <system_error>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sluice/format/asset/SdfSampler.h"

namespace sluice::bake {
namespace {

constexpr int kMinLongSide = 512;  // [px]
constexpr int kMaxLongSide = 2048; // [px]
constexpr int kGap = 8;            // [px] between the halves

const glm::dvec3 kWhite{1.0, 1.0, 1.0};
// Ends of the diverging map (close to ColorBrewer RdBu's): blue inside, red outside.
const glm::dvec3 kInside{0.08, 0.24, 0.70};
const glm::dvec3 kOutside{0.75, 0.08, 0.08};
const glm::dvec3 kContour{0.05, 0.05, 0.05};
const glm::dvec3 kGapColour{0.2, 0.2, 0.2};
const glm::dvec3 kLegendBackground{0.96, 0.96, 0.96};
const glm::dvec3 kText{0.1, 0.1, 0.1};

// The legend strip [px]: a line of text, the colour bar, a line of labels, with margins.
constexpr int kFontScale = 2;                 // [px per font pixel]
constexpr int kGlyphAdvance = 4 * kFontScale; // 3 columns and a space
constexpr int kLineHeight = 5 * kFontScale;   // 5 rows
constexpr int kMargin = 6;
constexpr int kBarHeight = 12;
constexpr int kLegendHeight =
    kMargin + kLineHeight + kMargin + kBarHeight + 4 + kLineHeight + kMargin;

// A 3 x 5 pixel font for the legend: five rows of three bits each, top row first, the high bit
// on the left. Letters are upper case; characters without a glyph are drawn as spaces.
struct Glyph {
    char c;
    std::uint8_t rows[5];
};
constexpr Glyph kFont[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}},
    {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}},
    {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}}, {'A', {2, 5, 7, 5, 5}}, {'B', {6, 5, 6, 5, 6}},
    {'C', {3, 4, 4, 4, 3}}, {'D', {6, 5, 5, 5, 6}}, {'E', {7, 4, 6, 4, 7}}, {'F', {7, 4, 6, 4, 4}},
    {'G', {3, 4, 5, 5, 3}}, {'H', {5, 5, 7, 5, 5}}, {'I', {7, 2, 2, 2, 7}}, {'J', {1, 1, 1, 5, 2}},
    {'K', {5, 5, 6, 5, 5}}, {'L', {4, 4, 4, 4, 7}}, {'M', {5, 7, 7, 5, 5}}, {'N', {6, 5, 5, 5, 5}},
    {'O', {2, 5, 5, 5, 2}}, {'P', {6, 5, 6, 4, 4}}, {'Q', {2, 5, 5, 6, 3}}, {'R', {6, 5, 6, 5, 5}},
    {'S', {3, 4, 2, 1, 6}}, {'T', {7, 2, 2, 2, 2}}, {'U', {5, 5, 5, 5, 7}}, {'V', {5, 5, 5, 5, 2}},
    {'W', {5, 5, 7, 7, 5}}, {'X', {5, 5, 2, 5, 5}}, {'Y', {5, 5, 2, 2, 2}}, {'Z', {7, 1, 2, 4, 7}},
    {'-', {0, 0, 7, 0, 0}}, {'+', {0, 2, 7, 2, 0}}, {'.', {0, 0, 0, 0, 2}}, {',', {0, 0, 0, 2, 4}},
    {':', {0, 2, 0, 2, 0}}, {'=', {0, 7, 0, 7, 0}}, {'(', {1, 2, 2, 2, 1}}, {')', {4, 2, 2, 2, 4}},
    {'/', {1, 1, 2, 4, 4}},
};

std::uint8_t toByte(double c) {
    return std::uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0));
}

void putPixel(Image& image, int x, int y, const glm::dvec3& c) {
    const std::size_t at = (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 3;
    image.rgb[at + 0] = toByte(c.x);
    image.rgb[at + 1] = toByte(c.y);
    image.rgb[at + 2] = toByte(c.z);
}

// Iso-line spacing [voxels]: 1, 2 or 5 times a power of ten, about eight lines across `range`.
double isoSpacingVoxels(double rangeVoxels) {
    const double raw = std::max(rangeVoxels / 8.0, 1.0);
    const double decade = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0})
        if (m * decade >= raw)
            return m * decade;
    return 10.0 * decade;
}

// How strongly a line at distance `px` [px] from the pixel centre covers it: fully within a
// quarter pixel, fading out over one pixel (a cheap antialiased line about 2 px wide).
double lineCoverage(double px) {
    return std::clamp(1.25 - px, 0.0, 1.0);
}

// The colour of distance `d` on the left half, before contour lines: white at zero, to the
// inside or outside colour at the end of its range.
glm::dvec3 distanceColour(double d, double rangeInside, double rangeOutside) {
    // A gentle power curve gives the near-surface band more of the ramp than the far field.
    const double t =
        std::pow(std::min(std::abs(d) / (d < 0 ? rangeInside : rangeOutside), 1.0), 0.7);
    return glm::mix(kWhite, d < 0 ? kInside : kOutside, t);
}

const Glyph* findGlyph(char c) {
    const char upper = char(std::toupper(static_cast<unsigned char>(c)));
    for (const Glyph& glyph : kFont)
        if (glyph.c == upper)
            return &glyph;
    return nullptr;
}

// [px] width of `text` in the legend font.
int textWidth(std::string_view text) {
    return int(text.size()) * kGlyphAdvance - kFontScale;
}

// Draws `text` with its top-left corner at (x, y), clipped to columns [x, clipRight).
void drawText(Image& image, int x, int y, std::string_view text, int clipRight) {
    for (std::size_t i = 0; i < text.size(); ++i, x += kGlyphAdvance) {
        const Glyph* glyph = findGlyph(text[i]);
        if (glyph == nullptr)
            continue;
        for (int row = 0; row < 5 * kFontScale; ++row)
            for (int col = 0; col < 3 * kFontScale; ++col) {
                const int px = x + col, py = y + row;
                const bool on = (glyph->rows[row / kFontScale] >> (2 - col / kFontScale)) & 1;
                if (on && px >= 0 && px < std::min(clipRight, int(image.width)) &&
                    py < int(image.height))
                    putPixel(image, px, py, kText);
            }
    }
}

// "0.25", "-1.2e+03": three significant digits.
std::string legendNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

const char* axisName(Axis axis) {
    return axis == Axis::X ? "X" : axis == Axis::Y ? "Y" : "Z";
}

// The legend strip under the halves (SliceLayout): axis names and the colour bar under the
// distance half, what the colours mean under the gradient half.
void drawLegend(Image& image, const SliceLayout& layout, const SliceSpec& slice, double rangeInside,
                double rangeOutside) {
    for (int py = layout.height; py < int(image.height); ++py)
        for (int px = 0; px < int(image.width); ++px)
            putPixel(image, px, py, kLegendBackground);
    const int line1 = layout.height + kMargin;
    const int bar = line1 + kLineHeight + kMargin;
    const int line2 = bar + kBarHeight + 4;
    const int left = kMargin, right = layout.halfWidth - kMargin; // [px] of the distance half
    drawText(image, left, line1,
             std::string("ACROSS ") + axisName(layout.uAxis) + ", UP " + axisName(layout.vAxis) +
                 ", AT " + axisName(slice.axis) + " = " + legendNumber(slice.fraction),
             layout.halfWidth);

    // The bar runs from -rangeInside (left) through 0 to +rangeOutside (right), zero in the
    // middle, in the colours of the field above it.
    const int barWidth = right - left;
    if (barWidth >= 2) {
        const int zero = left + barWidth / 2;
        for (int px = left; px < right; ++px) {
            const double d = px < zero ? -rangeInside * double(zero - px) / (zero - left)
                                       : rangeOutside * double(px - zero) / (right - 1 - zero);
            const glm::dvec3 c =
                px == zero ? kContour : distanceColour(d, rangeInside, rangeOutside);
            for (int py = bar; py < bar + kBarHeight; ++py)
                putPixel(image, px, py, c);
        }
        const std::string lo = legendNumber(-rangeInside), hi = legendNumber(rangeOutside);
        drawText(image, left, line2, lo, zero - kGlyphAdvance);
        drawText(image, zero - kFontScale, line2, "0", layout.halfWidth);
        drawText(image, right - textWidth(hi), line2, hi, layout.halfWidth);
    }

    const int gradientLeft = layout.halfWidth + layout.gap + kMargin;
    drawText(image, gradientLeft, line1, "GRADIENT: R, G, B = X, Y, Z", int(image.width));
    drawText(image, gradientLeft, bar, "LEFT: DISTANCE IN WORLD UNITS,", int(image.width));
    drawText(image, gradientLeft, line2, "BLUE INSIDE, RED OUTSIDE", int(image.width));
}

/// phi and its gradient at every pixel of one half of a slice picture, row after row.
struct SliceSamples {
    std::vector<float> phi;       ///< [world units]
    std::vector<glm::dvec3> grad; ///< [1]
};

/// Samples phi and its gradient at every pixel first: the colour ranges need the whole slice.
SliceSamples sampleSlice(const format::ColliderAsset& asset, const SliceSpec& slice,
                         const SliceLayout& layout) {
    const format::ColliderMeta& meta = asset.meta;
    const format::SdfSampler sampler(asset);
    const int u = int(layout.uAxis), v = int(layout.vAxis), w = int(slice.axis);
    const double h = meta.voxelSize; // central-difference step [world units]
    const std::size_t pixels = std::size_t(layout.halfWidth) * std::size_t(layout.height);
    SliceSamples samples{std::vector<float>(pixels), std::vector<glm::dvec3>(pixels)};
    tbb::parallel_for(tbb::blocked_range<int>(0, layout.height), [&](const auto& rows) {
        for (int py = rows.begin(); py != rows.end(); ++py)
            for (int px = 0; px < layout.halfWidth; ++px) {
                glm::dvec3 index(0.0);
                index[u] = px / layout.pixelsPerVoxel;
                index[v] = (layout.height - 1 - py) / layout.pixelsPerVoxel;
                index[w] = layout.planeIndex;
                const glm::dvec3 p = meta.origin + index * meta.voxelSize;
                const std::size_t at =
                    std::size_t(py) * std::size_t(layout.halfWidth) + std::size_t(px);
                samples.phi[at] = sampler.value(p);
                // A one-voxel central difference of the trilinear field is the trilinear
                // interpolant of the grid's central differences: smooth across cell faces,
                // unlike the analytic gradient of the interpolant.
                glm::dvec3 g;
                for (int a = 0; a < 3; ++a) {
                    glm::dvec3 e(0.0);
                    e[a] = h;
                    g[a] = (double(sampler.value(p + e)) - double(sampler.value(p - e))) / (2 * h);
                }
                samples.grad[at] = g;
            }
    });
    return samples;
}

/// [world units] The ends of the colour map and the spacing of the iso-lines.
struct ColourRanges {
    double inside = 0.0;  ///< the distance of the deepest blue
    double outside = 0.0; ///< the distance of the deepest red
    double spacing = 0.0; ///< between iso-lines
};

/// The ranges of the slice's distances: inside and outside are normalized separately, so both
/// ends of the map are used.
ColourRanges colourRanges(const std::vector<float>& phi, double voxelSize) {
    ColourRanges ranges{1e-3 * voxelSize, 1e-3 * voxelSize, 0.0};
    for (float d : phi) {
        if (d < 0)
            ranges.inside = std::max(ranges.inside, -double(d));
        else
            ranges.outside = std::max(ranges.outside, double(d));
    }
    ranges.spacing =
        isoSpacingVoxels(std::max(ranges.inside, ranges.outside) / voxelSize) * voxelSize;
    return ranges;
}

/// The colour of the distance half at a pixel of distance `d` and gradient `g`: the colour map
/// with iso-lines and the zero contour.
glm::dvec3 distancePixel(double d, const glm::dvec3& g, int u, int v, const ColourRanges& ranges,
                         double worldPerPixel) {
    glm::dvec3 c = distanceColour(d, ranges.inside, ranges.outside);
    // Lines drawn by their distance in pixels, |phi - level| / |grad phi in plane|, so they
    // keep their width however steep the field is. [world units / px]
    const double slope = std::max(std::hypot(g[u], g[v]), 0.05) * worldPerPixel;
    const double level = std::round(d / ranges.spacing) * ranges.spacing;
    if (level != 0.0)
        c *= 1.0 - 0.22 * lineCoverage(std::abs(d - level) / slope);
    return glm::mix(c, kContour, lineCoverage(std::abs(d) / slope));
}

/// Paints both halves above the legend: the distance on the left, the gap, and the normalized
/// gradient, (x, y, z) -> (r, g, b) as in Smeton 2020, on the right.
void paintHalves(Image& image, const SliceLayout& layout, const SliceSamples& samples,
                 const ColourRanges& ranges, double voxelSize) {
    const int u = int(layout.uAxis), v = int(layout.vAxis);
    const double worldPerPixel = voxelSize / layout.pixelsPerVoxel;
    tbb::parallel_for(tbb::blocked_range<int>(0, layout.height), [&](const auto& rows) {
        for (int py = rows.begin(); py != rows.end(); ++py) {
            for (int px = 0; px < layout.halfWidth; ++px) {
                const std::size_t at =
                    std::size_t(py) * std::size_t(layout.halfWidth) + std::size_t(px);
                const glm::dvec3& g = samples.grad[at];
                putPixel(image, px, py,
                         distancePixel(samples.phi[at], g, u, v, ranges, worldPerPixel));
                const double length = glm::length(g);
                const glm::dvec3 n = length > 1e-12 ? g / length : glm::dvec3(0.0);
                putPixel(image, layout.halfWidth + layout.gap + px, py, 0.5 + 0.5 * n);
            }
            for (int px = 0; px < layout.gap; ++px)
                putPixel(image, layout.halfWidth + px, py, kGapColour);
        }
    });
}

} // namespace

Result<SliceSpec> parseSlice(const std::string& text) {
    auto bad = [&](const std::string& why) {
        return fail(ErrorCode::InvalidArgument,
                    "--slice '" + text + "': " + why +
                        "; expected x|y|z=FRACTION with FRACTION in [0, 1], e.g. z=0.5");
    };
    if (text.size() < 2 || text[1] != '=')
        return bad("no axis=fraction");
    SliceSpec slice;
    switch (text[0]) {
    case 'x':
    case 'X':
        slice.axis = Axis::X;
        break;
    case 'y':
    case 'Y':
        slice.axis = Axis::Y;
        break;
    case 'z':
    case 'Z':
        slice.axis = Axis::Z;
        break;
    default:
        return bad("unknown axis '" + text.substr(0, 1) + "'");
    }
    const char* first = text.data() + 2;
    const char* last = text.data() + text.size();
    if (first == last)
        return bad("missing fraction");
    double value = 0.0;
    const auto [end, ec] = std::from_chars(first, last, value);
    if (ec != std::errc() || end != last)
        return bad("fraction is not a number");
    if (!std::isfinite(value))
        return bad("fraction is not finite");
    if (value < 0.0 || value > 1.0)
        return bad("fraction outside [0, 1]");
    slice.fraction = value;
    return slice;
}

SliceLayout sliceLayout(const format::ColliderMeta& meta, const SliceSpec& slice) {
    SLUICE_ASSERT(meta.dims.x >= 2 && meta.dims.y >= 2 && meta.dims.z >= 2,
                  "sliceLayout needs at least 2 grid points per axis");
    SliceLayout layout;
    const int w = int(slice.axis);
    layout.uAxis = slice.axis == Axis::X ? Axis::Y : Axis::X;
    layout.vAxis = slice.axis == Axis::Z ? Axis::Y : Axis::Z;
    const double extentU = meta.dims[int(layout.uAxis)] - 1.0; // [voxels]
    const double extentV = meta.dims[int(layout.vAxis)] - 1.0;
    const double longest = std::max(extentU, extentV);
    // Whole pixels per voxel while upscaling keeps grid points on pixel centres.
    if (longest < kMinLongSide - 1)
        layout.pixelsPerVoxel = std::ceil((kMinLongSide - 1) / longest);
    else if (longest > kMaxLongSide - 1)
        layout.pixelsPerVoxel = (kMaxLongSide - 1) / longest;
    else
        layout.pixelsPerVoxel = 1.0;
    layout.halfWidth = int(std::lround(extentU * layout.pixelsPerVoxel)) + 1;
    layout.height = int(std::lround(extentV * layout.pixelsPerVoxel)) + 1;
    layout.gap = kGap;
    layout.legendHeight = kLegendHeight;
    layout.planeIndex = std::clamp(slice.fraction, 0.0, 1.0) * (meta.dims[w] - 1.0);
    return layout;
}

Image renderSlice(const format::ColliderAsset& asset, const SliceSpec& slice) {
    const SliceLayout layout = sliceLayout(asset.meta, slice);
    const SliceSamples samples = sampleSlice(asset, slice, layout);
    const ColourRanges ranges = colourRanges(samples.phi, asset.meta.voxelSize);
    Image image;
    image.width = std::uint32_t(2 * layout.halfWidth + layout.gap);
    image.height = std::uint32_t(layout.height + layout.legendHeight);
    image.rgb.assign(std::size_t(image.width) * std::size_t(image.height) * 3, 0);
    paintHalves(image, layout, samples, ranges, asset.meta.voxelSize);
    drawLegend(image, layout, slice, ranges.inside, ranges.outside);
    return image;
}

} // namespace sluice::bake
