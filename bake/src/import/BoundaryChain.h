// The boundary chain of a triangle soup: edges whose directed uses do not cancel.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace sluice::bake {

/// Every edge (lo, hi) of the triangles with its net multiplicity: uses lo -> hi minus uses
/// hi -> lo. Edges that cancel are left out, so the result is empty exactly when the soup is a
/// cycle (closed and consistently oriented), whose winding number is an integer off the surface.
/// Sorted by edge, so the result does not depend on triangle order. `Tri` is indexable [0..2].
template <class Tri>
std::vector<std::pair<std::pair<std::uint64_t, std::uint64_t>, int>>
boundaryChain(const std::vector<Tri>& triangles) {
    std::vector<std::pair<std::pair<std::uint64_t, std::uint64_t>, int>> uses;
    uses.reserve(triangles.size() * 3);
    for (const Tri& t : triangles)
        for (int c = 0; c < 3; ++c) {
            const std::uint64_t u = t[c], v = t[(c + 1) % 3];
            uses.push_back({{std::min(u, v), std::max(u, v)}, u < v ? 1 : -1});
        }
    std::sort(uses.begin(), uses.end());
    std::vector<std::pair<std::pair<std::uint64_t, std::uint64_t>, int>> chain;
    for (std::size_t i = 0; i < uses.size();) {
        int net = 0;
        std::size_t j = i;
        for (; j < uses.size() && uses[j].first == uses[i].first; ++j)
            net += uses[j].second;
        if (net != 0)
            chain.push_back({uses[i].first, net});
        i = j;
    }
    return chain;
}

} // namespace sluice::bake
