// Small scenes and analytic collider assets for the runtime tests (CPU reference and GPU solver).
//
// Header-only. Every SimulationParams field is set explicitly, to the values readScene would
// default them to from `spacing` (format/include/sluice/format/scene/Scene.h), so the tests never
// depend on the scene reader.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "AnalyticAsset.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"

namespace sluice::testscene {

using testasset::assetFromSdf;
using testasset::boxSdf;
using testasset::sphereSdf;

/// A grid covering [lo - padding, hi + padding] at `voxelSize` [world units] (rounded up).
inline format::ColliderAsset assetOverBox(glm::dvec3 lo, glm::dvec3 hi, double voxelSize,
                                          double padding,
                                          const std::function<double(const glm::dvec3&)>& sdf) {
    const glm::dvec3 origin = lo - glm::dvec3(padding);
    const glm::dvec3 extent = hi - lo + glm::dvec3(2.0 * padding);
    const glm::uvec3 dims = glm::uvec3(glm::ceil(extent / voxelSize)) + glm::uvec3(1);
    return assetFromSdf(dims, origin, voxelSize, sdf);
}

/// Collider asset of the solid box [lo, hi] (local units), padded by 3 voxels.
inline format::ColliderAsset boxColliderAsset(glm::dvec3 lo, glm::dvec3 hi, double voxelSize) {
    return assetOverBox(lo, hi, voxelSize, 3.0 * voxelSize,
                        [lo, hi](const glm::dvec3& p) { return boxSdf(p, lo, hi); });
}

/// Collider asset of the solid sphere (local units), padded by 3 voxels.
inline format::ColliderAsset sphereColliderAsset(glm::dvec3 center, double radius,
                                                 double voxelSize) {
    return assetOverBox(
        center - glm::dvec3(radius), center + glm::dvec3(radius), voxelSize, 3.0 * voxelSize,
        [center, radius](const glm::dvec3& p) { return sphereSdf(p, center, radius); });
}

/// Every SimulationParams field set to what readScene derives from `spacing` (h = 2 s,
/// except targetDensityError = 0: tests run a fixed iteration count unless they say otherwise;
/// 8 iterations, relaxation 0.01, s_corr k 0.1 / n 4 / dq 0.2 h, xsph 0.01, vorticity
/// 0.01 sqrt(9.81 h)), with `substeps` substeps of a 1/60 s step and the given capacity.
inline format::SimulationParams defaultParams(float spacing, std::uint32_t substeps = 4,
                                              std::uint32_t capacity = 0) {
    format::SimulationParams p;
    p.spacing = spacing;
    p.kernelRadius = 2.0f * spacing;
    p.restDensity = 1000.0f;
    p.timeStep = 1.0f / 60.0f;
    p.substeps = substeps;
    p.minIterations = 2;
    p.maxIterations = 8;
    p.targetDensityError = 0.0f;
    p.relaxation = 0.01f;
    p.scorrK = 0.1f;
    p.scorrN = 4.0f;
    p.scorrDeltaQ = 0.2f * p.kernelRadius;
    p.xsph = 0.01f;
    p.vorticity = 0.01f * std::sqrt(9.81f * p.kernelRadius);
    p.gravity = glm::vec3(0.0f, -9.81f, 0.0f);
    p.capacity = capacity;
    return p;
}

/// The parity tests' static floor: the slab [-1, 1] x [-1, 0] x [-1, 1] in asset units (at voxel
/// 0.02), rotated 30 degrees about y and scaled by 0.5, so its top stays at y = 0; friction 0.3.
/// Appends the asset and its scene collider ("floor.slc").
inline void addTiltedFloor(format::Scene& scene, std::vector<format::ColliderAsset>& assets) {
    assets.push_back(boxColliderAsset({-1.0, -1.0, -1.0}, {1.0, 0.0, 1.0}, 0.02));
    format::SceneCollider floor;
    floor.asset = "floor.slc";
    floor.rotationDegrees = glm::vec3(0.0f, 30.0f, 0.0f);
    floor.scale = 0.5f;
    floor.friction = 0.3f;
    scene.colliders.push_back(floor);
}

/// A valid scene: a box block of counts.x * counts.y * counts.z particles filling
/// [0, counts * spacing] (lattice points at s (i + 1/2)), inside the domain box
/// [0, (counts.x, 2 counts.y, counts.z) * spacing]: a column of water standing in a tank.
/// Capacity = the block's particle count; no emitters, no colliders.
inline format::Scene smallScene(glm::uvec3 counts, float spacing = 0.02f,
                                std::uint32_t substeps = 4) {
    format::Scene scene;
    scene.path = "small.json";
    scene.name = "small";
    scene.simulation = defaultParams(spacing, substeps, counts.x * counts.y * counts.z);
    format::FluidBlock block;
    block.shape = format::FluidBlock::Shape::Box;
    block.min = glm::vec3(0.0f);
    block.max = glm::vec3(counts) * spacing;
    scene.blocks.push_back(block);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(counts.x, 2 * counts.y, counts.z) * spacing;
    return scene;
}

/// A scene holding nothing yet: every parameter set, no blocks, no domain, capacity given.
inline format::Scene emptyScene(float spacing = 0.02f, std::uint32_t substeps = 4,
                                std::uint32_t capacity = 1024) {
    format::Scene scene;
    scene.path = "empty.json";
    scene.name = "empty";
    scene.simulation = defaultParams(spacing, substeps, capacity);
    return scene;
}

/// emptyScene with one nozzle at (0, 1, 0) pointing down: a 4 cm disc at 1 m/s from 0 to 10 s.
inline format::Scene nozzleScene(std::uint32_t capacity, float spacing = 0.02f,
                                 std::uint32_t substeps = 2) {
    format::Scene scene = emptyScene(spacing, substeps, capacity);
    format::Emitter nozzle;
    nozzle.position = glm::vec3(0.0f, 1.0f, 0.0f);
    nozzle.radius = 0.04f;
    nozzle.speed = 1.0f;
    nozzle.stop = 10.0f;
    scene.emitters.push_back(nozzle);
    return scene;
}

} // namespace sluice::testscene
