// BVH build for the GPU bake: binned SAH splits, preorder with links, fast-winding data per node.
//
// The build works on one 64-byte record per triangle (its float corners and double centroid),
// kept in leaf order: each split partitions its own range of the records in place, so every
// level reads its triangles contiguously and nothing is allocated per node. Boxes and the
// fast-winding sums of an internal node are combined from its children; only the radius of the
// ball around a node's centroid takes a pass over the node's corners.
#include "gpu/Bvh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "sluice/format/support/Assert.h"

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

/// One triangle as the GPU sees it: corners rounded once to float, the centroid of those in
/// double, and its index in the input.
struct Ref {
    glm::vec3 a, b, c;
    std::uint32_t index = 0;
    glm::dvec3 centroid;
};
static_assert(sizeof(Ref) == 64, "one cache line per triangle");

glm::vec3 refLo(const Ref& r) {
    return glm::min(r.a, glm::min(r.b, r.c));
}
glm::vec3 refHi(const Ref& r) {
    return glm::max(r.a, glm::max(r.b, r.c));
}

double halfArea(const glm::vec3& lo, const glm::vec3& hi) {
    const glm::dvec3 d = glm::max(glm::dvec3(hi) - glm::dvec3(lo), glm::dvec3(0.0));
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

/// Ranges of more triangles than this build their two halves in parallel.
constexpr std::uint32_t kParallelTriangles = 4096;
/// Below this depth splits are median splits: the surface area heuristic may peel off a few
/// triangles at a time, and this bounds the tree's depth (and the build's recursion) to
/// kMaxSahDepth + log2(n).
constexpr std::uint32_t kMaxSahDepth = 48;
constexpr int kBins = 32;

/// A node before it is laid out in preorder.
struct Node {
    glm::vec3 lo{0.0f}, hi{0.0f};
    glm::dvec3 center{0.0}, dipole{0.0}, weighted{0.0};
    double area = 0.0, radius = 0.0;
    std::uint32_t begin = 0, end = 0;  ///< triangles refs[begin, end)
    std::uint32_t first = 0, second = 0; ///< children (0: a leaf; node 0 is the root)
    std::uint32_t size = 1;            ///< nodes in the subtree
    std::uint32_t depth = 0;           ///< levels below this node
};

struct Builder {
    std::vector<Ref> refs;    ///< in leaf order once built
    std::vector<Ref> scratch; ///< the same size: each split's stable partition goes through it
    std::vector<Node> nodes;  ///< fewer than 2 n
    std::atomic<std::uint32_t> nodeCount{1};

    /// Halves refs[begin, end) at the median centroid along the longest axis of the centroid box;
    /// (coordinate, index) is a total order, so the halves do not depend on the library.
    std::uint32_t medianSplit(std::uint32_t begin, std::uint32_t end, const glm::dvec3& clo,
                              const glm::dvec3& chi) {
        const glm::dvec3 extent = chi - clo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        auto less = [axis](const Ref& l, const Ref& r) {
            return l.centroid[axis] < r.centroid[axis] ||
                   (l.centroid[axis] == r.centroid[axis] && l.index < r.index);
        };
        const std::uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(refs.begin() + begin, refs.begin() + mid, refs.begin() + end, less);
        // nth_element leaves each half in an order of the library's choosing; sort them by input
        // index so the leaves' triangle order does not depend on it either.
        auto byIndex = [](const Ref& l, const Ref& r) { return l.index < r.index; };
        std::sort(refs.begin() + begin, refs.begin() + mid, byIndex);
        std::sort(refs.begin() + mid, refs.begin() + end, byIndex);
        return mid;
    }

    /// Splits refs[begin, end) in two non-empty parts and returns where the second starts: binned
    /// surface area heuristic over the centroid box (Wald 2007), which gives tighter boxes than
    /// median splits and so fewer node visits per distance query; halves where every centroid is
    /// the same. Stable partitions, so the result depends only on the input order.
    std::uint32_t split(std::uint32_t begin, std::uint32_t end, const glm::dvec3& clo,
                        const glm::dvec3& chi, std::uint32_t depth) {
        if (depth >= kMaxSahDepth)
            return medianSplit(begin, end, clo, chi);
        struct Bin {
            glm::vec3 lo{3e38f}, hi{-3e38f};
            std::uint32_t count = 0;
        };
        glm::dvec3 scale(0.0);
        std::array<bool, 3> splittable;
        for (int axis = 0; axis < 3; ++axis) {
            splittable[axis] = chi[axis] > clo[axis];
            scale[axis] = splittable[axis] ? kBins / (chi[axis] - clo[axis]) : 0.0;
        }
        auto binOf = [&](const Ref& r, int axis) {
            return std::clamp(int((r.centroid[axis] - clo[axis]) * scale[axis]), 0, kBins - 1);
        };
        // The bins of all three axes in one pass over the triangles.
        std::array<std::array<Bin, kBins>, 3> binsOf;
        for (std::uint32_t n = begin; n < end; ++n) {
            const Ref& r = refs[n];
            const glm::vec3 lo = refLo(r), hi = refHi(r);
            for (int axis = 0; axis < 3; ++axis) {
                Bin& bin = binsOf[axis][binOf(r, axis)];
                bin.lo = glm::min(bin.lo, lo);
                bin.hi = glm::max(bin.hi, hi);
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
        // Stable partition: the right side goes through the scratch range of the same triangles.
        std::uint32_t left = begin, rightCount = 0;
        for (std::uint32_t n = begin; n < end; ++n) {
            if (binOf(refs[n], bestAxis) <= bestBin)
                refs[left++] = refs[n];
            else
                scratch[begin + rightCount++] = refs[n];
        }
        std::copy_n(scratch.begin() + begin, rightCount, refs.begin() + left);
        return left;
    }

    /// The leaf's data from its triangles: box, fast-winding sums (Barill et al. 2018, eq. 14:
    /// the first-order coefficient is sum a_t n_t) from the float corners, in double.
    void leafData(Node& node) const {
        node.lo = glm::vec3(3e38f);
        node.hi = glm::vec3(-3e38f);
        for (std::uint32_t n = node.begin; n < node.end; ++n) {
            const Ref& r = refs[n];
            node.lo = glm::min(node.lo, refLo(r));
            node.hi = glm::max(node.hi, refHi(r));
            const glm::dvec3 a(r.a), b(r.b), c(r.c);
            const glm::dvec3 areaNormal = 0.5 * glm::cross(b - a, c - a);
            const double area = glm::length(areaNormal);
            node.dipole += areaNormal;
            node.weighted += area * r.centroid;
            node.area += area;
        }
    }

    /// Centroid of the node's area and the radius of the ball around it holding its corners.
    void ball(Node& node) const {
        node.center = node.area > 0.0 ? node.weighted / node.area
                                      : 0.5 * (glm::dvec3(node.lo) + glm::dvec3(node.hi));
        double radius2 = 0.0;
        for (std::uint32_t n = node.begin; n < node.end; ++n)
            for (const glm::vec3& corner : {refs[n].a, refs[n].b, refs[n].c}) {
                const glm::dvec3 d = glm::dvec3(corner) - node.center;
                radius2 = std::max(radius2, glm::dot(d, d));
            }
        node.radius = std::sqrt(radius2);
    }

    /// Builds node `slot`, the subtree of refs[begin, end) whose centroid box is [clo, chi]; big
    /// halves are built in parallel, which does not change the result (each half only permutes
    /// its own range of the records, and the layout follows the tree, not the node slots).
    void build(std::uint32_t slot, std::uint32_t begin, std::uint32_t end, const glm::dvec3& clo,
               const glm::dvec3& chi, std::uint32_t depth) {
        Node& node = nodes[slot];
        node.begin = begin;
        node.end = end;
        if (end - begin <= std::uint32_t(shared::kBvhLeafSize)) {
            leafData(node);
            ball(node);
            return;
        }
        const std::uint32_t mid = split(begin, end, clo, chi, depth);
        // The halves' centroid boxes.
        auto centroidBox = [&](std::uint32_t from, std::uint32_t to, glm::dvec3& lo,
                               glm::dvec3& hi) {
            lo = glm::dvec3(1e300);
            hi = glm::dvec3(-1e300);
            for (std::uint32_t n = from; n < to; ++n) {
                lo = glm::min(lo, refs[n].centroid);
                hi = glm::max(hi, refs[n].centroid);
            }
        };
        glm::dvec3 lo1, hi1, lo2, hi2;
        centroidBox(begin, mid, lo1, hi1);
        centroidBox(mid, end, lo2, hi2);
        node.first = nodeCount.fetch_add(2);
        node.second = node.first + 1;
        if (end - begin > kParallelTriangles) {
            tbb::parallel_invoke([&] { build(node.first, begin, mid, lo1, hi1, depth + 1); },
                                 [&] { build(node.second, mid, end, lo2, hi2, depth + 1); });
        } else {
            build(node.first, begin, mid, lo1, hi1, depth + 1);
            build(node.second, mid, end, lo2, hi2, depth + 1);
        }
        const Node& a = nodes[node.first];
        const Node& b = nodes[node.second];
        node.lo = glm::min(a.lo, b.lo);
        node.hi = glm::max(a.hi, b.hi);
        node.dipole = a.dipole + b.dipole;
        node.weighted = a.weighted + b.weighted;
        node.area = a.area + b.area;
        ball(node);
        node.size = 1 + a.size + b.size;
        node.depth = 1 + std::max(a.depth, b.depth);
    }

    /// Writes the texels of the subtree of `node` from preorder slot `slot` on.
    void layOut(Bvh& bvh, const Node& node, std::uint32_t slot) const {
        const bool leaf = node.first == 0;
        // A leaf's walk goes on at slot + 1; an internal node's skips past its subtree.
        const std::uint32_t link =
            leaf ? linkWord(node.begin, node.end - node.begin) : linkWord(slot + node.size, 0);
        const std::size_t texel = 2 * std::size_t(slot);
        bvh.distanceNodes[texel] = nodeTexel(node.lo, 0);
        bvh.distanceNodes[texel + 1] = nodeTexel(node.hi, link);
        bvh.windingNodes[texel] =
            nodeTexel(node.center, glm::floatBitsToUint(float(node.radius * (1.0 + 1e-6))));
        bvh.windingNodes[texel + 1] = nodeTexel(node.dipole, link);
        if (!leaf) {
            layOut(bvh, nodes[node.first], slot + 1);
            layOut(bvh, nodes[node.second], slot + 1 + nodes[node.first].size);
        }
    }
};

} // namespace

Bvh buildBvh(std::span<const BvhInputTriangle> input) {
    SLUICE_ASSERT(!input.empty(), "buildBvh: no triangles");
    SLUICE_ASSERT(input.size() < kBvhMaxTriangles, "buildBvh: too many triangles");
    Builder builder;
    builder.refs.resize(input.size());
    builder.scratch.resize(input.size());
    builder.nodes.resize(2 * input.size());
    tbb::parallel_for(std::size_t(0), input.size(), [&](std::size_t n) {
        Ref& r = builder.refs[n];
        r.a = glm::vec3(input[n].a);
        r.b = glm::vec3(input[n].b);
        r.c = glm::vec3(input[n].c);
        r.index = std::uint32_t(n);
        r.centroid = (glm::dvec3(r.a) + glm::dvec3(r.b) + glm::dvec3(r.c)) / 3.0;
    });
    glm::dvec3 clo(1e300), chi(-1e300);
    for (const Ref& r : builder.refs) {
        clo = glm::min(clo, r.centroid);
        chi = glm::max(chi, r.centroid);
    }
    builder.build(0, 0, std::uint32_t(input.size()), clo, chi, 0);

    Bvh bvh;
    const Node& root = builder.nodes[0];
    bvh.nodeCount = root.size;
    bvh.depth = root.depth;
    bvh.distanceNodes.resize(2 * std::size_t(bvh.nodeCount));
    bvh.windingNodes.resize(2 * std::size_t(bvh.nodeCount));
    builder.layOut(bvh, root, 0);
    bvh.triangleCount = std::uint32_t(input.size());
    bvh.triangles.resize(3 * input.size());
    for (std::size_t n = 0; n < builder.refs.size(); ++n) {
        const Ref& r = builder.refs[n];
        bvh.triangles[3 * n] = glm::vec4(r.a, 0.0f);
        bvh.triangles[3 * n + 1] = glm::vec4(r.b, 0.0f);
        bvh.triangles[3 * n + 2] = glm::vec4(r.c, 0.0f);
    }
    return bvh;
}

} // namespace sluice::bake
