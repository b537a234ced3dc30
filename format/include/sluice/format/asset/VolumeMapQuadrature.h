// The volume map's quadrature on the CPU (docs/pbf.md, "Volume maps"), as the GPU pass
// (shaders/colliders/pbf_volume_map.comp) computes it: `validate`'s brute-force check and the
// CPU reference of the solver both integrate with it, at their own lattices.
#pragma once

#include <algorithm>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace sluice::format {

/// At a point whose phi is `phi` and unit normal `n`: over the cells of a lattice `d` wide,
/// `steps` cells each way, inside the poly6 support of radius `support`, the solid's share (each
/// cell's volume fraction from phi at its centre, phiAt(offset from the point); a cell where
/// phiAt gives nullopt counts for neither) less the flat boundary's at phi along n, both
/// weighted by poly6 and over the weights of every cell of the support.
template <typename PhiAt>
double volumeMapQuadrature(double support, double d, int steps, double phi, glm::dvec3 n,
                           PhiAt&& phiAt) {
    double weights = 0.0, solid = 0.0, plane = 0.0;
    for (int k = -steps; k <= steps; ++k)
        for (int j = -steps; j <= steps; ++j)
            for (int i = -steps; i <= steps; ++i) {
                const glm::dvec3 o = glm::dvec3(i, j, k) * d;
                const double a = 1.0 - glm::dot(o, o) / (support * support);
                if (!(a > 0.0))
                    continue;
                const double w = a * a * a;
                weights += w;
                const std::optional<double> phiHere = phiAt(o);
                if (!phiHere)
                    continue;
                solid += w * std::clamp(0.5 - *phiHere / d, 0.0, 1.0);
                plane += w * std::clamp(0.5 - (phi + glm::dot(n, o)) / d, 0.0, 1.0);
            }
    return (solid - plane) / weights;
}

} // namespace sluice::format
