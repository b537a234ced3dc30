// Dynamic bodies at scene start: mass properties, contact points and the GPU records
// (docs/bodies.md).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "shared/Bodies.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"
#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::rt {

/// Every dynamic collider of a scene, ready for the GPU.
struct BodySetup {
    std::vector<shared::GpuBody> records; ///< one per dynamic collider, in scene order
    std::vector<glm::vec4> samples; ///< contact points, body-local [asset units]; w: area [units^2]
    std::vector<std::uint32_t> bodyOfCollider; ///< body index per collider, or kNoBody
    std::vector<double> volumes;               ///< each body's volume [m^3]
    std::vector<bool> fromMesh; ///< mass properties from the mesh (true) or the field (false)
};

/// Mass properties (the asset's mesh integrals when it has them, else the field's), contact
/// points and initial state of every dynamic collider. Errors name the scene file and the
/// collider's JSON path: a body of an open mesh, or one whose field holds no volume, is
/// InvalidArgument.
Result<BodySetup> setUpBodies(const format::Scene& scene,
                              const std::vector<format::ColliderAsset>& assets,
                              const PbfConstants& k);

/// setUpBodies' checks without its contact points: every dynamic collider has a volume and a
/// mass and inertia a float can invert. Errors as setUpBodies'.
Result<void> checkBodies(const format::Scene& scene,
                         const std::vector<format::ColliderAsset>& assets);

/// Density of the dynamic collider `c` [kg/m^3]: the scene's, or its mass over the volume
/// the body's mass properties give at the collider's scale. Errors as checkBodies'.
Result<double> bodyDensity(const format::Scene& scene, std::size_t c,
                           const format::ColliderAsset& asset);

/// Points on the zero level set of `asset`, about `gap` apart [asset units], in grid order:
/// grid points near the surface moved onto it along the gradient, one per gap-sized cell. At
/// most kMaxBodySamples (the gap grows until they fit). `w` is the surface area a point stands
/// for [asset units^2]: a plane of unit normal n crosses gap-sized cells at (|n_x| + |n_y| +
/// |n_z|) per gap^2 of its area, so gap^2 / |n|_1.
std::vector<glm::vec4> surfacePoints(const format::ColliderAsset& asset, double gap);

/// The contact points of a body of `asset` placed at `scale`: surfacePoints about one particle
/// spacing apart in the world (2 k.radius), at most one per voxel.
std::vector<glm::vec4> bodyContactPoints(const format::ColliderAsset& asset, double scale,
                                         const PbfConstants& k);

/// Removes the particles whose centre lies inside a dynamic body at its start pose; returns
/// how many.
std::uint32_t removeParticlesInBodies(const format::Scene& scene,
                                      const std::vector<format::ColliderAsset>& assets,
                                      std::vector<ParticleState>& particles);

/// World pose of a body's asset frame from its centre of mass and orientation.
ColliderPose bodyPose(const shared::GpuBody& body);

} // namespace sluice::rt
