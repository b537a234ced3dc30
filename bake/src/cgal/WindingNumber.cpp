// Generalized winding number of a triangle soup by brute force (Jacobson et al. 2013), SoA.
//
// Built with -fno-math-errno -fno-rounding-math (bake/CMakeLists.txt): otherwise std::sqrt is
// a library call (for errno, and for CGAL's dynamic rounding mode) and the block loop does not
// vectorize. Nothing here reads errno or changes the rounding mode.
#include "cgal/WindingNumber.h"

#include <cmath>
#include <numbers>

namespace sluice::bake {

void WindingSoup::add(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    if (m_count == m_ax.size()) {
        // Padding triangles have three equal corners at the origin: a . (b x c) is exactly
        // zero and the denominator is >= +0, so each adds atan2(+-0, >= +0) = 0.
        for (std::vector<double>* v :
             {&m_ax, &m_ay, &m_az, &m_bx, &m_by, &m_bz, &m_cx, &m_cy, &m_cz})
            v->resize(v->size() + kBlock, 0.0);
    }
    const std::size_t i = m_count++;
    m_ax[i] = a.x, m_ay[i] = a.y, m_az[i] = a.z;
    m_bx[i] = b.x, m_by[i] = b.y, m_bz[i] = b.z;
    m_cx[i] = c.x, m_cy[i] = c.y, m_cz[i] = c.z;
}

double WindingSoup::at(const glm::dvec3& p) const {
    double num[kBlock], den[kBlock];
    double sum = 0.0;
    for (std::size_t start = 0; start < m_ax.size(); start += kBlock) {
        const double* ax = &m_ax[start];
        const double* ay = &m_ay[start];
        const double* az = &m_az[start];
        const double* bx = &m_bx[start];
        const double* by = &m_by[start];
        const double* bz = &m_bz[start];
        const double* cx = &m_cx[start];
        const double* cy = &m_cy[start];
        const double* cz = &m_cz[start];
        // Van Oosterom & Strackee 1983: tan(Omega / 2) = a.(b x c) /
        // (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|), with a, b, c the corners relative to p.
        for (std::size_t k = 0; k < kBlock; ++k) {
            const double ux = ax[k] - p.x, uy = ay[k] - p.y, uz = az[k] - p.z;
            const double vx = bx[k] - p.x, vy = by[k] - p.y, vz = bz[k] - p.z;
            const double wx = cx[k] - p.x, wy = cy[k] - p.y, wz = cz[k] - p.z;
            const double lu = std::sqrt(ux * ux + uy * uy + uz * uz);
            const double lv = std::sqrt(vx * vx + vy * vy + vz * vz);
            const double lw = std::sqrt(wx * wx + wy * wy + wz * wz);
            num[k] = ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
            den[k] = lu * lv * lw + (ux * vx + uy * vy + uz * vz) * lw +
                     (vx * wx + vy * wy + vz * wz) * lu + (wx * ux + wy * uy + wz * uz) * lv;
        }
        // Omega = 2 atan2(num, den); the winding number is sum(Omega) / (4 pi).
        for (std::size_t k = 0; k < kBlock; ++k)
            sum += std::atan2(num[k], den[k]);
    }
    return sum / (2.0 * std::numbers::pi);
}

} // namespace sluice::bake
