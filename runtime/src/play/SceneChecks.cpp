// Scene sanity checks: particles of every block and emitter against the domain box and the
// colliders' distance fields, and each collider's size against the particle spacing.
#include "play/SceneChecks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

#include "bodies/BodySetup.h"
#include "sluice/format/asset/GridSamples.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/format/scene/SimulationLimits.h"
#include "sluice/format/support/NumberText.h"
#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::rt {
namespace {

/// Slack on the domain test [spacings]: a block whose first particle sits exactly a radius
/// from the wall (martin-moyce.json) is inside, whatever float rounding says.
constexpr double kDomainSlack = 1e-3;

/// "0.123" with a few significant digits.

std::string vec(const glm::dvec3& v) {
    return "(" + format::significant(v.x, 3) + ", " + format::significant(v.y, 3) + ", " +
           format::significant(v.z, 3) + ")";
}

/// "scene.json: colliders[2] (crate.slc): " for a collider's messages.
std::string colliderWhere(const format::Scene& scene, std::size_t c) {
    return scene.path + ": colliders[" + std::to_string(c) + "] (" +
           format::colliderName(scene.colliders[c]) + "): ";
}

/// A group of starting particles with the JSON path and the time they appear.
struct Spawn {
    std::string where; ///< "fluid[0]" or "emitters[1]"
    std::vector<glm::vec3> points;
    float time = 0.0f; ///< [s] when they appear (colliders are posed at this time)
};

/// The particles of every fluid block and the first disc of every emitter.
std::vector<Spawn> spawns(const format::Scene& scene) {
    std::vector<Spawn> out;
    format::Scene single = scene;
    for (std::size_t b = 0; b < scene.blocks.size(); ++b) {
        single.blocks = {scene.blocks[b]};
        Spawn spawn{"fluid[" + std::to_string(b) + "]", {}, 0.0f};
        for (const ParticleState& p : fillBlocks(single))
            spawn.points.push_back(p.position);
        out.push_back(std::move(spawn));
    }
    for (std::size_t e = 0; e < scene.emitters.size(); ++e) {
        const format::Emitter& emitter = scene.emitters[e];
        Spawn spawn{"emitters[" + std::to_string(e) + "]", {}, emitter.start};
        for (const glm::vec3& offset : emitterDisc(emitter, scene.simulation.spacing))
            spawn.points.push_back(emitter.position + offset);
        out.push_back(std::move(spawn));
    }
    return out;
}

void checkDomain(const format::Scene& scene, const std::vector<Spawn>& groups,
                 std::vector<PlayWarning>& out) {
    if (!scene.domainMin || !scene.domainMax)
        return;
    const double s = scene.simulation.spacing;
    const glm::dvec3 lo = glm::dvec3(*scene.domainMin) + 0.5 * s - kDomainSlack * s;
    const glm::dvec3 hi = glm::dvec3(*scene.domainMax) - 0.5 * s + kDomainSlack * s;
    for (const Spawn& group : groups) {
        std::size_t outside = 0;
        for (const glm::vec3& p : group.points)
            for (int a = 0; a < 3; ++a)
                if (p[a] < lo[a] || p[a] > hi[a]) {
                    ++outside;
                    break;
                }
        if (outside == 0)
            continue;
        out.push_back({"outside-domain",
                       scene.path + ": " + group.where + ": " + std::to_string(outside) + " of " +
                           std::to_string(group.points.size()) +
                           " particles start outside the domain box " + vec(*scene.domainMin) +
                           " to " + vec(*scene.domainMax) +
                           " and would be pushed onto its walls; move it inside \"domain\" or "
                           "enlarge the domain"});
    }
}

void checkColliderOverlap(const format::Scene& scene,
                          const std::vector<format::ColliderAsset>& colliders,
                          const std::vector<Spawn>& groups, std::vector<PlayWarning>& out) {
    const double radius = 0.5 * scene.simulation.spacing;
    for (std::size_t c = 0; c < colliders.size() && c < scene.colliders.size(); ++c) {
        // A dynamic body leaves out the block particles it starts on (docs/bodies.md).
        if (scene.colliders[c].dynamic)
            continue;
        const format::SdfSampler sdf(colliders[c]);
        for (const Spawn& group : groups) {
            const ColliderPose pose = colliderPose(scene.colliders[c], group.time);
            std::size_t inside = 0;
            std::size_t near = 0;
            for (const glm::vec3& p : group.points) {
                const double phi = double(sdf.value(glm::dvec3(pose.toLocal(p)))) * pose.scale;
                inside += phi < 0.0 ? 1 : 0;
                near += phi < radius ? 1 : 0;
            }
            if (near == 0)
                continue;
            out.push_back({"fluid-in-collider",
                           scene.path + ": " + group.where + ": " + std::to_string(near) + " of " +
                               std::to_string(group.points.size()) + " particles start inside (" +
                               std::to_string(inside) + ") or within a particle radius (" +
                               format::significant(radius, 3) + " m) of colliders[" +
                               std::to_string(c) + "] (" +
                               format::colliderName(scene.colliders[c]) +
                               "); the solver will throw them out of it on the first step. Move "
                               "the fluid or the collider apart"});
        }
    }
}

void checkColliderScale(const format::Scene& scene,
                        const std::vector<format::ColliderAsset>& colliders,
                        std::vector<PlayWarning>& out) {
    const double s = scene.simulation.spacing;
    for (std::size_t c = 0; c < colliders.size() && c < scene.colliders.size(); ++c) {
        const glm::dvec3 size = colliderWorldSize(scene.colliders[c], colliders[c]);
        const double side = std::max({size.x, size.y, size.z});
        const std::string where = colliderWhere(scene, c);
        const std::string measured =
            format::significant(size.x, 3) + " x " + format::significant(size.y, 3) + " x " +
            format::significant(size.z, 3) + " m, " + format::significant(side / s, 3) +
            " times the particle spacing (" + format::significant(s, 3) + " m)";
        if (side > kColliderMaxSpacings * s)
            out.push_back({"collider-scale",
                           where + measured + ", more than " +
                               format::significant(kColliderMaxSpacings, 3) +
                               ": was the mesh modelled in centimetres (FBX often is)? Re-bake it "
                               "with `sluice-bake bake --scale 0.01` or set \"scale\" on the "
                               "collider in the scene"});
        else if (side < kColliderMinSpacings * s)
            out.push_back(
                {"collider-scale", where + measured +
                                       ": particles are larger than the collider. Re-bake "
                                       "it with a larger `sluice-bake bake --scale` or "
                                       "set a larger \"scale\" on the collider in the scene"});
    }
}

void checkBodyDensity(const format::Scene& scene,
                      const std::vector<format::ColliderAsset>& colliders,
                      std::vector<PlayWarning>& out) {
    for (std::size_t c = 0; c < colliders.size() && c < scene.colliders.size(); ++c) {
        if (!scene.colliders[c].dynamic)
            continue;
        // A body without a volume or with an unusable mass is an error the solver reports.
        auto density = bodyDensity(scene, c, colliders[c]);
        if (!density || (*density >= kBodyDensityMin && *density <= kBodyDensityMax))
            continue;
        const bool fromMass = scene.colliders[c].dynamic->mass.has_value();
        out.push_back(
            {"body-density", colliderWhere(scene, c) + "a dynamic body of " +
                                 format::significant(*density, 3) + " kg/m^3" +
                                 (fromMass ? " (its mass over its volume)" : "") + ", outside " +
                                 format::significant(kBodyDensityMin, 3) + " to " +
                                 format::significant(kBodyDensityMax, 3) +
                                 " kg/m^3, the range of real materials (air-filled foam to the "
                                 "densest metals): the solver may lose it. Is the \"density\" in "
                                 "kg/m^3 and the \"mass\" in kg?"});
    }
}

void checkBodyDomain(const format::Scene& scene,
                     const std::vector<format::ColliderAsset>& colliders,
                     std::vector<PlayWarning>& out) {
    if (!scene.domainMin || !scene.domainMax)
        return;
    const glm::vec3 lo = *scene.domainMin;
    const glm::vec3 hi = *scene.domainMax;
    for (std::size_t c = 0; c < colliders.size() && c < scene.colliders.size(); ++c) {
        if (!scene.colliders[c].dynamic)
            continue;
        const format::ColliderAsset& asset = colliders[c];
        const ColliderPose pose = colliderPose(scene.colliders[c], 0.0f);
        std::size_t inside = 0;
        std::size_t outside = 0;
        format::forEachStoredSample(asset, [&](glm::uvec3 ijk, float phi) {
            if (phi > 0.0f)
                return;
            const glm::vec3 p = pose.toWorld(glm::vec3(asset.pointPosition(ijk.x, ijk.y, ijk.z)));
            ++inside;
            if (glm::any(glm::lessThan(p, lo)) || glm::any(glm::greaterThan(p, hi)))
                ++outside;
        });
        if (outside == 0)
            continue;
        out.push_back({"body-outside-domain",
                       colliderWhere(scene, c) + "the dynamic body starts " +
                           (outside == inside ? std::string("outside") : "partly outside") +
                           " the domain box " + vec(*scene.domainMin) + " to " +
                           vec(*scene.domainMax) + " (" + std::to_string(outside) + " of its " +
                           std::to_string(inside) +
                           " inside grid points); the walls would throw it in on the first "
                           "step. Move it inside \"domain\" or enlarge the domain"});
    }
}

} // namespace

