// CPU reference of the PBF substep, written straight from docs/pbf.md and docs/bodies.md.
#include "ReferencePbf.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "sluice/format/support/Assert.h"

namespace sluice::ref {

namespace {

/// Packs a cell (each coordinate in +-2^20) into one key.
std::int64_t cellKey(glm::ivec3 c) {
    constexpr std::int64_t kBias = 1 << 20, kBits = 21;
    return ((std::int64_t(c.x) + kBias) << (2 * kBits)) | ((std::int64_t(c.y) + kBias) << kBits) |
           (std::int64_t(c.z) + kBias);
}

} // namespace

ReferencePbf::ReferencePbf(const format::Scene& scene, std::vector<ReferenceCollider> colliders)
    : m_params(scene.simulation), m_c(rt::deriveConstants(scene.simulation)), m_schedule(scene) {
    SLUICE_ASSERT(m_params.maxIterations > 0, "ReferencePbf: maxIterations must be > 0");
    if (scene.domainMin && scene.domainMax) {
        m_hasDomain = true;
        m_domainMin = *scene.domainMin;
        m_domainMax = *scene.domainMax;
    }
    for (const ReferenceCollider& c : colliders) {
        SLUICE_ASSERT(c.asset != nullptr, "ReferencePbf: collider without an asset");
        Collider collider{c.placement, format::SdfSampler(*c.asset)};
        collider.asset = c.asset;
        if (!c.placement.dynamic)
            collider.volumeMap = buildVolumeMap(*c.asset, collider.sampler,
                                                double(m_c.h) / double(c.placement.scale));
        if (c.placement.dynamic) {
            collider.body = std::uint32_t(m_bodies.size());
            Body body;
            body.collider = m_colliders.size();
            body.pose = c.bodyPose ? *c.bodyPose : rt::colliderPose(c.placement, 0.0f);
            body.centerOfMass = c.centerOfMass;
            body.mass = c.mass;
            body.velocity = glm::dvec3(c.linearVelocity);
            body.angularVelocity = glm::dvec3(c.angularVelocity);
            body.invInertia = glm::dmat3(c.invInertia);
            body.contactPoints = c.contactPoints;
            // As rt::setUpBodies: the contact points' reach from the centre, and a voxel.
            const glm::dvec3 centreLocal(body.pose.toLocal(body.centerOfMass));
            double reach = 0.0;
            for (const glm::vec4& p : body.contactPoints)
                reach = std::max(reach, glm::length(glm::dvec3(glm::vec3(p)) - centreLocal));
            body.boundRadius = double(body.pose.scale) * (reach + c.asset->meta.voxelSize);
            m_bodies.push_back(body);
        }
        m_colliders.push_back(collider);
    }
    m_bodyOffset = m_c.bodyOffset;
    m_particles = rt::fillBlocks(scene);
    // Ids keep the blocks' numbering: emitted particles continue after the blocks' full count.
    m_nextId = std::uint32_t(m_particles.size());
    removeParticlesInBodies();
    if (m_particles.size() > m_params.capacity) {
        m_particles.resize(m_params.capacity);
        m_stats.capacityReached = true;
        m_nextId = m_particles.empty() ? 0 : m_particles.back().id + 1;
    }
}

// docs/bodies.md: a particle whose centre starts inside a body (phi < 0 at the placement's pose
// at t = 0, no offset) is left out.
void ReferencePbf::removeParticlesInBodies() {
    for (const Body& body : m_bodies) {
        const Collider& c = m_colliders[body.collider];
        const rt::ColliderPose start = rt::colliderPose(c.placement, 0.0f);
        const auto inside = [&](const rt::ParticleState& p) {
            return c.sampler.value(glm::dvec3(start.toLocal(p.position))) < 0.0f;
        };
        const auto first = std::remove_if(m_particles.begin(), m_particles.end(), inside);
        m_removedAtSpawn += std::uint32_t(m_particles.end() - first);
        m_particles.erase(first, m_particles.end());
    }
}

float ReferencePbf::timeAt(std::uint64_t substepIndex) const {
    return float(double(substepIndex) * double(m_c.dt));
}

float ReferencePbf::W(float q) const {
    const float h = m_c.h;
    if (q >= h)
        return 0.0f;
    const float d = h * h - q * q;
    return m_c.poly6 * d * d * d;
}

glm::vec3 ReferencePbf::gradW(glm::vec3 x) const {
    const float q = glm::length(x);
    if (q <= 0.0f || q >= m_c.h)
        return glm::vec3(0.0f);
    const float d = m_c.h - q;
    return (m_c.spikyGrad * d * d / q) * x;
}

void ReferencePbf::substep() {
    m_stats.nonFinite = 0;
    m_stats.capacityReached = false;
    startBodyStep();
    substepImpl(1.0);
    finishStats();
}

void ReferencePbf::step() {
    m_stats.nonFinite = 0;
    m_stats.capacityReached = false;
    startBodyStep();
    // Bodies report the mean force and torque over the step's substeps.
    const double share = 1.0 / double(std::max(1u, m_params.substeps));
    for (std::uint32_t n = 0; n < m_params.substeps; ++n)
        substepImpl(share);
    finishStats();
}

void ReferencePbf::substepImpl(double bodyShare) {
    const float t = timeAt(m_substepIndex);
    const float dt = m_c.dt;

    // 1. Emit.
    std::vector<rt::ParticleState> fresh;
    if (!m_schedule.emit(t, std::uint32_t(m_particles.size()), m_params.capacity, m_nextId, fresh))
        m_stats.capacityReached = true;
    m_particles.insert(m_particles.end(), fresh.begin(), fresh.end());
    const std::size_t n = m_particles.size();

    // 2. Predict (symplectic Euler).
    m_predicted.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        rt::ParticleState& p = m_particles[i];
        p.velocity += dt * m_params.gravity;
        m_predicted[i] = p.position + dt * p.velocity;
        if (!isFinite(m_predicted[i]) || !isFinite(p.velocity)) {
            m_predicted[i] = p.position; // docs/pbf.md step 2: no NaN enters the search
            p.velocity = glm::vec3(0.0f);
            ++m_stats.nonFinite;
        }
    }

