// Test support: two particle sets (the GPU's and the CPU reference's, or two runs) compared
// particle by particle, matched by id.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::rt::test {

/// Raw bytes of the particles in memory order (position, velocity, id), for bit-for-bit checks.
inline std::vector<unsigned char> particleBytes(const std::vector<ParticleState>& particles) {
    std::vector<unsigned char> bytes(particles.size() * sizeof(ParticleState));
    if (!particles.empty())
        std::memcpy(bytes.data(), particles.data(), bytes.size());
    return bytes;
}

/// The particles by id.
inline std::unordered_map<std::uint32_t, ParticleState>
byId(const std::vector<ParticleState>& particles) {
    std::unordered_map<std::uint32_t, ParticleState> out;
    for (const ParticleState& p : particles)
        out[p.id] = p;
    return out;
}

/// Largest position difference between `a` and `b` by id [m]; every id of `a` must be in `b`,
/// and they must hold as many.
inline double maxPositionDifference(const std::vector<ParticleState>& a,
                                    const std::vector<ParticleState>& b) {
    EXPECT_EQ(a.size(), b.size());
    const auto ref = byId(b);
    double worst = 0.0;
    for (const ParticleState& p : a) {
        const auto it = ref.find(p.id);
        EXPECT_NE(it, ref.end()) << "id " << p.id << " only on one side";
        if (it != ref.end())
            worst = std::max(worst, double(glm::length(p.position - it->second.position)));
    }
    return worst;
}

/// Mean position difference between `a` and `b` by id [m].
inline double meanPositionDifference(const std::vector<ParticleState>& a,
                                     const std::vector<ParticleState>& b) {
    const auto ref = byId(b);
    double sum = 0.0;
    for (const ParticleState& p : a)
        sum += glm::length(p.position - ref.at(p.id).position);
    return a.empty() ? 0.0 : sum / double(a.size());
}

/// Particles of two runs in the same order that differ in any byte (0: the same bits). Runs of
/// different sizes fail the test and count the longer one's extra particles.
inline std::size_t differingParticles(const std::vector<ParticleState>& a,
                                      const std::vector<ParticleState>& b) {
    EXPECT_EQ(a.size(), b.size());
    std::size_t differing = std::max(a.size(), b.size()) - std::min(a.size(), b.size());
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        differing += std::memcmp(&a[i], &b[i], sizeof(ParticleState)) != 0 ? 1 : 0;
    return differing;
}

} // namespace sluice::rt::test
