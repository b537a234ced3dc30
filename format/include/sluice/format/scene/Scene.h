// The scene file as plain data: what sluice-play simulates. Read with readScene (SceneIO.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sluice::format {

/// Current scene-file version ("version": 1). A file without "version" is read as version 1;
/// a larger version is rejected with UnsupportedVersion.
inline constexpr int kSceneVersion = 1;

/// Largest particle capacity a scene may ask for (docs/limits.md).
inline constexpr std::uint32_t kMaxSceneParticles = 1u << 24;

/// Most colliders in one scene.
inline constexpr std::uint32_t kMaxSceneColliders = 64;

/// Marks a float parameter whose default follows from the kernel radius (scorrDeltaQ,
/// vorticity): completeScene (SceneDefaults.h) replaces it, as the scene reader does for a key the
/// file leaves out. Any other negative value is out of range.
inline constexpr float kDerived = -1.0f;

/// Simulation parameters. A default-constructed value is a complete set once completeScene (or
/// readScene) has filled in the fields marked "derived" from `spacing` and the scene, as
/// documented in docs/scene-format.md; after that every field holds a value in its range.
struct SimulationParams {
    float spacing = 0.02f;             ///< particle rest spacing [m]; particle radius = spacing / 2
    float kernelRadius = 0.0f;         ///< SPH support h [m]; 0: derived, 2 * spacing
    float restDensity = 1000.0f;       ///< rho0 [kg/m^3]
    float timeStep = 1.0f / 60.0f;     ///< one step of `--steps` [s]
    std::uint32_t substeps = 0;        ///< PBF substeps per step; 0: derived from a CFL estimate
    std::uint32_t minIterations = 2;   ///< solver iterations always run per substep
    std::uint32_t maxIterations = 8;   ///< iteration cap per substep, >= minIterations
    float targetDensityError = 0.005f; ///< stop iterating when the average compression (rho/rho0-1,
                                       ///< >= 0) is below this (after minIterations); 0 = always
                                       ///< run maxIterations
    float relaxation = 0.01f;          ///< lambda epsilon as a fraction of sum |grad C|^2 of a
                                       ///< full-neighbourhood particle (eq. 8)
    float scorrK = 0.1f;               ///< s_corr k (eq. 10), in units of that particle's lambda
                                       ///< per unit compression
    float scorrN = 4.0f;               ///< s_corr exponent n (eq. 10)
    float scorrDeltaQ = kDerived;      ///< s_corr delta q [m]; kDerived: 0.2 * h
    float xsph = 0.01f;                ///< XSPH viscosity c, fraction of the neighbour average
    float vorticity = kDerived;        ///< vorticity confinement epsilon [m/s], 0 = off;
                                       ///< kDerived: 0.01 * sqrt(9.81 * h)
    glm::vec3 gravity{0.0f, -9.81f, 0.0f}; ///< [m/s^2]
    std::uint32_t capacity = 0; ///< most particles; 0: derived, the blocks + everything emitters
                                ///< emit between start and stop (stop defaults start + 10 s)
};

/// A region filled with particles at the rest spacing when the scene starts.
struct FluidBlock {
    enum class Shape { Box, Sphere };
    Shape shape = Shape::Box;
    glm::vec3 min{0.0f};      ///< box corner [m]
    glm::vec3 max{0.0f};      ///< box corner [m], > min on every axis
    glm::vec3 center{0.0f};   ///< sphere centre [m]
    float radius = 0.0f;      ///< sphere radius [m]
    glm::vec3 velocity{0.0f}; ///< initial velocity [m/s]
};

/// A nozzle: a disc of particles at the rest spacing leaves it every spacing / speed seconds.
struct Emitter {
    glm::vec3 position{0.0f};               ///< disc centre [m]
    glm::vec3 direction{0.0f, -1.0f, 0.0f}; ///< unit after reading
    float radius = 0.0f;                    ///< disc radius [m], >= spacing / 2
    float speed = 0.0f;                     ///< exit speed [m/s], > 0
    float rate = 0.0f;                      ///< optional cap [particles/s]; 0 = no cap
    float start = 0.0f;                     ///< [s]
    float stop = 0.0f;                      ///< [s]; default start + 10 s; > start
};

/// Most drain boxes in one scene (and in Simulation::setDrains).
inline constexpr std::uint32_t kMaxDrains = 8;

/// A box that removes every particle whose position at a substep's start lies inside it:
/// min <= x < max on every axis.
struct Drain {
    glm::vec3 min{0.0f}; ///< [m]
    glm::vec3 max{0.0f}; ///< [m], > min on every axis
};

