// Volume, centre of mass and inertia of a collider's solid, integrated from its distance field.
#include "sluice/format/asset/MassProperties.h"

#include <cmath>
#include <numbers>

#include <glm/matrix.hpp>

namespace sluice::format {

namespace {

// Smoothed Heaviside of -phi (1 inside, 0 outside) over a band of eps each side of the
// surface (Osher & Fedkiw 2003, eq. 1.22): the share of a grid point's cell that is solid, to
// second order where the surface is smooth on the scale of the band.
double insideShare(double phi, double eps) {
    const double x = -phi;
    if (x <= -eps)
        return 0.0;
    if (x >= eps)
        return 1.0;
    return 0.5 + x / (2.0 * eps) + std::sin(std::numbers::pi * x / eps) / (2.0 * std::numbers::pi);
}

} // namespace

Result<MassProperties> massPropertiesFromField(const ColliderAsset& asset) {
    const ColliderMeta& m = asset.meta;
    if (asset.sparse()) // its inside is tiles, not samples: the sums below would miss them
        return fail(ErrorCode::Unsupported,
                    m.sourceFile + " is a sparse collider without the mass properties of a "
                                   "closed mesh; re-bake it from its closed mesh, or bake it "
                                   "dense, to use it as a dynamic body");
    const double h = m.voxelSize;
    const double eps = 1.5 * h;
    const double cell = h * h * h;
    // Sums about the grid origin (small coordinates keep the second moments accurate), then
    // moved to the centre of mass.
    double volume = 0.0;
    glm::dvec3 first(0.0);
    glm::dmat3 second(0.0); // sum of H r r^T
    bool deepInside = false;
    for (std::uint32_t k = 0; k < m.dims.z; ++k)
        for (std::uint32_t j = 0; j < m.dims.y; ++j)
            for (std::uint32_t i = 0; i < m.dims.x; ++i) {
                const double phi = asset.distances[asset.index(i, j, k)];
                const double w = insideShare(phi, eps);
                if (w <= 0.0)
                    continue;
                deepInside = deepInside || phi < -eps;
                const glm::dvec3 r = glm::dvec3(i, j, k) * h;
                volume += w;
                first += w * r;
                second += w * glm::outerProduct(r, r);
            }
    if (!deepInside || !(volume > 0.0))
        return fail(ErrorCode::InvalidArgument,
                    "the field encloses no volume (no grid point lies inside the surface band): "
                    "a dynamic body needs a closed mesh");
    MassProperties out;
    out.volume = volume * cell;
    const glm::dvec3 c = first / volume; // about the grid origin
    out.centerOfMass = m.origin + c;
    // Second moment about the centre of mass, then I = tr(S) 1 - S.
    const glm::dmat3 s = (second / volume - glm::outerProduct(c, c)) * out.volume;
    const double trace = s[0][0] + s[1][1] + s[2][2];
    out.inertia = trace * glm::dmat3(1.0) - s;
    return out;
}

} // namespace sluice::format
