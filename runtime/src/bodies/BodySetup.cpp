// Dynamic bodies at scene start: mass properties, contact points and the GPU records.
#include "bodies/BodySetup.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_set>

#include <glm/gtc/quaternion.hpp>
#include <glm/matrix.hpp>

#include "sluice/format/asset/GridSamples.h"
#include "sluice/format/asset/MassProperties.h"
#include "sluice/format/asset/SdfSampler.h"

namespace sluice::rt {

namespace {

// Fixed-point units of the reaction sums: a particle's correction is at most a few h, so
// 2^28 / h keeps it in 32 bits with 28 bits below h (docs/bodies.md, "Reaction").
constexpr double kSumUnitsPerH = double(shared::kSumUnitsPerH);

std::string colliderPath(std::size_t c) {
    return "colliders[" + std::to_string(c) + "].dynamic";
}

// The mass properties the body uses, in the asset frame at unit density.
Result<format::MassProperties> massOf(const format::Scene& scene, std::size_t c,
                                      const format::ColliderAsset& asset, bool& fromMesh) {
    const format::ColliderMeta& m = asset.meta;
    fromMesh = m.meshMass.has_value();
    if (fromMesh)
        return *m.meshMass;
    if (m.mesh.triangles > 0 && !m.mesh.closed)
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + colliderPath(c) + ": " + m.sourceFile +
                        " is an open mesh (" + std::to_string(m.mesh.boundaryEdges) +
                        " boundary edges), so it has no volume to float or weigh; close the "
                        "mesh and re-bake it, or make the collider static");
    auto field = format::massPropertiesFromField(asset);
    if (!field)
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + colliderPath(c) + ": " + field.error().detail);
    return *field;
}

// A dynamic collider's mass, inertia and volume in the world, from the asset's mass properties
// scaled by the placement and the density (or the density that gives the scene's mass).
struct BodyMass {
    double mass = 0.0;           // [kg]
    double volume = 0.0;         // [m^3]
    glm::dvec3 centerLocal{0.0}; // centre of mass in the asset frame [asset units]
    glm::mat3 invInertia{0.0f};  // body-local inverse inertia [1/(kg m^2)]
    bool fromMesh = false;
};

Result<BodyMass> bodyMass(const format::Scene& scene, std::size_t c,
                          const format::ColliderAsset& asset) {
    const format::SceneCollider& sc = scene.colliders[c];
    const format::DynamicBody& d = *sc.dynamic;
    BodyMass out;
    auto unit = massOf(scene, c, asset, out.fromMesh);
    if (!unit)
        return unit.error();
    const double s = sc.scale;
    out.volume = unit->volume * s * s * s;
    out.centerLocal = unit->centerOfMass;
    const double density = d.density ? double(*d.density) : double(*d.mass) / out.volume;
    out.mass = density * out.volume;
    const glm::dmat3 inertia = unit->inertia * (density * s * s * s * s * s); // [kg m^2]
    if (!(out.mass > 0.0) || !std::isfinite(out.mass) || !(glm::determinant(inertia) > 0.0))
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + colliderPath(c) +
                        ": the body's mass or inertia is not positive (volume " +
                        std::to_string(out.volume) + " m^3); is the mesh closed?");
    // The GPU works in float: a mass or inertia whose inverse a float cannot hold would turn
    // the body's state into infinities.
    out.invInertia = glm::mat3(glm::inverse(inertia));
    bool usable = std::isfinite(float(1.0 / out.mass)) && float(out.mass) > 0.0f;
    for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row)
            usable = usable && std::isfinite(out.invInertia[col][row]);
    if (!usable)
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + colliderPath(c) + ": a mass of " +
                        std::to_string(out.mass) +
                        " kg is too small to simulate in single precision; give the body a "
                        "density of at least a few kg/m^3");
    return out;
}

} // namespace

Result<double> bodyDensity(const format::Scene& scene, std::size_t c,
                           const format::ColliderAsset& asset) {
    auto mass = bodyMass(scene, c, asset);
    if (!mass)
        return mass.error();
    return mass->mass / mass->volume;
}

Result<void> checkBodies(const format::Scene& scene,
                         const std::vector<format::ColliderAsset>& assets) {
    for (std::size_t c = 0; c < scene.colliders.size() && c < assets.size(); ++c)
        if (scene.colliders[c].dynamic)
            if (auto mass = bodyMass(scene, c, assets[c]); !mass)
                return mass.error();
    return {};
}

