// Generalized winding number of a triangle soup by brute force (Jacobson et al. 2013), SoA.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

namespace sluice::bake {

/// Triangles stored as nine coordinate arrays, padded to whole blocks, so the per-triangle
/// algebra runs as a fixed-length branch-free loop that the compiler vectorizes.
class WindingSoup {
public:
    /// Triangles per block; the arrays are padded to a multiple of it.
    static constexpr std::size_t kBlock = 64;

    void add(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);
    std::size_t size() const { return m_count; }
    bool empty() const { return m_count == 0; }

    /// Sum of the signed solid angles of the triangles seen from p, over 4 pi: 1 inside a closed
    /// outward-oriented surface, 0 outside, fractional near the holes of an open one. Undefined
    /// on the triangles themselves. O(triangles); summed in a fixed order, so deterministic.
    double at(const glm::dvec3& p) const;

private:
    std::size_t m_count = 0; ///< real triangles; the rest of each block is padding
    std::vector<double> m_ax, m_ay, m_az, m_bx, m_by, m_bz, m_cx, m_cy, m_cz;
};

} // namespace sluice::bake
