// The exact CPU reference: signed distance to a triangle soup with CGAL, in double precision.
//
// Distance: exact closest point over the non-degenerate triangles in a CGAL AABB tree.
// Sign, one of:
//  - Parity: CGAL::Side_of_triangle_mesh (vertical ray, random rays on degenerate hits) on a
//    Surface_mesh made from the welded soup (orient_polygon_soup + polygon_soup_to_polygon_mesh).
//    Only meaningful for closed soups; if the mesh cannot be made, the winding number is used
//    and signFallbackReason() says why. A point within the previous point's empty ball (its
//    distance) takes that point's side without a ray: the segment between them meets nothing.
//  - Winding: the generalized winding number w (Jacobson et al. 2013), inside where w > 0.5.
//    Brute force is O(points x triangles), so we use an exact shortcut instead:
//      Close the soup M into a cycle Z = M + K by adding a cone K from one apex over the
//      boundary chain of M (the edges whose signed use counts do not cancel). The winding number
//      of a cycle is an integer, constant off its triangles, changing by +-1 at each proper
//      crossing. So W_Z(p) is an exact signed crossing count along a segment to a point far
//      outside (or from the previous point, carrying W along), and
//      w_M(p) = W_Z(p) - w_K(p), where w_K needs only the few cone triangles.
//    Crossings are decided with exact orientation predicates (EPICK); a crossing through an
//    edge, a vertex or an end point is not counted but sends that point to brute force.
//    For a closed soup K is empty and w_M = W_Z is the integer winding number.
#include "sluice/bake/cgal/CgalReference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "import/BoundaryChain.h"
#include "cgal/WindingNumber.h"