std::vector<glm::vec4> surfacePoints(const format::ColliderAsset& asset, double gap) {
    const format::SdfSampler sampler(asset);
    const format::ColliderMeta& m = asset.meta;
    const double band = 0.75 * m.voxelSize;
    std::vector<glm::vec3> onSurface;
    format::forEachStoredSample(asset, [&](glm::uvec3 ijk, float phi) {
        if (std::abs(phi) > band)
            return;
        glm::dvec3 p = asset.pointPosition(ijk.x, ijk.y, ijk.z);
        // Two Newton steps onto phi = 0 along the gradient.
        for (int it = 0; it < 2; ++it) {
            const glm::dvec3 g = sampler.gradient(p);
            const double g2 = glm::dot(g, g);
            if (!(g2 > 1e-12))
                break;
            p -= double(sampler.value(p)) * g / g2;
        }
        if (std::abs(sampler.value(p)) <= 0.05 * m.voxelSize)
            onSurface.emplace_back(p);
    });
    for (;; gap *= 1.25) {
        std::vector<glm::vec4> kept;
        std::unordered_set<std::uint64_t> cells;
        for (const glm::vec3& p : onSurface) {
            // Cells from the grid's corner; points lie inside the grid box (bakes pad it).
            const glm::dvec3 c =
                glm::clamp(glm::floor((glm::dvec3(p) - m.origin) / gap), 0.0, 2097151.0);
            const std::uint64_t key =
                std::uint64_t(c.x) | (std::uint64_t(c.y) << 21) | (std::uint64_t(c.z) << 42);
            if (!cells.insert(key).second)
                continue;
            const glm::dvec3 g = sampler.gradient(glm::dvec3(p));
            const double l1 = std::abs(g.x) + std::abs(g.y) + std::abs(g.z);
            const double len = glm::length(g);
            const double area = l1 > 0.0 ? gap * gap * len / l1 : gap * gap;
            kept.emplace_back(p, float(area));
        }
        if (kept.size() <= shared::kMaxBodySamples)
            return kept;
    }
}

std::vector<glm::vec4> bodyContactPoints(const format::ColliderAsset& asset, double scale,
                                         const PbfConstants& k) {
    // About one particle spacing apart (what the fluid resolves), at most one per voxel.
    return surfacePoints(asset, std::max(asset.meta.voxelSize, double(2.0f * k.radius) / scale));
}

Result<BodySetup> setUpBodies(const format::Scene& scene,
                              const std::vector<format::ColliderAsset>& assets,
                              const PbfConstants& k) {
    BodySetup out;
    out.bodyOfCollider.assign(scene.colliders.size(), shared::kNoBody);
    for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
        const format::SceneCollider& sc = scene.colliders[c];
        if (!sc.dynamic)
            continue;
        const format::ColliderAsset& asset = assets[c];
        auto mass = bodyMass(scene, c, asset);
        if (!mass)
            return mass.error();
        const format::DynamicBody& d = *sc.dynamic;
        const double s = sc.scale;

        const std::vector<glm::vec4> points = bodyContactPoints(asset, s, k);
        double reach = 0.0;
        for (const glm::vec4& p : points)
            reach = std::max(reach, glm::length(glm::dvec3(glm::vec3(p)) - mass->centerLocal));

        const ColliderPose start = colliderPose(sc, 0.0f);
        shared::GpuBody b{};
        b.position = start.toWorld(glm::vec3(mass->centerLocal));
        b.orientation =
            glm::vec4(start.rotation.x, start.rotation.y, start.rotation.z, start.rotation.w);
        b.mass = float(mass->mass);
        b.invMass = float(1.0 / mass->mass);
        b.linearVelocity = d.linearVelocity;
        b.angularVelocity = glm::radians(d.angularVelocityDegrees);
        b.collider = std::uint32_t(c);
        b.invInertia = glm::mat4(mass->invInertia);
        b.centerLocal = glm::vec3(mass->centerLocal);
        b.scale = float(s);
        b.boundRadius = float(s * (reach + asset.meta.voxelSize));
        b.sumScale = float(kSumUnitsPerH / k.h);
        b.momentScale = float(kSumUnitsPerH / (k.h * (double(b.boundRadius) + k.h)));
        b.sampleOffset = std::uint32_t(out.samples.size());
        b.sampleCount = std::uint32_t(points.size());
        b.friction = d.friction;
        b.restitution = d.restitution;
        out.samples.insert(out.samples.end(), points.begin(), points.end());
        out.bodyOfCollider[c] = std::uint32_t(out.records.size());
        out.records.push_back(b);
        out.volumes.push_back(mass->volume);
        out.fromMesh.push_back(mass->fromMesh);
    }
    return out;
}

std::uint32_t removeParticlesInBodies(const format::Scene& scene,
                                      const std::vector<format::ColliderAsset>& assets,
                                      std::vector<ParticleState>& particles) {
    std::uint32_t removed = 0;
    for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
        if (!scene.colliders[c].dynamic)
            continue;
        const format::SdfSampler sampler(assets[c]);
        const ColliderPose pose = colliderPose(scene.colliders[c], 0.0f);
        const auto inside = [&](const ParticleState& p) {
            return sampler.value(glm::dvec3(pose.toLocal(p.position))) < 0.0f;
        };
        const auto first = std::remove_if(particles.begin(), particles.end(), inside);
        removed += std::uint32_t(particles.end() - first);
        particles.erase(first, particles.end());
    }
    return removed;
}

ColliderPose bodyPose(const shared::GpuBody& body) {
    ColliderPose pose;
    pose.rotation =
        glm::quat(body.orientation.w, body.orientation.x, body.orientation.y, body.orientation.z);
    pose.scale = body.scale;
    pose.translation = body.position - pose.rotation * (body.scale * body.centerLocal);
    return pose;
}

} // namespace sluice::rt