glm::dvec3 colliderWorldSize(const format::SceneCollider& collider,
                             const format::ColliderAsset& asset) {
    const format::ColliderMeta& m = asset.meta;
    glm::uvec3 lo{std::numeric_limits<std::uint32_t>::max()};
    glm::uvec3 hi{0};
    bool any = false;
    // A sparse asset's inside tiles lie within its band's inside voxels: those bound the solid.
    format::forEachStoredSample(asset, [&](glm::uvec3 ijk, float phi) {
        if (phi <= 0.0f) {
            lo = glm::min(lo, ijk);
            hi = glm::max(hi, ijk);
            any = true;
        }
    });
    glm::dvec3 local;
    if (any) {
        // The surface lies up to a voxel beyond the outermost inside points on each side.
        local = (glm::dvec3(hi - lo) + 1.0) * m.voxelSize;
    } else {
        const glm::dvec3 grid = glm::dvec3(m.dims - 1u) * m.voxelSize;
        local = glm::max(grid - 2.0 * m.bake.padding * m.voxelSize, glm::dvec3(m.voxelSize));
    }
    return local * double(collider.scale);
}

// A solve that always runs the same odd number of iterations leaves water at rest stirring
// (docs/pbf.md, "The early stop's parity": 31 to 130 times the rest motion of the even counts
// beside it). With the early stop on, the count changes from substep to substep: no warning.
void checkIterations(const format::Scene& scene, std::vector<PlayWarning>& out) {
    const format::SimulationParams& p = scene.simulation;
    const bool fixed = p.targetDensityError <= 0.0f || p.minIterations >= p.maxIterations;
    if (!fixed || p.maxIterations % 2 == 0)
        return;
    const std::uint32_t n = p.maxIterations;
    out.push_back(
        {"odd-iterations",
         scene.path + ": simulation: every substep runs " + std::to_string(n) +
             " solver iteration" + (n == 1 ? "" : "s") +
             ", an odd count, which leaves water at rest stirring (docs/pbf.md, \"The "
             "early stop's parity\"); use " +
             (n == 1 ? std::string("2") : std::to_string(n - 1) + " or " + std::to_string(n + 1)) +
             ", or an early stop (\"targetDensityError\" above 0 and "
             "\"minIterations\" below \"maxIterations\")"});
}

