// Exact mass properties of a closed triangle mesh from surface integrals (divergence theorem).
#include "import/MeshMass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace sluice::bake {

namespace {

/// The ten volume integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx over the solid, about
/// some origin.
struct VolumeIntegrals {
    double volume = 0.0;
    glm::dvec3 first{0.0};    ///< (int x, int y, int z) dV
    glm::dvec3 squares{0.0};  ///< (int x^2, int y^2, int z^2) dV
    glm::dvec3 products{0.0}; ///< (int xy, int yz, int zx) dV
};

/// Sums of powers of one coordinate over a triangle's corners w0, w1, w2: Eberly, "Polyhedral
/// Mass Properties (Revisited)" (2002), procedure Subexpressions. The surface integrals of
/// Mirtich 1996 reduce over a triangle to these polynomials of the corners.
struct Subexpressions {
    double f1, f2, f3, g0, g1, g2;

    Subexpressions(double w0, double w1, double w2) {
        const double temp0 = w0 + w1;
        f1 = temp0 + w2;
        const double temp1 = w0 * w0;
        const double temp2 = temp1 + w1 * temp0;
        f2 = temp2 + w2 * f1;
        f3 = w0 * temp1 + w1 * temp2 + w2 * f2;
        g0 = f2 + w0 * (f1 + w0);
        g1 = f2 + w1 * (f1 + w1);
        g2 = f2 + w2 * (f1 + w2);
    }
};

/// The integrals over the solid bounded by `soup`, with coordinates taken relative to `origin`
/// (small coordinates keep the second moments accurate). Each triangle adds its term of the
/// divergence theorem (Mirtich 1996, eqs. 6-8; Eberly 2002, procedure Compute), with the
/// unnormalised face normal d = (p1 - p0) x (p2 - p0); outward triangles give volume > 0.
VolumeIntegrals integrate(const TriangleSoup& soup, const glm::dvec3& origin) {
    std::array<double, 10> sum{};
    for (const glm::uvec3& t : soup.triangles) {
        const glm::dvec3 p0 = soup.positions[t.x] - origin;
        const glm::dvec3 p1 = soup.positions[t.y] - origin;
        const glm::dvec3 p2 = soup.positions[t.z] - origin;
        const glm::dvec3 d = glm::cross(p1 - p0, p2 - p0);
        const Subexpressions x(p0.x, p1.x, p2.x);
        const Subexpressions y(p0.y, p1.y, p2.y);
        const Subexpressions z(p0.z, p1.z, p2.z);
        sum[0] += d.x * x.f1;
        sum[1] += d.x * x.f2;
        sum[2] += d.y * y.f2;
        sum[3] += d.z * z.f2;
        sum[4] += d.x * x.f3;
        sum[5] += d.y * y.f3;
        sum[6] += d.z * z.f3;
        sum[7] += d.x * (p0.y * x.g0 + p1.y * x.g1 + p2.y * x.g2);
        sum[8] += d.y * (p0.z * y.g0 + p1.z * y.g1 + p2.z * y.g2);
        sum[9] += d.z * (p0.x * z.g0 + p1.x * z.g1 + p2.x * z.g2);
    }
    VolumeIntegrals out;
    out.volume = sum[0] / 6.0;
    out.first = glm::dvec3(sum[1], sum[2], sum[3]) / 24.0;
    out.squares = glm::dvec3(sum[4], sum[5], sum[6]) / 60.0;
    out.products = glm::dvec3(sum[7], sum[8], sum[9]) / 120.0;
    return out;
}

/// Whether every edge of the soup is walked once in each direction by its two triangles, as an
/// orientable closed surface with consistent winding has it. Triangles with a repeated corner
/// are not faces and are left out (their integrals are zero).
bool consistentlyOriented(const TriangleSoup& soup) {
    std::vector<std::uint64_t> directed;
    directed.reserve(soup.triangles.size() * 3);
    for (const glm::uvec3& t : soup.triangles) {
        if (t.x == t.y || t.y == t.z || t.z == t.x)
            continue;
        for (int c = 0; c < 3; ++c)
            directed.push_back(std::uint64_t(t[c]) << 32 | t[(c + 1) % 3]);
    }
    std::sort(directed.begin(), directed.end());
    return std::adjacent_find(directed.begin(), directed.end()) == directed.end();
}

bool isFinite(const format::MassProperties& m) {
    bool finite = std::isfinite(m.volume);
    for (int i = 0; i < 3; ++i) {
        finite = finite && std::isfinite(m.centerOfMass[i]);
        for (int j = 0; j < 3; ++j)
            finite = finite && std::isfinite(m.inertia[i][j]);
    }
    return finite;
}

} // namespace

format::MassProperties polyhedronMassProperties(const TriangleSoup& soup) {
    const Box box = soup.bounds();
    format::MassProperties out;
    out.centerOfMass = box.empty() ? glm::dvec3(0.0) : 0.5 * (box.lo + box.hi);

    // First pass about the box centre: volume and centre of mass. An inward-facing soup has
    // every integral negated; multiplying by the sign of the volume flips it outward.
    const VolumeIntegrals coarse = integrate(soup, out.centerOfMass);
    if (!(std::abs(coarse.volume) > 0.0))
        return out;
    const double orientation = coarse.volume < 0.0 ? -1.0 : 1.0;
    out.volume = orientation * coarse.volume;
    out.centerOfMass += coarse.first / coarse.volume;

    // Second pass about that centre, so the second moments need almost no parallel-axis
    // correction (which would cancel digits for a mesh far from its box centre's scale).
    const VolumeIntegrals fine = integrate(soup, out.centerOfMass);
    const double volume = orientation * fine.volume;
    const glm::dvec3 first = orientation * fine.first;
    const glm::dvec3 squares = orientation * fine.squares;
    const glm::dvec3 products = orientation * fine.products;
    const glm::dvec3 shift = first / volume; // what the first pass missed, ~ rounding
    out.centerOfMass += shift;

    // Second moment S = int r r^T dV about the centre of mass (parallel axis for `shift`), then
    // the inertia tensor I = tr(S) 1 - S.
    glm::dmat3 s(squares.x, products.x, products.z,  // column 0: xx, xy, zx
                 products.x, squares.y, products.y,  // column 1: xy, yy, yz
                 products.z, products.y, squares.z); // column 2: zx, yz, zz
    s -= volume * glm::outerProduct(shift, shift);
    const double trace = s[0][0] + s[1][1] + s[2][2];
    out.inertia = trace * glm::dmat3(1.0) - s;
    out.volume = volume;
    return out;
}

std::optional<format::MassProperties> closedMeshMass(const TriangleSoup& soup,
                                                     const format::MeshDiagnostics& diagnostics) {
    // A closed mesh with some triangles wound the other way bounds a solid, but the integrals
    // would subtract those triangles' parts instead of adding them.
    if (!diagnostics.closed || !consistentlyOriented(soup))
        return std::nullopt;
    const format::MassProperties mass = polyhedronMassProperties(soup);
    if (!(mass.volume > 0.0) || !isFinite(mass))
        return std::nullopt;
    return mass;
}

} // namespace sluice::bake