namespace sluice::bake {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using Mesh = CGAL::Surface_mesh<Point>;
using SideOf = CGAL::Side_of_triangle_mesh<Mesh, Kernel>;

/// Points per parallel task. Fixed, so the split (and any carried state) is the same in every
/// run: results do not depend on the thread count or scheduling.
constexpr std::size_t kChunk = 256;
/// How far a winding number of the closed cycle may sit from an integer and still be trusted.
constexpr double kIntegerTolerance = 1e-6;

Point toPoint(const glm::dvec3& p) {
    return Point(p.x, p.y, p.z);
}
glm::dvec3 toGlm(const Point& p) {
    return {p.x(), p.y(), p.z()};
}

/// Adds the signed proper crossings of segment q -> p with the tree's triangles to `delta`
/// (+1 entering a triangle against its normal, i.e. from its front side to its back).
/// Returns false when a crossing is not proper (through an edge or a vertex, or an end point
/// on a triangle's plane): the count is then unreliable.
bool addCrossings(const Tree& tree, const Point& q, const Point& p, long& delta,
                  std::vector<Tree::Primitive_id>& hits) {
    if (tree.empty())
        return true;
    hits.clear();
    tree.all_intersected_primitives(Segment(q, p), std::back_inserter(hits));
    for (const Tree::Primitive_id& id : hits) {
        const Triangle& t = *id;
        const CGAL::Orientation sq = CGAL::orientation(t[0], t[1], t[2], q);
        const CGAL::Orientation sp = CGAL::orientation(t[0], t[1], t[2], p);
        if (sq == CGAL::COPLANAR || sp == CGAL::COPLANAR)
            return false;
        if (sq == sp)
            continue;
        const CGAL::Orientation o0 = CGAL::orientation(q, p, t[0], t[1]);
        const CGAL::Orientation o1 = CGAL::orientation(q, p, t[1], t[2]);
        const CGAL::Orientation o2 = CGAL::orientation(q, p, t[2], t[0]);
        if (o0 == CGAL::COPLANAR || o1 == CGAL::COPLANAR || o2 == CGAL::COPLANAR)
            return false;
        if (o0 == o1 && o1 == o2)
            delta += sq == CGAL::POSITIVE ? 1 : -1;
    }
    return true;
}

/// Makes a closed Surface_mesh of the soup for Side_of_triangle_mesh; returns why not, or "".
/// Triangles with a repeated index are no faces and are left out; zero-area ones with three
/// distinct corners stay (a closed mesh without its slivers would have holes).
std::string buildParityMesh(const TriangleSoup& soup, Mesh& mesh) {
    std::vector<Point> points;
    points.reserve(soup.positions.size());
    for (const glm::dvec3& p : soup.positions)
        points.push_back(toPoint(p));
    std::vector<std::array<std::size_t, 3>> polygons;
    polygons.reserve(soup.triangles.size());
    for (const glm::uvec3& t : soup.triangles)
        if (t.x != t.y && t.y != t.z && t.z != t.x)
            polygons.push_back({t.x, t.y, t.z});
    namespace PMP = CGAL::Polygon_mesh_processing;
    // Returns false when it had to split non-manifold vertices; the result is still usable.
    (void)PMP::orient_polygon_soup(points, polygons);
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
        return "the triangles cannot be oriented consistently into a polygon mesh";
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
    if (!CGAL::is_triangle_mesh(mesh) || !CGAL::is_closed(mesh))
        return "the polygon mesh made from the triangles is not closed";
    return {};
}

/// The boundary chain of a soup (boundaryChain): edges with their net multiplicity.
using Boundary = std::vector<std::pair<std::pair<std::uint64_t, std::uint64_t>, int>>;

/// The soup's triangles with three distinct corners that are not collinear. Degenerate
/// triangles have no closest-point or solid-angle meaning (CGAL asserts on them); leaving them
/// out changes neither the distance nor the winding number anywhere off them.
std::vector<glm::uvec3> nonDegenerateTriangles(const TriangleSoup& soup) {
    std::vector<glm::uvec3> kept;
    kept.reserve(soup.triangles.size());
    for (const glm::uvec3& t : soup.triangles) {
        const Point a = toPoint(soup.positions[t.x]), b = toPoint(soup.positions[t.y]),
                    c = toPoint(soup.positions[t.z]);
        if (t.x != t.y && t.y != t.z && t.z != t.x && !CGAL::collinear(a, b, c))
            kept.push_back(t);
    }
    return kept;
}

/// Turns a closed soup (an empty `boundary`) wound inward, which would give w = -1 inside,
/// outward; its volume is origin-independent because it is a cycle. Open soups keep their
/// winding as given.
void orientOutward(const TriangleSoup& soup, const Boundary& boundary, const glm::dvec3& center,
                   std::vector<glm::uvec3>& kept) {
    if (!boundary.empty())
        return;
    double volume = 0.0;
    for (const glm::uvec3& t : kept)
        volume += glm::dot(soup.positions[t.x] - center,
                           glm::cross(soup.positions[t.y] - center, soup.positions[t.z] - center));
    if (volume < 0.0)
        for (glm::uvec3& t : kept)
            std::swap(t.y, t.z);
}

/// The cone K from one apex over the boundary chain, which closes the soup into a cycle.
struct Cone {
    std::vector<Triangle> triangles;
    WindingSoup winding;
};

/// The cone from `apex`: net copies of each boundary edge lo -> hi are cancelled by net copies
/// of (hi, lo, apex). None when the apex is collinear with a boundary edge.
std::optional<Cone> coneFrom(const TriangleSoup& soup, const Boundary& boundary,
                             const glm::dvec3& apex) {
    Cone cone;
    for (const auto& [edge, net] : boundary) {
        const glm::dvec3 lo = soup.positions[edge.first];
        const glm::dvec3 hi = soup.positions[edge.second];
        const glm::dvec3 first = net > 0 ? hi : lo, second = net > 0 ? lo : hi;
        if (CGAL::collinear(toPoint(first), toPoint(second), toPoint(apex)))
            return std::nullopt;
        for (int k = 0; k < std::abs(net); ++k) {
            cone.triangles.emplace_back(toPoint(first), toPoint(second), toPoint(apex));
            cone.winding.add(first, second, apex);
        }
    }
    return cone;
}

/// The cone from the first of a few off-centre apexes that makes one (none when every apex is
/// collinear with a boundary edge). Scaled by the longest side, so a flat soup gets its apex
/// off its plane.
std::optional<Cone> closingCone(const TriangleSoup& soup, const Boundary& boundary,
                                const glm::dvec3& center, double longest) {
    static const glm::dvec3 kApexOffsets[] = {{0.1234567, 0.0765432, 0.0312345},
                                              {-0.0917265, 0.1471013, -0.0551237},
                                              {0.0418233, -0.1127481, 0.1371139}};
    for (const glm::dvec3& offset : kApexOffsets)
        if (std::optional<Cone> cone = coneFrom(soup, boundary, center + offset * longest))
            return cone;
    return std::nullopt;
}
} // namespace

