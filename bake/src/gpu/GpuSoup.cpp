// The triangle soup of a GPU bake, prepared as the CGAL reference prepares it.
#include "gpu/GpuSoup.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <glm/geometric.hpp>

#include "import/BoundaryChain.h"

namespace sluice::bake {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

Point toPoint(const glm::dvec3& p) {
    return Point(p.x, p.y, p.z);
}

/// True when every edge's uses in one direction cancel its uses in the other: the soup is a
/// cycle, whose winding number is an integer everywhere off it.
bool isCycle(const std::vector<std::array<std::size_t, 3>>& polygons) {
    return boundaryChain(polygons).empty();
}

/// True when every edge of the triangles is used exactly twice, once in each direction: a closed,
/// consistently oriented surface. orient_polygon_soup has nothing to change on such a soup
/// but to split vertices where two sheets touch (same coordinates, new indices), and
/// is_polygon_soup_a_polygon_mesh then accepts it, so the parity bake may skip both (a third of
/// a second on a 50k-triangle mesh).
bool isClosedOrientedSurface(const std::vector<std::array<std::size_t, 3>>& polygons) {
    // One key per directed edge: the undirected edge (lower, higher index) and the direction as
    // the lowest bit. Sorted, the keys must come in pairs of the same edge, one each way.
    std::vector<std::uint64_t> keys;
    keys.reserve(polygons.size() * 3);
    for (const auto& t : polygons)
        for (int c = 0; c < 3; ++c) {
            const std::uint64_t u = t[c], v = t[(c + 1) % 3];
            if (u >= (std::uint64_t(1) << 31) || v >= (std::uint64_t(1) << 31))
                return false; // cannot happen for a welded soup (32-bit indices); be safe
            keys.push_back(std::min(u, v) << 33 | std::max(u, v) << 1 | (u < v ? 1 : 0));
        }
    std::sort(keys.begin(), keys.end());
    if (keys.size() % 2 != 0)
        return false;
    for (std::size_t i = 0; i < keys.size(); i += 2)
        if ((keys[i] >> 1) != (keys[i + 1] >> 1) || (keys[i] & 1) != 0 || (keys[i + 1] & 1) != 1)
            return false; // a boundary edge, or one used twice or three times the same way
    return true;
}

} // namespace

Result<GpuSoup> prepareGpuSoup(const TriangleSoup& soup, const format::MeshDiagnostics& diagnostics,
                               SignMode mode) {
    Result<format::SignMethod> method = chooseSignMethod(diagnostics, mode);
    if (!method)
        return method.error();
    GpuSoup out;
    out.method = *method;
    out.points = soup.positions;
    std::vector<std::array<std::size_t, 3>> faces; // three distinct corners
    faces.reserve(soup.triangles.size());
    for (const glm::uvec3& t : soup.triangles)
        if (t.x != t.y && t.y != t.z && t.z != t.x)
            faces.push_back({t.x, t.y, t.z});

    bool closedOriented = false;
    if (out.method == format::SignMethod::Parity && isClosedOrientedSurface(faces)) {
        closedOriented = true;
    } else if (out.method == format::SignMethod::Parity) {
        // As CGAL's Side_of_triangle_mesh needs: one consistent orientation of the closed
        // surface. Zero-area faces stay in for this (without them a closed mesh has holes).
        std::vector<Point> points;
        points.reserve(out.points.size());
        for (const glm::dvec3& p : out.points)
            points.push_back(toPoint(p));
        std::vector<std::array<std::size_t, 3>> oriented = faces;
        namespace PMP = CGAL::Polygon_mesh_processing;
        (void)PMP::orient_polygon_soup(points, oriented);
        if (PMP::is_polygon_soup_a_polygon_mesh(oriented) && isCycle(oriented)) {
            out.points.clear();
            for (const Point& p : points)
                out.points.push_back({p.x(), p.y(), p.z()});
            faces = std::move(oriented);
        } else {
            out.method = format::SignMethod::Winding;
        }
    }

    for (const auto& t : faces)
        if (!CGAL::collinear(toPoint(out.points[t[0]]), toPoint(out.points[t[1]]),
                             toPoint(out.points[t[2]])))
            out.triangles.push_back(t);
    if (out.triangles.empty())
        return fail(ErrorCode::EmptyMesh, "the mesh has no triangle of non-zero area");

    // A closed soup wound inward would give w = -1 inside; turn it outward, as the reference does.
    out.cycle = (closedOriented && out.triangles.size() == faces.size()) || isCycle(out.triangles);
    if (out.cycle) {
        const Box box = soup.bounds();
        const glm::dvec3 center = 0.5 * (box.lo + box.hi);
        double volume = 0.0;
        for (const auto& t : out.triangles)
            volume += glm::dot(out.points[t[0]] - center,
                               glm::cross(out.points[t[1]] - center, out.points[t[2]] - center));
        if (volume < 0.0)
            for (auto& t : out.triangles)
                std::swap(t[1], t[2]);
    }
    return out;
}

} // namespace sluice::bake
