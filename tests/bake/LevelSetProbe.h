// Probing an OpenVDB float level set in the bake tests: its value at a world point and where it
// first turns positive along a ray.
#pragma once

#include <cmath>

#include <glm/vec3.hpp>

#include "interop/VdbHeaders.h"

SLUICE_VDB_WARNINGS_OFF
#include <openvdb/tools/Interpolation.h>
SLUICE_VDB_WARNINGS_ON

namespace sluice::testlevelset {

/// The grid's value at world point p, trilinear.
inline double sample(const openvdb::FloatGrid& grid, const glm::dvec3& p) {
    return openvdb::tools::BoxSampler::sample(grid.tree(),
                                              grid.worldToIndex(openvdb::Vec3R(p.x, p.y, p.z)));
}

/// [world units] Where the level set first turns positive walking from `from` along `dir` (a
/// unit vector) up to `maxDistance`, linearly interpolated between samples a hundredth of
/// `voxel` apart; NAN when it does not.
inline double zeroCrossing(const openvdb::FloatGrid& grid, const glm::dvec3& from,
                           const glm::dvec3& dir, double maxDistance, double voxel) {
    const double step = voxel / 100;
    double previous = sample(grid, from);
    for (double t = step; t <= maxDistance; t += step) {
        const double value = sample(grid, from + dir * t);
        if (previous < 0.0 && value >= 0.0)
            return t - step * value / (value - previous);
        previous = value;
    }
    return NAN;
}

} // namespace sluice::testlevelset
