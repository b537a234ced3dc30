// BVH build for the GPU bake: median splits, preorder with skip links, fast-winding data per node.
#include "Bvh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>

#include "sluice/format/Assert.h"

namespace sluice::bake {

namespace {

glm::vec4 toVec4(const glm::dvec3& v) {
    return {float(v.x), float(v.y), float(v.z), 0.0f};
}
glm::dvec3 toDvec3(const glm::vec4& v) {
    return {v.x, v.y, v.z};
}

struct Builder {
    std::span<const BvhInputTriangle> input;
    std::vector<shared::BvhTriangle> floats; ///< input order, rounded once to float
    std::vector<glm::dvec3> centroids;
    std::vector<std::uint32_t> order; ///< triangle indices, permuted into leaf order
    Bvh bvh;

    /// Appends the subtree of the triangles order[begin, end) in preorder.
    void build(std::uint32_t begin, std::uint32_t end, std::uint32_t depth) {
        bvh.depth = std::max(bvh.depth, depth);
        const std::uint32_t slot = std::uint32_t(bvh.nodes.size());
        bvh.nodes.emplace_back();
        // Box, centroid box and the fast-winding data, in double from the float corners.
        glm::dvec3 lo(1e300), hi(-1e300), clo(1e300), chi(-1e300);
        glm::dvec3 dipole(0.0), weighted(0.0);
        double area = 0.0;
        for (std::uint32_t n = begin; n < end; ++n) {
            const shared::BvhTriangle& t = floats[order[n]];
            const glm::dvec3 a = toDvec3(t.a), b = toDvec3(t.b), c = toDvec3(t.c);
            lo = glm::min(lo, glm::min(a, glm::min(b, c)));
            hi = glm::max(hi, glm::max(a, glm::max(b, c)));
            clo = glm::min(clo, centroids[order[n]]);
            chi = glm::max(chi, centroids[order[n]]);
            // Barill et al. 2018, eq. 14: the first-order coefficient is sum a_t n_t.
            const glm::dvec3 areaNormal = 0.5 * glm::cross(b - a, c - a);
            const double triangleArea = glm::length(areaNormal);
            dipole += areaNormal;
            weighted += triangleArea * (a + b + c) / 3.0;
            area += triangleArea;
        }
        const glm::dvec3 center = area > 0.0 ? weighted / area : 0.5 * (lo + hi);
        double radius = 0.0;
        for (std::uint32_t n = begin; n < end; ++n) {
            const shared::BvhTriangle& t = floats[order[n]];
            for (const glm::vec4& corner : {t.a, t.b, t.c})
                radius = std::max(radius, glm::length(toDvec3(corner) - center));
        }
        shared::BvhNode node{};
        // lo and hi are minima and maxima of float corners, so they convert exactly.
        node.boxMin = glm::vec4(float(lo.x), float(lo.y), float(lo.z), 0.0f);
        node.boxMax = glm::vec4(float(hi.x), float(hi.y), float(hi.z), 0.0f);
        node.center = glm::vec4(float(center.x), float(center.y), float(center.z),
                                float(radius * (1.0 + 1e-6)));
        node.dipole = toVec4(dipole);

        const std::uint32_t count = end - begin;
        if (count <= std::uint32_t(shared::kBvhLeafSize)) {
            node.first = begin;
            node.count = count;
            node.skip = slot + 1;
            bvh.nodes[slot] = node;
            return;
        }
        // Median split on the longest axis of the centroid box; (coordinate, index) is a total
        // order, so nth_element's result does not depend on the library's pivot choices.
        const glm::dvec3 extent = chi - clo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        const std::uint32_t mid = begin + count / 2;
        std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                         [&](std::uint32_t l, std::uint32_t r) {
                             const double cl = centroids[l][axis], cr = centroids[r][axis];
                             return cl < cr || (cl == cr && l < r);
                         });
        build(begin, mid, depth + 1);
        node.first = std::uint32_t(bvh.nodes.size());
        build(mid, end, depth + 1);
        node.count = 0;
        node.skip = std::uint32_t(bvh.nodes.size());
        bvh.nodes[slot] = node;
    }
};

} // namespace

Bvh buildBvh(std::span<const BvhInputTriangle> input) {
    SLUICE_ASSERT(!input.empty(), "buildBvh: no triangles");
    SLUICE_ASSERT(input.size() < (std::size_t(1) << 31), "buildBvh: too many triangles");
    Builder builder{.input = input};
    builder.floats.reserve(input.size());
    builder.centroids.reserve(input.size());
    for (const BvhInputTriangle& t : input) {
        shared::BvhTriangle f{toVec4(t.a), toVec4(t.b), toVec4(t.c)};
        builder.floats.push_back(f);
        builder.centroids.push_back((toDvec3(f.a) + toDvec3(f.b) + toDvec3(f.c)) / 3.0);
    }
    builder.order.resize(input.size());
    std::iota(builder.order.begin(), builder.order.end(), 0u);
    builder.bvh.nodes.reserve(input.size()); // fewer nodes than triangles (leaves hold >= 2)
    builder.build(0, std::uint32_t(input.size()), 0);
    builder.bvh.triangles.reserve(input.size());
    for (std::uint32_t index : builder.order)
        builder.bvh.triangles.push_back(builder.floats[index]);
    return std::move(builder.bvh);
}

} // namespace sluice::bake