    // 3. Neighbours from x*, kept for the whole substep.
    buildNeighbours();

    // 4. Solve, with collisions and the domain clamp after every position update.
    solve();

    // 5. Velocity, and the non-finite guard.
    std::vector<glm::vec3> velocity(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 x = m_particles[i].position;
        velocity[i] = (m_predicted[i] - x) / dt;
        if (!isFinite(m_predicted[i]) || !isFinite(velocity[i])) {
            m_predicted[i] = x;
            velocity[i] = glm::vec3(0.0f);
            ++m_stats.nonFinite;
        }
    }

    // 6. Vorticity confinement and XSPH, from the velocities of step 5.
    vorticityAndXsph(velocity);

    // 7. Commit; the bodies take the reaction of the substep (they stay where they are).
    for (std::size_t i = 0; i < n; ++i) {
        m_particles[i].position = m_predicted[i];
        m_particles[i].velocity = velocity[i];
    }
    finishBodySubstep(bodyShare);
    ++m_substepIndex;
}

void ReferencePbf::startBodyStep() {
    for (Body& b : m_bodies) {
        b.force = glm::dvec3(0.0);
        b.torque = glm::dvec3(0.0);
        b.heldForce = glm::dvec3(0.0);
        b.sealedForce = glm::dvec3(0.0);
    }
}

// docs/bodies.md, "The body pass": every correction dx a body gave a particle is an impulse
// m dx / dt on the particle; the body takes -m dx / dt, so its force over the substep is
// -m sum dx / dt^2 and its torque -m sum (x - c) x dx / dt^2.
void ReferencePbf::finishBodySubstep(double share) {
    const double m = m_c.mass;
    const double dt = m_c.dt;
    const float t1 = timeAt(m_substepIndex + 1);
    for (Body& b : m_bodies) {
        const glm::dvec3 before = b.sumDx;
        addFilm(b, t1);
        b.sealedForce += share * (-m * (b.sumDx - before) / (dt * dt));
        b.force += share * (-m * b.sumDx / (dt * dt));
        b.torque += share * (-m * b.sumMoment / (dt * dt));
        // The film model's excess, then the held particles' reaction: only the part that stops
        // the body moving into them, from its velocity after gravity and the rest of the
        // reaction (pbf_bodies.comp), the held contact where it acts. The reference's bodies do
        // not turn: the spin only decides these shares.
        BodyMotion motion;
        if (b.mass > 0.0) {
            motion.v = b.velocity + dt * glm::dvec3(m_params.gravity) - m * b.sumDx / dt / b.mass;
            motion.w = b.angularVelocity + b.invInertia * (-m * b.sumMoment / dt);
        }
        takeStopping(b, -m * b.filmDx / dt, -m * b.filmMoment / dt, double(shared::kFilmDrainSpeed),
                     false, share, motion);
        const glm::dvec3 heldImpulse = -m * b.heldDx / dt;
        b.heldForce += share * heldImpulse / dt;
        takeStopping(b, heldImpulse, -m * b.heldMoment / dt, 0.0, true, share, motion);
        b.sumDx = glm::dvec3(0.0);
        b.sumMoment = glm::dvec3(0.0);
        b.heldDx = glm::dvec3(0.0);
        b.heldMoment = glm::dvec3(0.0);
        b.underDx = glm::dvec3(0.0);
        b.underMoment = glm::dvec3(0.0);
        b.surface = 0;
        b.filmDx = glm::dvec3(0.0);
        b.filmMoment = glm::dvec3(0.0);
    }
}

