// Slice pictures of a collider: distance colour map with the zero contour, beside the gradient.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Image.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

enum class Axis { X = 0, Y = 1, Z = 2 };

struct SliceSpec {
    Axis axis = Axis::Z;
    double fraction = 0.5; ///< position along the axis in [0, 1] of the grid extent
};

/// Parses "x=0.5" / "y=0.25" / "z=1". Errors: InvalidArgument.
Result<SliceSpec> parseSlice(const std::string& text);

/// Slice pictures are format::Image (8-bit RGB, top row first), written with format::writePng.
using format::Image;

/// Where things are in a renderSlice picture. Both halves show the same window onto the slice
/// plane: columns run along `uAxis` (left to right), rows along `vAxis` (bottom to top). Pixel
/// (px, py) of a half shows grid coordinates u = px / pixelsPerVoxel and
/// v = (height - 1 - py) / pixelsPerVoxel [voxels], so the corner pixels sit on grid points.
/// Under both halves, rows height .. height + legendHeight - 1 hold the legend: the axis names
/// and slice position, a colour bar of the distance map with its range, and the gradient's
/// colour key.
struct SliceLayout {
    Axis uAxis = Axis::X;        ///< world axis along the columns
    Axis vAxis = Axis::Y;        ///< world axis along the rows (pointing up)
    int halfWidth = 0;           ///< [px] width of each half
    int height = 0;              ///< [px] of the field, above the legend
    int legendHeight = 0;        ///< [px] of the legend strip under the field
    int gap = 0;                 ///< [px] between the halves (right half starts at halfWidth + gap)
    double pixelsPerVoxel = 0.0; ///< [px per voxel]; an integer when the grid is under 512 voxels
    double planeIndex = 0.0;     ///< [voxels] grid coordinate of the slice along its axis
};

/// The layout renderSlice uses for this grid: x slices show (y, z), y slices (x, z), z slices
/// (x, y). The longer side is at least 512 px (at most 2048 px for grids over 2048 voxels).
/// Precondition (asserted): dims >= 2 on every axis.
SliceLayout sliceLayout(const format::ColliderMeta& meta, const SliceSpec& slice);

/// Renders the slice (trilinear between grid planes): left half the signed distance as a
/// diverging colour map (blue inside, red outside, white at zero, with a dark zero contour and
/// faint iso-lines every few voxels), right half the normalized gradient as RGB (like Fig. 4 of
/// the Smeton 2020 paper, whose bottom panel maps the normal's (x, y, z) to (r, g, b)).
/// A legend strip under the halves names the axes ("ACROSS X, UP Y, AT Z = 0.5") and shows the
/// colour map as a bar from the most negative to the most positive distance [world units].
/// Image size and pixel positions as sliceLayout says (the image is height + legendHeight tall).
/// Precondition (asserted): as SdfSampler's (a dense or a validated sparse asset).
Image renderSlice(const format::ColliderAsset& asset, const SliceSpec& slice);

} // namespace sluice::bake