struct CgalReference::Impl {
    format::SignMethod method = format::SignMethod::Winding;
    std::vector<Triangle> triangles; ///< non-degenerate triangles of the soup (winding order kept)
    Tree tree;
    WindingSoup winding;        ///< the same triangles, for brute force
    std::vector<Triangle> cone; ///< cone K closing the soup into a cycle (empty if closed)
    Tree coneTree;
    WindingSoup coneWinding;
    bool exactCycle = false;  ///< the crossing-count shortcut is available
    double farDistance = 0.0; ///< [world units] beyond the box of M and K from any point in it
    glm::dvec3 center{0.0};
    Mesh mesh; ///< for parity only
    std::unique_ptr<SideOf> side;
    std::string fallbackReason;

    /// The AABB tree and the brute-force winding sum over `kept`, winding order kept.
    void addTriangles(const TriangleSoup& soup, const std::vector<glm::uvec3>& kept) {
        triangles.reserve(kept.size());
        for (const glm::uvec3& t : kept) {
            triangles.emplace_back(toPoint(soup.positions[t.x]), toPoint(soup.positions[t.y]),
                                   toPoint(soup.positions[t.z]));
            winding.add(soup.positions[t.x], soup.positions[t.y], soup.positions[t.z]);
        }
        tree.rebuild(triangles.begin(), triangles.end());
        tree.accelerate_distance_queries(); // build both now: queries run on many threads
    }

    /// The cone K that closes the soup into a cycle, for the crossing-count shortcut. It pays
    /// off while it is much smaller than the soup (a soup of loose triangles is all boundary).
    void closeWithCone(const TriangleSoup& soup, const Boundary& boundary, std::size_t kept,
                       double longest) {
        if (boundary.size() * 2 > kept)
            return;
        if (std::optional<Cone> closing = closingCone(soup, boundary, center, longest)) {
            cone = std::move(closing->triangles);
            coneWinding = std::move(closing->winding);
            exactCycle = true;
        }
        if (!cone.empty())
            coneTree.rebuild(cone.begin(), cone.end());
    }

    /// For parity, the closed Surface_mesh and its side test; the winding number, with the
    /// reason, when none can be made of the soup.
    void prepareParity(const TriangleSoup& soup) {
        if (method != format::SignMethod::Parity)
            return;
        fallbackReason = buildParityMesh(soup, mesh);
        if (!fallbackReason.empty()) {
            method = format::SignMethod::Winding;
            return;
        }
        side = std::make_unique<SideOf>(mesh);
        // Its AABB tree is built lazily on the first query: do that here, not in threads.
        (void)(*side)(toPoint(center));
    }

    double unsignedDistance(const Point& p) const { return std::sqrt(tree.squared_distance(p)); }
    /// The same distance, the search started from `hint` (a point of M, updated to p's closest
    /// point): the previous query's closest point bounds a neighbour's search tightly, so the
    /// tree walk prunes more. The result does not depend on the hint.
    double unsignedDistance(const Point& p, Point& hint) const {
        hint = tree.closest_point(p, hint);
        return std::sqrt(CGAL::squared_distance(p, hint));
    }