namespace {

// dx into `sum` and (x - c) x dx into `moment`, in double.
void addSums(glm::dvec3& sum, glm::dvec3& moment, glm::vec3 c, glm::vec3 x, glm::vec3 dx) {
    const glm::dvec3 d(dx);
    sum += d;
    moment += glm::cross(glm::dvec3(x) - glm::dvec3(c), d);
}

} // namespace

void ReferencePbf::addReaction(Body& body, glm::vec3 x, glm::vec3 dx) {
    addSums(body.sumDx, body.sumMoment, body.centerOfMass, x, dx);
}

void ReferencePbf::addHeld(Body& body, glm::vec3 x, glm::vec3 dx) {
    addSums(body.heldDx, body.heldMoment, body.centerOfMass, x, dx);
}

glm::dvec3 ReferencePbf::bodyForce(std::size_t b) const {
    SLUICE_ASSERT(b < m_bodies.size(), "ReferencePbf::bodyForce: no such body");
    return m_bodies[b].force;
}

glm::dvec3 ReferencePbf::bodyTorque(std::size_t b) const {
    SLUICE_ASSERT(b < m_bodies.size(), "ReferencePbf::bodyTorque: no such body");
    return m_bodies[b].torque;
}

glm::dvec3 ReferencePbf::bodyHeldForce(std::size_t b) const {
    SLUICE_ASSERT(b < m_bodies.size(), "ReferencePbf::bodyHeldForce: no such body");
    return m_bodies[b].heldForce;
}

glm::dvec3 ReferencePbf::bodySealedForce(std::size_t b) const {
    SLUICE_ASSERT(b < m_bodies.size(), "ReferencePbf::bodySealedForce: no such body");
    return m_bodies[b].sealedForce;
}

void ReferencePbf::buildNeighbours() {
    const std::size_t n = m_predicted.size();
    const float h = m_c.h;
    std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;
    std::vector<glm::ivec3> cells(n);
    for (std::size_t i = 0; i < n; ++i) {
        // A non-finite x* has no cell: it neither has nor is a neighbour (step 5 resets it).
        if (!isFinite(m_predicted[i]))
            continue;
        // Far-away cells fold into the outermost ones; the distance test still decides.
        constexpr float kLimit = float(1 << 19);
        cells[i] = glm::ivec3(glm::clamp(glm::floor(m_predicted[i] / h), -kLimit, kLimit));
        grid[cellKey(cells[i])].push_back(std::uint32_t(i));
    }
    m_neighbourStart.assign(n + 1, 0);
    m_neighbours.clear();
    std::vector<std::uint32_t> found;
    for (std::size_t i = 0; i < n; ++i) {
        m_neighbourStart[i] = std::uint32_t(m_neighbours.size());
        if (!isFinite(m_predicted[i]))
            continue;
        found.clear();
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const auto it = grid.find(cellKey(cells[i] + glm::ivec3(dx, dy, dz)));
                    if (it == grid.end())
                        continue;
                    for (std::uint32_t j : it->second)
                        if (j != i && glm::length(m_predicted[i] - m_predicted[j]) < h)
                            found.push_back(j);
                }
        std::sort(found.begin(), found.end()); // a fixed summation order
        m_neighbours.insert(m_neighbours.end(), found.begin(), found.end());
    }
    m_neighbourStart[n] = std::uint32_t(m_neighbours.size());
}

