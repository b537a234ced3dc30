// Colliders given by a shape instead of a bake: a sphere, a box or a capsule, their distance
// field computed in closed form on a dense grid, with their exact mass properties.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"

namespace sluice::format {

/// Most samples a shape's grid may have (64 MiB of floats).
inline constexpr std::uint64_t kMaxShapeSamples = 1ull << 24;

/// Grid points a shape's field takes beyond the shape on every side, as a bake pads its mesh.
inline constexpr double kShapePaddingVoxels = 3.0;

/// The signed distance from local point p to the shape's surface [m], negative inside: exact
/// for each kind (a capsule's axis is local y, everything is centred on the origin).
double shapeDistance(const ColliderShape& shape, glm::dvec3 p);

/// The shape's volume, centre of mass (the origin) and inertia about it at unit density, exact.
MassProperties shapeMass(const ColliderShape& shape);

/// The shape as a dense collider asset: shapeDistance sampled on a grid of shape.voxelSize
/// centred on the origin, reaching kShapePaddingVoxels beyond the shape, with its exact mass
/// properties, so every part of Sluice (the solver, bodies, volume maps, the renderer) treats it
/// like a baked collider. InvalidArgument for a size that is not positive and finite (or a
/// capsule shorter than its two caps), SizeOverflow for more than kMaxShapeSamples samples; the
/// detail names the field.
Result<ColliderAsset> shapeCollider(const ColliderShape& shape);

} // namespace sluice::format
