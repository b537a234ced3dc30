// The GPU bake's BVH (bake/src/gpu/Bvh.h): every triangle in exactly one leaf, boxes that are the
// union of what they hold, balls that hold every corner, the fast-winding sums, links that walk
// the tree in preorder, and the same arrays on every build.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gpu/Bvh.h"

namespace sluice::bake {
namespace {

glm::vec3 texelFloats(const glm::uvec4& t) {
    return {glm::uintBitsToFloat(t.x), glm::uintBitsToFloat(t.y), glm::uintBitsToFloat(t.z)};
}
std::uint32_t linkCount(std::uint32_t link) {
    return link & ((1u << shared::kBvhLinkShift) - 1u);
}
std::uint32_t linkIndex(std::uint32_t link) {
    return link >> shared::kBvhLinkShift;
}

/// Random small triangles in a 100-voxel box, a run of identical ones (every centroid equal:
/// the split falls back to halves) and zero-area ones (a repeated corner, three on a line).
std::vector<BvhInputTriangle> soup(std::uint32_t seed, int count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> where(0.0, 100.0), offset(-2.0, 2.0);
    std::vector<BvhInputTriangle> t;
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 a(where(rng), where(rng), where(rng));
        t.push_back({a, a + glm::dvec3(offset(rng), offset(rng), offset(rng)),
                     a + glm::dvec3(offset(rng), offset(rng), offset(rng))});
    }
    for (int i = 0; i < 40; ++i)
        t.push_back({{1, 2, 3}, {2, 2, 3}, {1, 3, 3}});
    t.push_back({{5, 5, 5}, {5, 5, 5}, {6, 5, 5}});
    t.push_back({{5, 5, 5}, {6, 6, 6}, {7, 7, 7}});
    return t;
}

struct Subtree {
    std::uint32_t begin = 0, end = 0; ///< triangles in leaf order
    std::uint32_t next = 0;           ///< the node after the subtree in preorder
};

/// Checks node n's subtree against the triangles it holds and returns their range.
Subtree check(const Bvh& bvh, std::uint32_t n, std::uint32_t depth, std::uint32_t& maxDepth) {
    maxDepth = std::max(maxDepth, depth);
    const glm::uvec4 lo = bvh.distanceNodes[2 * n], hi = bvh.distanceNodes[2 * n + 1];
    const glm::uvec4 ball = bvh.windingNodes[2 * n], dipole = bvh.windingNodes[2 * n + 1];
    EXPECT_EQ(hi.w, dipole.w) << "node " << n << ": the two node arrays share links";
    Subtree s;
    if (linkCount(hi.w) != 0) {
        EXPECT_LE(linkCount(hi.w), std::uint32_t(shared::kBvhLeafSize));
        s = {linkIndex(hi.w), linkIndex(hi.w) + linkCount(hi.w), n + 1};
    } else {
        EXPECT_LT(n + 1, bvh.nodeCount);
        const Subtree first = check(bvh, n + 1, depth + 1, maxDepth);
        const Subtree second = check(bvh, first.next, depth + 1, maxDepth);
        EXPECT_EQ(first.end, second.begin) << "node " << n << ": children hold adjacent ranges";
        EXPECT_EQ(linkIndex(hi.w), second.next) << "node " << n << ": skip link";
        s = {first.begin, second.end, second.next};
    }
    // The box is the union of the float corners; the ball holds each of them; the dipole is
    // the sum of the area-weighted normals (Barill et al. 2018).
    glm::vec3 boxLo(3e38f), boxHi(-3e38f);
    glm::dvec3 sum(0.0);
    const glm::vec3 center = texelFloats(ball);
    const float radius = glm::uintBitsToFloat(ball.w);
    for (std::uint32_t t = s.begin; t < s.end; ++t) {
        const glm::vec3 a(bvh.triangles[3 * t]), b(bvh.triangles[3 * t + 1]),
            c(bvh.triangles[3 * t + 2]);
        for (const glm::vec3& corner : {a, b, c}) {
            boxLo = glm::min(boxLo, corner);
            boxHi = glm::max(boxHi, corner);
            // Up to the rounding of the centre to float.
            EXPECT_LE(glm::distance(glm::dvec3(corner), glm::dvec3(center)),
                      double(radius) + 1e-6 * (1.0 + glm::length(glm::dvec3(center))))
                << "node " << n << ", triangle " << t;
        }
        sum += 0.5 * glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
    }
    EXPECT_EQ(texelFloats(lo), boxLo) << "node " << n;
    EXPECT_EQ(texelFloats(hi), boxHi) << "node " << n;
    const glm::dvec3 stored(texelFloats(dipole));
    EXPECT_LE(glm::length(stored - sum), 1e-5 * (1.0 + glm::length(sum))) << "node " << n;
    return s;
}

TEST(Bvh, HoldsEveryTriangleOnceInBoxesAndBallsThatFitWithPreorderLinks) {
    const std::vector<BvhInputTriangle> input = soup(7, 20000);
    const Bvh bvh = buildBvh(input);
    ASSERT_EQ(bvh.triangleCount, input.size());
    ASSERT_EQ(bvh.triangles.size(), 3 * input.size());
    EXPECT_LT(bvh.nodeCount, 2 * input.size());
    ASSERT_EQ(bvh.distanceNodes.size(), 2 * std::size_t(bvh.nodeCount));

    std::uint32_t maxDepth = 0;
    const Subtree root = check(bvh, 0, 0, maxDepth);
    EXPECT_EQ(root.begin, 0u);
    EXPECT_EQ(root.end, bvh.triangleCount);
    EXPECT_EQ(root.next, bvh.nodeCount) << "the walk ends past the last node";
    EXPECT_EQ(maxDepth, bvh.depth);
    // SAH splits of random triangles stay near log2(n / leaf size) = 12 levels.
    EXPECT_LE(bvh.depth, 30u);

    // Every input triangle, rounded to float, is in the leaves exactly as often as in the input.
    using Key = std::tuple<float, float, float, float, float, float, float, float, float>;
    auto key = [](const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
        return Key{a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
    };
    std::map<Key, int> count;
    for (const BvhInputTriangle& t : input)
        ++count[key(glm::vec3(t.a), glm::vec3(t.b), glm::vec3(t.c))];
    for (std::uint32_t t = 0; t < bvh.triangleCount; ++t)
        --count[key(glm::vec3(bvh.triangles[3 * t]), glm::vec3(bvh.triangles[3 * t + 1]),
                    glm::vec3(bvh.triangles[3 * t + 2]))];
    for (const auto& [k, c] : count)
        ASSERT_EQ(c, 0);
}

TEST(Bvh, BuildsTheSameArraysEveryTime) {
    const std::vector<BvhInputTriangle> input = soup(11, 30000);
    const Bvh first = buildBvh(input);
    for (int run = 0; run < 3; ++run) {
        const Bvh again = buildBvh(input);
        EXPECT_EQ(again.distanceNodes, first.distanceNodes);
        EXPECT_EQ(again.windingNodes, first.windingNodes);
        EXPECT_EQ(again.triangles, first.triangles);
    }
}

TEST(Bvh, OneTriangleIsOneLeaf) {
    const std::vector<BvhInputTriangle> input = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
    const Bvh bvh = buildBvh(input);
    EXPECT_EQ(bvh.nodeCount, 1u);
    EXPECT_EQ(bvh.depth, 0u);
    EXPECT_EQ(linkCount(bvh.distanceNodes[1].w), 1u);
    EXPECT_EQ(texelFloats(bvh.distanceNodes[0]), glm::vec3(0.0f));
    EXPECT_EQ(texelFloats(bvh.distanceNodes[1]), glm::vec3(1.0f, 1.0f, 0.0f));
}

} // namespace
} // namespace sluice::bake