void ReferencePbf::solve() {
    const std::size_t n = m_predicted.size();
    const float V = m_c.volume;
    const float t0 = timeAt(m_substepIndex);
    const float t1 = timeAt(m_substepIndex + 1);
    m_lambda.assign(n, 0.0f);
    m_constraint.assign(n, 0.0f);
    std::vector<glm::vec3> dp(n);
    std::vector<glm::vec3> xOld(n);
    for (std::size_t i = 0; i < n; ++i)
        xOld[i] = m_particles[i].position;

    // Kernel values of every neighbour pair, from the x* of the current iteration (the lambda
    // and the correction passes read the same x*).
    std::vector<float> pairW(m_neighbours.size());
    std::vector<glm::vec3> pairGrad(m_neighbours.size());

    std::uint32_t updates = 0;
    for (std::uint32_t k = 0; k < m_params.maxIterations; ++k) {
        for (std::size_t i = 0; i < n; ++i)
            for (std::uint32_t a = m_neighbourStart[i]; a < m_neighbourStart[i + 1]; ++a) {
                const glm::vec3 d = m_predicted[i] - m_predicted[m_neighbours[a]];
                pairW[a] = W(glm::length(d));
                pairGrad[a] = gradW(d);
            }

        // 4.1 Density constraint and lambda (eq. 1, 7, 8).
        double errorSum = 0.0;
        for (std::size_t i = 0; i < n; ++i)
            errorSum += constraintAndLambda(i, pairW, pairGrad, t1);
        // The film model's level over each body (ReferenceFilm.cpp).
        if (k == 0 && !m_bodies.empty())
            for (std::size_t i = 0; i < n; ++i)
                if (m_lambda[i] != 0.0f)
                    recordSurface(m_predicted[i]);
        // 4.2 Early exit on the mean compression, after an even count only.
        const double meanError = n > 0 ? errorSum / double(n) : 0.0;
        const bool countAllowed = k % 2 == 0;
        if (k >= m_params.minIterations && countAllowed && m_params.targetDensityError > 0.0f &&
            meanError <= m_params.targetDensityError)
            break;

        // 4.3 Position corrections, all from the same x* (eq. 10, 11).
        for (std::size_t i = 0; i < n; ++i) {
            glm::vec3 sum(0.0f);
            for (std::uint32_t a = m_neighbourStart[i]; a < m_neighbourStart[i + 1]; ++a) {
                const std::uint32_t j = m_neighbours[a];
                const float scorr = -m_params.scorrK * m_c.lambdaRef *
                                    std::pow(pairW[a] / m_c.wDeltaQ, m_params.scorrN);
                sum += (m_lambda[i] + m_lambda[j] + scorr) * pairGrad[a];
            }
            dp[i] = V * sum;
        }

        // 4.4 Apply, push off the solids' boundaries, collide in scene order, clamp into the
        // domain shrunk by r.
        for (std::size_t i = 0; i < n; ++i)
            m_predicted[i] = applyCorrection(i, dp[i], xOld[i], t0, t1);
        ++updates;
    }

    double sum = 0.0, maxC = 0.0;
    for (float C : m_constraint) {
        sum += C;
        maxC = std::max(maxC, double(C));
    }
    m_stats.avgDensityError = n > 0 ? sum / double(n) : 0.0;
    m_stats.maxDensityError = maxC;
    m_stats.iterationsLastSubstep = updates;
}

void ReferencePbf::vorticityAndXsph(std::vector<glm::vec3>& velocity) const {
    const std::size_t n = velocity.size();
    const float V = m_c.volume;
    const float dt = m_c.dt;
    // Eq. 15: omega_i = sum_j V (v_j - v_i) x gradW(x_j - x_i).
    std::vector<glm::vec3> omega(n, glm::vec3(0.0f));
    for (std::size_t i = 0; i < n; ++i)
        for (std::uint32_t a = m_neighbourStart[i]; a < m_neighbourStart[i + 1]; ++a) {
            const std::uint32_t j = m_neighbours[a];
            omega[i] +=
                V * glm::cross(velocity[j] - velocity[i], gradW(m_predicted[j] - m_predicted[i]));
        }
    std::vector<glm::vec3> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        glm::vec3 eta(0.0f), xsph(0.0f);
        const float omegaI = glm::length(omega[i]);
        for (std::uint32_t a = m_neighbourStart[i]; a < m_neighbourStart[i + 1]; ++a) {
            const std::uint32_t j = m_neighbours[a];
            const glm::vec3 d = m_predicted[i] - m_predicted[j];
            eta += V * (glm::length(omega[j]) - omegaI) * gradW(d);
            xsph += V * (velocity[j] - velocity[i]) * W(glm::length(d));
        }
        const float etaLength = glm::length(eta);
        const glm::vec3 N = etaLength < 1e-12f ? glm::vec3(0.0f) : eta / etaLength;
        // Eq. 16 (confinement force) and eq. 17 (XSPH), weights normalised by V.
        out[i] =
            velocity[i] + dt * m_params.vorticity * glm::cross(N, omega[i]) + m_params.xsph * xsph;
    }
    velocity = std::move(out);
}

float ReferencePbf::colliderDistance(glm::vec3 x, float t) const {
    float best = std::numeric_limits<float>::infinity();
    for (const Collider& c : m_colliders) {
        const rt::ColliderPose pose =
            c.body != kNoBody ? m_bodies[c.body].pose : rt::colliderPose(c.placement, t);
        best = std::min(best, pose.scale * c.sampler.value(glm::dvec3(pose.toLocal(x))));
    }
    return best;
}

void ReferencePbf::finishStats() {
    const float t = time();
    double maxSpeed = 0.0;
    std::uint32_t inside = 0;
    for (const rt::ParticleState& p : m_particles) {
        maxSpeed = std::max(maxSpeed, double(glm::length(p.velocity)));
        if (colliderDistance(p.position, t) < -0.5f * m_c.radius)
            ++inside;
    }
    m_stats.maxSpeed = maxSpeed;
    m_stats.insideColliders = inside;
}

} // namespace sluice::ref