// "boundary": "bodies" names the boundary model that was removed: the scene plays with the one
// there is (the format reader accepts the key, so an older scene still plays).
void checkBoundaryModel(const format::Scene& scene, std::vector<PlayWarning>& out) {
    if (scene.namesRemovedBoundaryModel)
        out.push_back(
            {"removed-boundary-model", scene.path + ": " + format::removedBoundaryModelWarning()});
}

std::vector<PlayWarning> checkScene(const format::Scene& scene,
                                    const std::vector<format::ColliderAsset>& colliders) {
    std::vector<PlayWarning> out;
    checkBoundaryModel(scene, out);
    const std::vector<Spawn> groups = spawns(scene);
    checkDomain(scene, groups, out);
    checkColliderOverlap(scene, colliders, groups, out);
    checkColliderScale(scene, colliders, out);
    checkBodyDensity(scene, colliders, out);
    checkBodyDomain(scene, colliders, out);
    checkIterations(scene, out);
    return out;
}

std::vector<std::string> describeColliders(const format::Scene& scene,
                                           const std::vector<format::ColliderAsset>& colliders) {
    std::vector<std::string> lines;
    for (std::size_t c = 0; c < colliders.size() && c < scene.colliders.size(); ++c) {
        const glm::dvec3 size = colliderWorldSize(scene.colliders[c], colliders[c]);
        lines.push_back("colliders[" + std::to_string(c) + "] " +
                        format::colliderName(scene.colliders[c]) + ": " +
                        format::significant(size.x, 3) + " x " + format::significant(size.y, 3) +
                        " x " + format::significant(size.z, 3) + " m (scale " +
                        format::significant(scene.colliders[c].scale, 3) + ")");
    }
    return lines;
}

std::string warningLine(const PlayWarning& warning) {
    return "sluice-play: warning: " + warning.text + " [" + warning.kind + "]";
}

} // namespace sluice::rt
