// Sphere, box and capsule colliders: their closed-form distance sampled on a dense grid, and
// their exact volume and inertia.
#include "sluice/format/asset/ShapeCollider.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include "support/Json.h"

namespace sluice::format {

namespace {

using detail::formatNumber; // numbers in messages as the scene reader writes them
constexpr double kPi = std::numbers::pi;

// Half the length of a capsule's axis segment, between its caps' centres [m].
double capsuleHalfAxis(const ColliderShape& s) {
    return 0.5 * double(s.height) - double(s.radius);
}

// Half the shape's extent along each local axis [m].
glm::dvec3 halfExtent(const ColliderShape& s) {
    switch (s.kind) {
    case ColliderShape::Kind::Sphere:
        return glm::dvec3(s.radius);
    case ColliderShape::Kind::Box:
        return 0.5 * glm::dvec3(s.size);
    case ColliderShape::Kind::Capsule:
        return {s.radius, 0.5 * double(s.height), s.radius};
    }
    return glm::dvec3(0.0);
}

bool positive(double v) {
    return std::isfinite(v) && v > 0.0;
}

// The first field of the shape out of range, as "radius: -1 must be > 0".
std::string sizeProblem(const ColliderShape& s) {
    if (s.kind == ColliderShape::Kind::Box) {
        for (int a = 0; a < 3; ++a)
            if (!positive(s.size[a]))
                return "size: " + formatNumber(s.size[a]) + " must be finite and > 0 on every axis";
    } else if (!positive(s.radius)) {
        return "radius: " + formatNumber(s.radius) + " must be finite and > 0";
    }
    if (s.kind == ColliderShape::Kind::Capsule &&
        !(std::isfinite(s.height) && s.height >= 2.0f * s.radius))
        return "height: " + formatNumber(s.height) + " must be at least 2 * radius (" +
               formatNumber(2.0 * s.radius) + "): it runs tip to tip";
    if (!positive(s.voxelSize))
        return "voxel: " + formatNumber(s.voxelSize) + " must be finite and > 0";
    return {};
}

} // namespace

double shapeDistance(const ColliderShape& s, glm::dvec3 p) {
    switch (s.kind) {
    case ColliderShape::Kind::Sphere:
        return glm::length(p) - double(s.radius);
    case ColliderShape::Kind::Box: {
        const glm::dvec3 q = glm::abs(p) - 0.5 * glm::dvec3(s.size);
        const double inside = std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
        return glm::length(glm::max(q, glm::dvec3(0.0))) + inside;
    }
    case ColliderShape::Kind::Capsule: {
        const double a = capsuleHalfAxis(s);
        const glm::dvec3 axis(0.0, std::clamp(p.y, -a, a), 0.0);
        return glm::length(p - axis) - double(s.radius);
    }
    }
    return 0.0;
}

MassProperties shapeMass(const ColliderShape& s) {
    MassProperties m;
    const double r = s.radius;
    double ix = 0.0, iy = 0.0, iz = 0.0;
    switch (s.kind) {
    case ColliderShape::Kind::Sphere:
        m.volume = 4.0 / 3.0 * kPi * r * r * r;
        ix = iy = iz = 0.4 * m.volume * r * r;
        break;
    case ColliderShape::Kind::Box: {
        const glm::dvec3 e(s.size);
        m.volume = e.x * e.y * e.z;
        ix = m.volume / 12.0 * (e.y * e.y + e.z * e.z);
        iy = m.volume / 12.0 * (e.x * e.x + e.z * e.z);
        iz = m.volume / 12.0 * (e.x * e.x + e.y * e.y);
        break;
    }
    case ColliderShape::Kind::Capsule: {
        // A cylinder of length 2a and the two half balls at its ends; each half ball's centre
        // of mass lies 3r/8 beyond the cylinder's face (the parallel-axis terms).
        const double a = capsuleHalfAxis(s);
        const double cylinder = kPi * r * r * 2.0 * a;
        const double ball = 4.0 / 3.0 * kPi * r * r * r;
        m.volume = cylinder + ball;
        iy = 0.5 * cylinder * r * r + 0.4 * ball * r * r;
        ix = iz =
            cylinder * (a * a / 3.0 + r * r / 4.0) + ball * (0.4 * r * r + a * a + 0.75 * a * r);
        break;
    }
    }
    m.centerOfMass = glm::dvec3(0.0);
    m.inertia = glm::dmat3(0.0);
    m.inertia[0][0] = ix;
    m.inertia[1][1] = iy;
    m.inertia[2][2] = iz;
    return m;
}

Result<ColliderAsset> shapeCollider(const ColliderShape& shape) {
    const char* kind = shapeName(shape.kind);
    if (std::string problem = sizeProblem(shape); !problem.empty())
        return fail(ErrorCode::InvalidArgument, std::string(kind) + "." + problem);
    const double voxel = shape.voxelSize;
    const glm::dvec3 reach = halfExtent(shape) + kShapePaddingVoxels * voxel;
    glm::dvec3 cells = glm::ceil(2.0 * reach / voxel);
    const double samples = (cells.x + 1.0) * (cells.y + 1.0) * (cells.z + 1.0);
    if (!(samples <= double(kMaxShapeSamples)))
        return fail(ErrorCode::SizeOverflow,
                    std::string(kind) + ".voxel: " + formatNumber(voxel) + " m gives " + formatNumber(samples) +
                        " samples, more than the limit " + std::to_string(kMaxShapeSamples) +
                        "; give a larger voxel");
    ColliderAsset asset;
    ColliderMeta& meta = asset.meta;
    meta.dims = glm::uvec3(cells) + 1u;
    meta.voxelSize = voxel;
    meta.origin = -0.5 * cells * voxel; // centred on the shape
    meta.sourceFile = kind;
    meta.bake.backend = "shape";
    meta.bake.signUsed = SignMethod::Level;
    meta.toolVersion = "sluice shape";
    meta.mesh.closed = true;
    meta.meshMass = shapeMass(shape);
    asset.distances.resize(std::size_t(samples));
    std::size_t i = 0;
    for (std::uint32_t z = 0; z < meta.dims.z; ++z)
        for (std::uint32_t y = 0; y < meta.dims.y; ++y)
            for (std::uint32_t x = 0; x < meta.dims.x; ++x)
                asset.distances[i++] =
                    float(shapeDistance(shape, meta.origin + glm::dvec3(x, y, z) * voxel));
    return asset;
}

} // namespace sluice::format
