// The CPU reference PBF (tests/reference) against an independent evaluation of docs/pbf.md: one
// substep of one iteration in double, over all pairs.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "ReferencePbf.h"
#include "RuntimeTestScenes.h"
#include "VecExpect.h"

using namespace sluice;
using sluice::test::expectVecNear;

namespace {

constexpr float kSpacing = 0.02f;

} // namespace

namespace {

/// docs/pbf.md steps 2 to 6 for one substep of one solver iteration, in double, all pairs, no
/// colliders or domain: an independent evaluation to hold the reference's float code against.
struct BruteForceSubstep {
    std::vector<glm::dvec3> x, v;
    double confinementShare = 0.0; ///< max |dt eps (N x omega)| [m/s], to see it is exercised

    BruteForceSubstep(const std::vector<rt::ParticleState>& start,
                      const format::SimulationParams& p, const rt::PbfConstants& c) {
        const double h = c.h, V = c.volume, dt = c.dt, pi = std::numbers::pi;
        auto W = [&](double q) {
            return q < h ? 315.0 / (64.0 * pi * std::pow(h, 9)) * std::pow(h * h - q * q, 3) : 0.0;
        };
        auto gradW = [&](const glm::dvec3& d) {
            const double q = glm::length(d);
            return q > 0.0 && q < h ? -45.0 / (pi * std::pow(h, 6)) * (h - q) * (h - q) / q * d
                                    : glm::dvec3(0.0);
        };
        const std::size_t n = start.size();
        std::vector<glm::dvec3> xs(n);
        v.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            v[i] = glm::dvec3(start[i].velocity) + dt * glm::dvec3(p.gravity);
            xs[i] = glm::dvec3(start[i].position) + dt * v[i];
        }
        std::vector<std::vector<std::size_t>> nb(n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j)
                if (j != i && glm::length(xs[i] - xs[j]) < h)
                    nb[i].push_back(j);
        std::vector<double> lambda(n);
        for (std::size_t i = 0; i < n; ++i) {
            double rho = W(0.0), gSq = 0.0;
            glm::dvec3 gSum(0.0);
            for (std::size_t j : nb[i]) {
                rho += W(glm::length(xs[i] - xs[j]));
                const glm::dvec3 g = V * gradW(xs[i] - xs[j]);
                gSum += g;
                gSq += glm::dot(g, g);
            }
            const double C = std::max(c.mass * rho / p.restDensity - 1.0, 0.0);
            lambda[i] = -C / (gSq + glm::dot(gSum, gSum) + c.epsilon);
        }
        std::vector<glm::dvec3> dp(n, glm::dvec3(0.0));
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j : nb[i]) {
                const double scorr = -p.scorrK * c.lambdaRef *
                                     std::pow(W(glm::length(xs[i] - xs[j])) / c.wDeltaQ, p.scorrN);
                dp[i] += V * (lambda[i] + lambda[j] + scorr) * gradW(xs[i] - xs[j]);
            }
        for (std::size_t i = 0; i < n; ++i) {
            xs[i] += dp[i];
            v[i] = (xs[i] - glm::dvec3(start[i].position)) / dt;
        }
        std::vector<glm::dvec3> omega(n, glm::dvec3(0.0));
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j : nb[i])
                omega[i] += V * glm::cross(v[j] - v[i], gradW(xs[j] - xs[i]));
        std::vector<glm::dvec3> out(n);
        for (std::size_t i = 0; i < n; ++i) {
            glm::dvec3 eta(0.0), xsph(0.0);
            for (std::size_t j : nb[i]) {
                eta += V * (glm::length(omega[j]) - glm::length(omega[i])) * gradW(xs[i] - xs[j]);
                xsph += V * (v[j] - v[i]) * W(glm::length(xs[i] - xs[j]));
            }
            const glm::dvec3 N = glm::length(eta) < 1e-12 ? glm::dvec3(0.0) : glm::normalize(eta);
            const glm::dvec3 confinement = dt * double(p.vorticity) * glm::cross(N, omega[i]);
            confinementShare = std::max(confinementShare, glm::length(confinement));
            out[i] = v[i] + confinement + double(p.xsph) * xsph;
        }
        v = out;
        x = xs;
    }
};

} // namespace

TEST(ReferencePbf, OneIterationMatchesABruteForceDoubleEvaluationOfPbfMd) {
    format::Scene scene = testscene::emptyScene(kSpacing, 4, 64);
    scene.simulation.minIterations = 1;
    scene.simulation.maxIterations = 1;
    scene.simulation.xsph = 0.05f;
    scene.simulation.vorticity = 0.5f;
    format::FluidBlock block;
    block.max = glm::vec3(4.0f * kSpacing);
    scene.blocks.push_back(block);
    ref::ReferencePbf sim(scene, {});
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> jitter(-0.15f * kSpacing, 0.15f * kSpacing),
        vel(-0.5f, 0.5f);
    for (rt::ParticleState& p : sim.mutableParticles()) {
        p.position = 0.85f * p.position + glm::vec3(jitter(rng), jitter(rng), jitter(rng));
        p.velocity = glm::vec3(vel(rng), vel(rng), vel(rng));
    }
    const BruteForceSubstep expected(sim.particles(), scene.simulation, sim.constants());
    sim.substep();
    double maxDx = 0.0;
    for (std::size_t i = 0; i < expected.x.size(); ++i) {
        const rt::ParticleState& p = sim.particles()[i];
        expectVecNear(p.position, glm::vec3(expected.x[i]), 2e-7f);
        expectVecNear(p.velocity, glm::vec3(expected.v[i]), 1e-4f);
        maxDx = std::max(maxDx, glm::length(expected.x[i] - glm::dvec3(p.position)));
    }
    EXPECT_GT(sim.stats().avgDensityError, 0.05); // compressed: the solve moved particles
    EXPECT_GT(expected.confinementShare, 1e-2);   // and confinement changed velocities
}