    /// Winding number of the cycle Z at p from crossings along segments to far points; false if
    /// every direction tried hit an edge or a vertex.
    bool cycleWindingByRay(const Point& p, long& w, std::vector<Tree::Primitive_id>& hits) const {
        // Directions of no special alignment with axis-aligned or symmetric meshes.
        static const glm::dvec3 kDirections[] = {{0.8134, 0.4621, 0.3532},
                                                 {-0.3411, 0.8872, -0.3109},
                                                 {0.2143, -0.5318, 0.8195},
                                                 {-0.7071, -0.1913, -0.6806}};
        const glm::dvec3 from = toGlm(p);
        const double reach = glm::length(from - center) + farDistance;
        for (const glm::dvec3& dir : kDirections) {
            const Point far = toPoint(from + glm::normalize(dir) * reach);
            long delta = 0; // W(far) = 0 = W(p) + delta
            if (addCrossings(tree, p, far, delta, hits) &&
                addCrossings(coneTree, p, far, delta, hits)) {
                w = -delta;
                return true;
            }
        }
        return false;
    }

    /// Signed distances of points [begin, end), carrying the cycle winding number from point to
    /// point. Deterministic for a given range.
    void signedRange(std::span<const glm::dvec3> points, std::size_t begin, std::size_t end,
                     double* out) const {
        std::vector<Tree::Primitive_id> hits;
        bool known = false; // W and the previous point are valid
        long w = 0;
        bool sideKnown = false; // parity: the previous point and its side are valid
        bool previousInside = false;
        Point previous;
        double previousDistance = 0.0;
        std::optional<Point> hint; // the previous point's closest point on M
        for (std::size_t i = begin; i < end; ++i) {
            const Point p = toPoint(points[i]);
            if (!hint)
                hint = tree.closest_point(p);
            const double d = unsignedDistance(p, *hint);
            if (d == 0.0) { // on the surface: no sign, and no winding number to carry
                out[i] = 0.0;
                known = false;
                sideKnown = false;
                continue;
            }
            bool inside = false;
            if (method == format::SignMethod::Parity) {
                // The open ball of radius previousDistance around the previous point holds no
                // triangle, so the segment to a point inside it crosses none: same side, no ray
                // to shoot (the points of a brick or grid row are a voxel apart, and most lie
                // farther than that from the surface). Margin for rounding, as below.
                if (sideKnown && std::sqrt(CGAL::squared_distance(p, previous)) <
                                     previousDistance * (1.0 - 1e-9))
                    inside = previousInside;
                else
                    inside = (*side)(p) == CGAL::ON_BOUNDED_SIDE;
                sideKnown = true;
                previousInside = inside;
            } else if (!exactCycle) {
                inside = winding.at(points[i]) > 0.5;
            } else {
                if (known && p != previous) {
                    long delta = 0;
                    // The ball of radius previousDistance around the previous point holds no
                    // triangle of M, so a shorter step cannot cross one (margin for rounding).
                    const bool clearOfM = std::sqrt(CGAL::squared_distance(p, previous)) <
                                          previousDistance * (1.0 - 1e-9);
                    known = (clearOfM || addCrossings(tree, previous, p, delta, hits)) &&
                            addCrossings(coneTree, previous, p, delta, hits);
                    w += delta;
                }
                if (!known)
                    known = cycleWindingByRay(p, w, hits);
                if (known) {
                    const double coneW = coneWinding.empty() ? 0.0 : coneWinding.at(points[i]);
                    inside = double(w) - coneW > 0.5;
                } else {
                    // Brute force, and recover W for the next point if the value is clean.
                    const double wm = winding.at(points[i]);
                    inside = wm > 0.5;
                    const double total =
                        wm + (coneWinding.empty() ? 0.0 : coneWinding.at(points[i]));
                    const double rounded = std::round(total);
                    if (std::abs(total - rounded) < kIntegerTolerance) {
                        w = long(rounded);
                        known = true;
                    }
                }
            }
            out[i] = inside ? -d : d;
            previous = p;
            previousDistance = d;
        }
    }
};

