// The tank scenes and cube bodies of the body tests (SimulationBodiesTest.cpp,
// BodyReleaseTest.cpp), and what they measure of a body: its lowest point, its submerged share
// under a water level found by mass, its health over a run.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>

#include "RuntimeTestScenes.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt::bodytest {

constexpr float kSpacing = 0.02f;
constexpr float kSide = 8 * kSpacing; // the smallest cube the issue allows: 8 spacings wide

// A tank of `tank` (x, z) [m] holding water `depth` deep, open above up to `height`.
inline format::Scene tankScene(glm::vec2 tank, float depth, float height,
                               std::uint32_t substeps = 4) {
    format::Scene scene;
    scene.path = "tank.json";
    scene.name = "tank";
    const glm::uvec3 counts(std::uint32_t(std::lround(tank.x / kSpacing)),
                            std::uint32_t(std::lround(depth / kSpacing)),
                            std::uint32_t(std::lround(tank.y / kSpacing)));
    scene.simulation = testscene::defaultParams(kSpacing, substeps, counts.x * counts.y * counts.z);
    scene.simulation.targetDensityError = 0.005f;
    format::FluidBlock block;
    block.min = glm::vec3(0.0f);
    block.max = glm::vec3(counts) * kSpacing;
    scene.blocks.push_back(block);
    scene.domainMin = glm::vec3(0.0f);
    scene.domainMax = glm::vec3(tank.x, height, tank.y);
    return scene;
}

// A dynamic collider centred at `centre`, `ratio` times the water's density.
inline format::SceneCollider cubeBody(glm::vec3 centre, float ratio) {
    format::SceneCollider c;
    c.asset = "cube.slc";
    c.translation = centre;
    format::DynamicBody d;
    d.density = ratio * 1000.0f;
    c.dynamic = d;
    return c;
}

inline format::ColliderAsset cubeAsset(float side) {
    const double h = 0.5 * side;
    return testscene::boxColliderAsset(glm::dvec3(-h), glm::dvec3(h), 0.25 * kSpacing);
}

// A static cube of side kSide on the floor at (0.45, 0.2) and, above it, a body at 0.8 tilted
// 5 degrees, so it rocks onto the pedestal's top face and settles (centre 1.5 kSide up).
inline void addPedestalAndTiltedBox(format::Scene& scene) {
    format::SceneCollider pedestal;
    pedestal.asset = "cube.slc";
    pedestal.translation = glm::vec3(0.45f, 0.5f * kSide, 0.2f);
    scene.colliders.push_back(pedestal);
    format::SceneCollider top = cubeBody(glm::vec3(0.45f, 1.5f * kSide + 0.005f, 0.2f), 0.8f);
    top.rotationDegrees = glm::vec3(0.0f, 0.0f, 5.0f);
    scene.colliders.push_back(top);
}

// Height of the water surface away from the body, by mass: hydrostatic pressure at height y
// is the weight of the water above it, so the surface Archimedes' law refers to is
// y + (volume m / rho0 of the particles above y) / (their floor area). Measured above `below`
// (the body's lowest point), over the columns farther than `clear` [m] horizontally from
// `centre` and two spacings from the walls (the wall layers sit closer than the rest spacing).
// The top particles' heights are not that surface: PBF's surface layer sits closer than the
// rest spacing too.
inline double waterLevel(const std::vector<ParticleState>& particles, glm::vec3 centre,
                         double clear, glm::vec2 tank, double particleVolume, double below) {
    const double margin = 2.0 * kSpacing;
    std::uint64_t above = 0;
    for (const ParticleState& p : particles) {
        const glm::vec2 d(p.position.x - centre.x, p.position.z - centre.z);
        if (std::max(std::abs(d.x), std::abs(d.y)) < clear || p.position.x < margin ||
            p.position.z < margin || p.position.x > tank.x - margin ||
            p.position.z > tank.y - margin || p.position.y < below)
            continue;
        ++above;
    }
    const double area =
        (double(tank.x) - 2.0 * margin) * (double(tank.y) - 2.0 * margin) - 4.0 * clear * clear;
    return below + double(above) * particleVolume / area;
}

// Lowest point of the cube of side `side` at the body's pose.
inline double lowestPoint(const BodyState& body, float side) {
    double lowest = 1e30;
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner = (glm::vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1) - 0.5f) * side;
        lowest = std::min(lowest, double(body.pose.toWorld(corner).y));
    }
    return lowest;
}

// Share of the cube's volume below height `level`: 24^3 points inside it at its pose.
inline double submergedShare(const BodyState& body, float side, double level) {
    const int n = 24;
    int below = 0;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const glm::vec3 local =
                    (glm::vec3(i, j, k) + 0.5f) / float(n) * side - glm::vec3(0.5f * side);
                if (body.pose.toWorld(local).y < level)
                    ++below;
            }
    return double(below) / double(n * n * n);
}

// The level the water's volume gives in a tank of floor `area` [m^2] with a cube of side `side`
// at the body's pose: the particles' rest volume plus the cube's volume under the level fills the
// floor up to it, `particles V + share(level) side^3 = area level`, solved by fixed-point
// iteration (the cube's footprint is less than the floor, so each step shrinks the error by that
// ratio at least, and it stops within a micrometre). Every particle counts:
// unlike waterLevel it does not depend on how the few columns between a cube and close walls are
// arranged (docs/bodies.md, "What the tests hold it to").
inline double volumeLevel(std::size_t particles, double particleVolume, double area,
                          const BodyState& body, float side) {
    const double water = double(particles) * particleVolume;
    const double cube = double(side) * side * side;
    double level = water / area;
    for (int k = 0; k < 40; ++k) {
        const double next = (water + submergedShare(body, side, level) * cube) / area;
        const bool settled = std::abs(next - level) < 1e-6;
        level = next;
        if (settled)
            break;
    }
    return level;
}

// Robustness figures over a whole run: the worst step.
struct Health {
    std::uint32_t inside = 0;    ///< particles with phi < -r/2 in some collider or body
    std::uint32_t nonFinite = 0; ///< particles reset because they went non-finite
    void add(const StepStats& stats) {
        inside = std::max(inside, stats.insideColliders);
        nonFinite = std::max(nonFinite, stats.nonFinite);
    }
};

inline bool finite(const BodyState& b) {
    const float values[] = {b.position.x,        b.position.y,        b.position.z,
                            b.linearVelocity.x,  b.linearVelocity.y,  b.linearVelocity.z,
                            b.angularVelocity.x, b.angularVelocity.y, b.angularVelocity.z,
                            b.orientation.x,     b.orientation.y,     b.orientation.z,
                            b.orientation.w};
    return std::all_of(std::begin(values), std::end(values),
                       [](float v) { return std::isfinite(v); });
}

} // namespace sluice::rt::bodytest
