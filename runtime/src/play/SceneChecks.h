// Scene sanity checks sluice-play runs on the CPU before the first step: fluid outside the
// domain box, fluid spawned in or against a collider, colliders far from the scene's scale.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"

namespace sluice::rt {

/// One thing about a run that is probably a mistake but not an error (--strict makes it one).
struct PlayWarning {
    std::string kind; ///< short stable name: "outside-domain", "fluid-in-collider",
                      ///< "collider-scale", "body-density", "body-outside-domain",
                      ///< "screenshot-after-end", "unused-option", "odd-iterations",
                      ///< "removed-boundary-model"
    std::string text; ///< the whole message: where (scene file and JSON path), what, what to do
};

/// Colliders larger than this many particle spacings are reported as off the scene's scale
/// (a mesh in centimetres in a scene in metres).
inline constexpr double kColliderMaxSpacings = 1000.0;

/// Colliders smaller than this many particle spacings are reported as off the scene's scale:
/// particles larger than the collider pass it as a point (a mesh in metres scaled as if it were
/// in centimetres).
inline constexpr double kColliderMinSpacings = 1.0;

/// Dynamic bodies denser or lighter than real materials are reported (body-density) [kg/m^3]:
/// a density typed in g/cm^3, or a mass in grams, gives a body the solver may lose.
inline constexpr double kBodyDensityMin = 10.0;
inline constexpr double kBodyDensityMax = 25000.0;

/// World size of a collider as the scene places it [m]: the box of the asset's grid points
/// inside the surface (phi <= 0) widened by one voxel, times the collider's scale. Where no
/// point is inside (an open or thinner-than-a-voxel mesh), the grid box less the bake padding.
glm::dvec3 colliderWorldSize(const format::SceneCollider& collider,
                             const format::ColliderAsset& asset);

/// Warnings about `scene` with its loaded `colliders` (one per scene collider, in order):
///  - outside-domain: a fluid block or an emitter's first disc has particles outside the
///    domain box less a particle radius (where the solver would clamp them);
///  - fluid-in-collider: particles of a block, or of an emitter's first disc, start inside or
///    within a particle radius of a collider placed at its start-time pose;
///  - collider-scale: a collider's largest side is more than kColliderMaxSpacings or less than
///    kColliderMinSpacings particle spacings;
///  - body-density: a dynamic body's density (given, or its mass over its volume) is outside
///    kBodyDensityMin to kBodyDensityMax;
///  - body-outside-domain: a dynamic body's inside grid points at its start pose are partly or
///    all outside the domain box;
///  - odd-iterations: every substep runs the same odd number of solver iterations;
///  - removed-boundary-model: the scene names "boundary": "bodies", which was removed.
/// Each text starts with the scene file and the JSON path ("scene.json: fluid[0]: ...").
std::vector<PlayWarning> checkScene(const format::Scene& scene,
                                    const std::vector<format::ColliderAsset>& colliders);

/// "colliders[0] tank.slc 0.8 x 0.43 x 0.5 m" for every collider, for the start-up lines.
std::vector<std::string> describeColliders(const format::Scene& scene,
                                           const std::vector<format::ColliderAsset>& colliders);

/// The line printed on stderr: "sluice-play: warning: TEXT [KIND]".
std::string warningLine(const PlayWarning& warning);

} // namespace sluice::rt