Result<SignMode> parseSignMode(const std::string& text) {
    if (text == "auto")
        return SignMode::Auto;
    if (text == "parity")
        return SignMode::Parity;
    if (text == "winding")
        return SignMode::Winding;
    return fail(ErrorCode::InvalidArgument,
                "unknown sign mode '" + text + "'; use auto, parity or winding");
}

const char* signModeName(SignMode mode) {
    switch (mode) {
    case SignMode::Auto:
        return "auto";
    case SignMode::Parity:
        return "parity";
    case SignMode::Winding:
        return "winding";
    }
    return "auto";
}

Result<format::SignMethod> chooseSignMethod(const format::MeshDiagnostics& diagnostics,
                                            SignMode mode) {
    if (mode == SignMode::Parity && !diagnostics.closed)
        return fail(ErrorCode::InvalidArgument,
                    "ray parity needs a closed mesh, and this one has " +
                        std::to_string(diagnostics.boundaryEdges) + " boundary and " +
                        std::to_string(diagnostics.nonManifoldEdges) +
                        " non-manifold edges; use --sign winding or auto");
    const bool parity = mode == SignMode::Parity ||
                        (mode == SignMode::Auto && diagnostics.closed && !diagnostics.selfIntersecting);
    return parity ? format::SignMethod::Parity : format::SignMethod::Winding;
}

Result<CgalReference> CgalReference::build(const TriangleSoup& soup,
                                           const format::MeshDiagnostics& diagnostics,
                                           SignMode mode) {
    Result<format::SignMethod> method = chooseSignMethod(diagnostics, mode);
    if (!method)
        return method.error();
    auto impl = std::make_unique<Impl>();
    impl->method = *method;
    std::vector<glm::uvec3> kept = nonDegenerateTriangles(soup);
    if (kept.empty())
        return fail(ErrorCode::EmptyMesh, "the mesh has no triangle of non-zero area");

    // The boundary chain: each edge's uses in one direction minus uses in the other.
    const Boundary boundary = boundaryChain(kept);
    const Box box = soup.bounds();
    impl->center = 0.5 * (box.lo + box.hi);
    orientOutward(soup, boundary, impl->center, kept);
    impl->addTriangles(soup, kept);
    const glm::dvec3 extent = box.hi - box.lo;
    impl->farDistance = 2.0 * glm::length(extent) + 1.0;
    impl->closeWithCone(soup, boundary, kept.size(),
                        std::max(extent.x, std::max(extent.y, extent.z)));
    impl->prepareParity(soup);
    return CgalReference(std::move(impl));
}

CgalReference::CgalReference(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
CgalReference::CgalReference(CgalReference&&) noexcept = default;
CgalReference& CgalReference::operator=(CgalReference&&) noexcept = default;
CgalReference::~CgalReference() = default;

format::SignMethod CgalReference::signMethod() const {
    return m_impl->method;
}

const std::string& CgalReference::signFallbackReason() const {
    return m_impl->fallbackReason;
}

double CgalReference::unsignedDistance(const glm::dvec3& p) const {
    return m_impl->unsignedDistance(toPoint(p));
}

double CgalReference::windingNumber(const glm::dvec3& p) const {
    return m_impl->winding.at(p);
}

double CgalReference::signedDistance(const glm::dvec3& p) const {
    double out = 0.0;
    m_impl->signedRange(std::span<const glm::dvec3>(&p, 1), 0, 1, &out);
    return out;
}

std::vector<double> CgalReference::signedDistances(std::span<const glm::dvec3> points,
                                                   Progress* progress) const {
    std::vector<double> out(points.size());
    // simple_partitioner splits down to kChunk exactly the same way every run.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, points.size(), kChunk),
        [&](const tbb::blocked_range<std::size_t>& r) {
            m_impl->signedRange(points, r.begin(), r.end(), out.data());
            if (progress)
                progress->add(r.size());
        },
        tbb::simple_partitioner());
    return out;
}

} // namespace sluice::bake