/// One keyframe of a kinematic collider; between keys translation is linear and rotation slerped.
struct ColliderKey {
    float time = 0.0f;               ///< [s], strictly increasing across keys
    glm::vec3 translation{0.0f};     ///< [m]
    glm::vec3 rotationDegrees{0.0f}; ///< Euler angles X, Y, Z [degrees], applied Z * Y * X
};

/// What makes a collider dynamic: the fluid and the other bodies push it, gravity pulls it
/// (docs/bodies.md). Exactly one of density and mass is set after reading.
struct DynamicBody {
    std::optional<float> density;           ///< [kg/m^3], > 0; mass = density * volume
    std::optional<float> mass;              ///< [kg], > 0; the density follows from the volume
    glm::vec3 linearVelocity{0.0f};         ///< initial velocity of the centre of mass [m/s]
    glm::vec3 angularVelocityDegrees{0.0f}; ///< initial angular velocity [degrees/s]
    float friction = 0.5f;                  ///< Coulomb coefficient of body contacts, [0, 2]
    float restitution = 0.0f;               ///< share of the normal speed kept on impact, [0, 1]
};

/// A collider given by its shape instead of a baked asset: a sphere, a box or a capsule (a
/// game's characters), centred on the collider's origin. Its distance field is computed in closed
/// form at load (format::shapeCollider, ShapeCollider.h), so it needs no bake.
struct ColliderShape {
    enum class Kind { Sphere, Box, Capsule };
    Kind kind = Kind::Sphere;
    float radius = 0.0f;    ///< sphere and capsule [m], > 0
    glm::vec3 size{0.0f};   ///< box: edge lengths along local x, y, z [m], each > 0
    float height = 0.0f;    ///< capsule: tip to tip along local y [m], >= 2 * radius
    float voxelSize = 0.0f; ///< spacing of its sampled field [m]; 0: derived, spacing / 2
};

/// "sphere" | "box" | "capsule", as the scene file spells them.
inline const char* shapeName(ColliderShape::Kind kind) {
    switch (kind) {
    case ColliderShape::Kind::Sphere:
        return "sphere";
    case ColliderShape::Kind::Box:
        return "box";
    case ColliderShape::Kind::Capsule:
        return "capsule";
    }
    return "shape";
}

/// A collider placed in the scene: a baked asset, or a shape.
struct SceneCollider {
    std::string asset;               ///< path as written in the file (relative to the scene);
                                     ///< empty for a shape
    std::string resolvedPath;        ///< absolute or cwd-relative path readScene resolved
    std::optional<ColliderShape> shape; ///< set instead of an asset
    glm::vec3 translation{0.0f};     ///< [m]
    glm::vec3 rotationDegrees{0.0f}; ///< Euler X, Y, Z [degrees], applied Z * Y * X
    float scale = 1.0f;              ///< uniform scale, > 0 (SDFs only survive uniform scale)
    float friction = 0.0f;           ///< fraction of tangential slip removed per contact [0, 1]
    glm::vec3 linearVelocity{0.0f};  ///< kinematic motion [m/s]
    glm::vec3 angularVelocityDegrees{0.0f}; ///< about the collider origin [degrees/s]
    std::vector<ColliderKey> keys;          ///< keyframes; when present they replace the velocities
    /// Set for a dynamic body; then the collider has no "motion" (velocities and keys are 0).
    std::optional<DynamicBody> dynamic;
    /// A static or kinematic collider: measure the fluid's force and torque on it
    /// (Simulation::latestForces). A dynamic body's are always known.
    bool measureForce = false;
};

/// What messages and tables call a collider: its asset path, or its shape's name.
inline std::string colliderName(const SceneCollider& c) {
    return c.shape ? std::string(shapeName(c.shape->kind)) : c.asset;
}

/// The camera sluice-play renders from.
struct Camera {
    glm::vec3 position{2.0f, 1.5f, 2.0f}; ///< [m]
    glm::vec3 target{0.0f};               ///< [m]
    float fovDegrees = 45.0f;             ///< vertical field of view [degrees]
    bool set = false;                     ///< false: sluice-play frames the scene itself
};

/// A whole scene file.
struct Scene {
    std::string path; ///< the file it was read from
    std::string name; ///< "name", default the file stem
    SimulationParams simulation;
    std::vector<FluidBlock> blocks;
    std::vector<Emitter> emitters;
    std::vector<SceneCollider> colliders;
    std::vector<Drain> drains;          ///< at most kMaxDrains
    std::optional<glm::vec3> domainMin; ///< particles stay inside [domainMin, domainMax] if set
    std::optional<glm::vec3> domainMax;
    Camera camera;
    /// The file named `"boundary": "bodies"`, a boundary model no longer there: the walls and
    /// every collider add boundary volume now (docs/pbf.md, "Boundary volume"), and
    /// sluice-play warns (docs/scene-format.md).
    bool namesRemovedBoundaryModel = false;
};

} // namespace sluice::format
