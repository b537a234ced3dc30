// BVH build for the GPU bake: binned SAH splits, preorder with links, fast-winding data per node.
#include "Bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "sluice/format/Assert.h"

namespace sluice::bake {

namespace {

/// A node texel: three floats as their bits and a word (shared/SdfBake.h).
glm::uvec4 nodeTexel(const glm::dvec3& v, std::uint32_t w) {
    return {glm::floatBitsToUint(float(v.x)), glm::floatBitsToUint(float(v.y)),
            glm::floatBitsToUint(float(v.z)), w};
}
std::uint32_t linkWord(std::uint32_t index, std::uint32_t count) {
    return (index << shared::kBvhLinkShift) | count;
}

/// One triangle as the GPU sees it (corners rounded once to float), with what the build needs
/// of it in double.
struct Primitive {
    std::array<glm::dvec3, 3> corners; ///< the float corners, exactly
    glm::dvec3 lo, hi;                 ///< box
    glm::dvec3 centroid;
    glm::dvec3 areaNormal; ///< area times unit normal
    glm::dvec3 weighted;   ///< area times centroid
    double area = 0.0;
};

Primitive primitive(const BvhInputTriangle& t) {
    Primitive p;
    p.corners = {glm::dvec3(glm::vec3(t.a)), glm::dvec3(glm::vec3(t.b)),
                 glm::dvec3(glm::vec3(t.c))};
    const auto& [a, b, c] = p.corners;
    p.lo = glm::min(a, glm::min(b, c));
    p.hi = glm::max(a, glm::max(b, c));
    p.centroid = (a + b + c) / 3.0;
    // Barill et al. 2018, eq. 14: the first-order coefficient is sum a_t n_t.
    p.areaNormal = 0.5 * glm::cross(b - a, c - a);
    p.area = glm::length(p.areaNormal);
    p.weighted = p.area * p.centroid;
    return p;
}

double halfArea(const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 d = glm::max(hi - lo, glm::dvec3(0.0));
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

/// Ranges of more triangles than this build their two halves in parallel.
constexpr std::uint32_t kParallelTriangles = 4096;
/// Below this depth splits are median splits: the surface area heuristic may peel off a few
/// triangles at a time, and this bounds the tree's depth (and the build's recursion) to
/// kMaxSahDepth + log2(n).
constexpr std::uint32_t kMaxSahDepth = 48;

struct Builder {
    std::vector<Primitive> primitives; ///< input order
    std::vector<std::uint32_t> order;  ///< triangle indices, permuted into leaf order
    Bvh bvh;

    /// Halves order[begin, end) at the median centroid along the longest axis of the centroid
    /// box; (coordinate, index) is a total order, so the halves do not depend on the library.
    std::uint32_t medianSplit(std::uint32_t begin, std::uint32_t end, const glm::dvec3& clo,
                              const glm::dvec3& chi) {
        const glm::dvec3 extent = chi - clo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        const std::uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                         [&](std::uint32_t l, std::uint32_t r) {
                             const double cl = primitives[l].centroid[axis];
                             const double cr = primitives[r].centroid[axis];
                             return cl < cr || (cl == cr && l < r);
                         });
        // nth_element leaves each half in an order of the library's choosing; sort them so the
        // leaves' triangle order does not depend on it either.
        std::sort(order.begin() + begin, order.begin() + mid);
        std::sort(order.begin() + mid, order.begin() + end);
        return mid;
    }

    /// Splits order[begin, end) in two non-empty parts and returns where the second starts:
    /// binned surface area heuristic over the centroid box (Wald 2007), which gives tighter
    /// boxes than median splits and so fewer node visits per distance query; halves by index
    /// where every centroid is the same. Stable partitions, so the result depends only on the
    /// input order.
    std::uint32_t split(std::uint32_t begin, std::uint32_t end, const glm::dvec3& clo,
                        const glm::dvec3& chi, std::uint32_t depth) {
        if (depth >= kMaxSahDepth)
            return medianSplit(begin, end, clo, chi);
        constexpr int kBins = 32;
        struct Bin {
            glm::dvec3 lo{1e300}, hi{-1e300};
            std::uint32_t count = 0;
        };
        auto binOf = [&](std::uint32_t triangle, int axis) {
            const double extent = chi[axis] - clo[axis];
            const int bin = int((primitives[triangle].centroid[axis] - clo[axis]) / extent * kBins);
            return std::clamp(bin, 0, kBins - 1);
        };
        // The bins of all three axes in one pass over the triangles (the same bins as one pass
        // per axis, read from memory once).
        std::array<std::array<Bin, kBins>, 3> binsOf;
        std::array<bool, 3> splittable;
        for (int axis = 0; axis < 3; ++axis)
            splittable[axis] = chi[axis] > clo[axis];
        for (std::uint32_t n = begin; n < end; ++n) {
            const Primitive& p = primitives[order[n]];
            for (int axis = 0; axis < 3; ++axis) {
                if (!splittable[axis])
                    continue;
                Bin& bin = binsOf[axis][binOf(order[n], axis)];
                bin.lo = glm::min(bin.lo, p.lo);
                bin.hi = glm::max(bin.hi, p.hi);
                ++bin.count;
            }
        }
        double bestCost = 1e300;
        int bestAxis = -1, bestBin = 0;
        for (int axis = 0; axis < 3; ++axis) {
            if (!splittable[axis])
                continue;
            const std::array<Bin, kBins>& bins = binsOf[axis];
            // Cost of splitting after bin i: area(left) * count(left) + the same for the right.
            std::array<double, kBins> rightCost{};
            Bin right;
            for (int i = kBins - 1; i > 0; --i) {
                right.lo = glm::min(right.lo, bins[i].lo);
                right.hi = glm::max(right.hi, bins[i].hi);
                right.count += bins[i].count;
                rightCost[i - 1] =
                    right.count > 0 ? halfArea(right.lo, right.hi) * right.count : -1.0;
            }
            Bin left;
            for (int i = 0; i < kBins - 1; ++i) {
                left.lo = glm::min(left.lo, bins[i].lo);
                left.hi = glm::max(left.hi, bins[i].hi);
                left.count += bins[i].count;
                if (left.count == 0 || rightCost[i] < 0.0)
                    continue;
                const double cost = halfArea(left.lo, left.hi) * left.count + rightCost[i];
                if (cost < bestCost) {
                    bestCost = cost;
                    bestAxis = axis;
                    bestBin = i;
                }
            }
        }
        if (bestAxis < 0)
            return begin + (end - begin) / 2;
        const auto middle =
            std::stable_partition(order.begin() + begin, order.begin() + end,
                                  [&](std::uint32_t t) { return binOf(t, bestAxis) <= bestBin; });
        return std::uint32_t(middle - order.begin());
    }

    /// A subtree before it is laid out in preorder.
    struct Node {
        glm::dvec3 lo, hi, center, dipole;
        double radius = 0.0;
        std::uint32_t begin = 0, end = 0; ///< triangles order[begin, end)
        std::uint32_t size = 1;           ///< nodes in the subtree
        std::uint32_t depth = 0;          ///< levels below this node
        std::unique_ptr<Node> first, second;
    };

    /// The subtree of the triangles order[begin, end); big halves are built in parallel, which
    /// does not change the result (each half only permutes its own range of `order`).
    std::unique_ptr<Node> build(std::uint32_t begin, std::uint32_t end, std::uint32_t depth) {
        auto node = std::make_unique<Node>();
        node->begin = begin;
        node->end = end;
        // Box, centroid box and the fast-winding data, in double from the float corners.
        glm::dvec3 clo(1e300), chi(-1e300), weighted(0.0);
        node->lo = glm::dvec3(1e300);
        node->hi = glm::dvec3(-1e300);
        node->dipole = glm::dvec3(0.0);
        double area = 0.0;
        for (std::uint32_t n = begin; n < end; ++n) {
            const Primitive& p = primitives[order[n]];
            node->lo = glm::min(node->lo, p.lo);
            node->hi = glm::max(node->hi, p.hi);
            clo = glm::min(clo, p.centroid);
            chi = glm::max(chi, p.centroid);
            node->dipole += p.areaNormal;
            weighted += p.weighted;
            area += p.area;
        }
        node->center = area > 0.0 ? weighted / area : 0.5 * (node->lo + node->hi);
        double radius2 = 0.0;
        for (std::uint32_t n = begin; n < end; ++n)
            for (const glm::dvec3& corner : primitives[order[n]].corners) {
                const glm::dvec3 d = corner - node->center;
                radius2 = std::max(radius2, glm::dot(d, d));
            }
        node->radius = std::sqrt(radius2);
        if (end - begin <= std::uint32_t(shared::kBvhLeafSize))
            return node;
        const std::uint32_t mid = split(begin, end, clo, chi, depth);
        if (end - begin > kParallelTriangles) {
            tbb::parallel_invoke([&] { node->first = build(begin, mid, depth + 1); },
                                 [&] { node->second = build(mid, end, depth + 1); });
        } else {
            node->first = build(begin, mid, depth + 1);
            node->second = build(mid, end, depth + 1);
        }
        node->size = 1 + node->first->size + node->second->size;
        node->depth = 1 + std::max(node->first->depth, node->second->depth);
        return node;
    }

    /// Writes the subtree's texels from node `slot` on, in preorder.
    void layOut(const Node& node, std::uint32_t slot) {
        const bool leaf = !node.first;
        // A leaf's walk goes on at slot + 1; an internal node's skips past its subtree.
        const std::uint32_t link =
            leaf ? linkWord(node.begin, node.end - node.begin) : linkWord(slot + node.size, 0);
        const std::size_t texel = 2 * std::size_t(slot);
        // lo and hi are minima and maxima of float corners, so they convert exactly.
        bvh.distanceNodes[texel] = nodeTexel(node.lo, 0);
        bvh.distanceNodes[texel + 1] = nodeTexel(node.hi, link);
        bvh.windingNodes[texel] =
            nodeTexel(node.center, glm::floatBitsToUint(float(node.radius * (1.0 + 1e-6))));
        bvh.windingNodes[texel + 1] = nodeTexel(node.dipole, link);
        if (!leaf) {
            layOut(*node.first, slot + 1);
            layOut(*node.second, slot + 1 + node.first->size);
        }
    }
};

} // namespace

Bvh buildBvh(std::span<const BvhInputTriangle> input) {
    SLUICE_ASSERT(!input.empty(), "buildBvh: no triangles");
    SLUICE_ASSERT(input.size() < kBvhMaxTriangles, "buildBvh: too many triangles");
    Builder builder;
    builder.primitives.resize(input.size());
    tbb::parallel_for(std::size_t(0), input.size(),
                      [&](std::size_t n) { builder.primitives[n] = primitive(input[n]); });
    builder.order.resize(input.size());
    std::iota(builder.order.begin(), builder.order.end(), 0u);
    const std::unique_ptr<Builder::Node> root = builder.build(0, std::uint32_t(input.size()), 0);

    Bvh& bvh = builder.bvh;
    bvh.nodeCount = root->size;
    bvh.depth = root->depth;
    bvh.distanceNodes.resize(2 * std::size_t(bvh.nodeCount));
    bvh.windingNodes.resize(2 * std::size_t(bvh.nodeCount));
    builder.layOut(*root, 0);
    bvh.triangleCount = std::uint32_t(input.size());
    bvh.triangles.reserve(3 * input.size());
    for (std::uint32_t index : builder.order)
        for (const glm::dvec3& corner : builder.primitives[index].corners)
            bvh.triangles.push_back(glm::vec4(glm::vec3(corner), 0.0f));
    return std::move(bvh);
}

} // namespace sluice::bake
