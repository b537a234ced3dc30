// Test support: the neighbour mask decoded on the CPU (NeighbourRecords.h).
#include "sim/NeighbourRecords.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "shared/Pbf.h"

namespace sluice::rt::test {
namespace {

// The candidate range [begin, end) of row or bucket `cc` seen from `cell`, or false when the
// dense grid has no such row (PBF_RANGES_BEGIN's order: rows x - 1 .. x + 1 as one range on
// the dense grid, the 27 buckets on the hash).
bool rangeOf(const Simulation::NeighbourState& s, glm::ivec3 cell, glm::ivec3 cc,
             std::uint32_t& begin, std::uint32_t& end) {
    const glm::uvec3 dims = s.gridDims;
    if (dims.x == 0) {
        const std::uint32_t bucket = shared::pbfCellHash(cc, s.tableSize - 1);
        begin = s.cellStart[bucket];
        end = s.cellStart[bucket + 1];
        return true;
    }
    if (cc.y < 0 || cc.y >= int(dims.y) || cc.z < 0 || cc.z >= int(dims.z))
        return false;
    begin = s.cellStart[shared::pbfDenseBucket({std::max(cell.x - 1, 0), cc.y, cc.z}, dims)];
    end = s.cellStart[shared::pbfDenseBucket({std::min(cell.x + 1, int(dims.x) - 1), cc.y, cc.z},
                                             dims) +
                      1];
    return true;
}

} // namespace

std::vector<RecordedNeighbours> recordedNeighbours(const Simulation& sim) {
    const Simulation::NeighbourState s = sim.neighbourState();
    const std::size_t n = s.ids.size();
    std::vector<RecordedNeighbours> out(n);
    const bool dense = s.gridDims.x > 0;
    const float invH = 1.0f / s.h, h2 = s.h * s.h;
    auto cellOf = [&](glm::vec3 x) { return shared::pbfCellOf(x, s.gridOrigin, s.gridDims, invH); };
    for (std::size_t i = 0; i < n; ++i) {
        RecordedNeighbours& r = out[i];
        r.id = s.ids[i];
        r.start = glm::vec3(s.start[i]);
        const glm::ivec3 cell = cellOf(r.start);
        std::uint32_t c = 0;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= (dense ? -1 : 1); ++dx) {
                    const glm::ivec3 cc = cell + glm::ivec3(dx, dy, dz);
                    std::uint32_t begin = 0, end = 0;
                    if (!rangeOf(s, cell, cc, begin, end))
                        continue;
                    for (std::uint32_t j = begin; j < end; ++j, ++c) {
                        if (c < shared::kNeighbourMaskBits) {
                            if ((s.mask[i * shared::kNeighbourMaskWords + c / 32] >> (c % 32)) & 1u)
                                r.fromMask.push_back(s.ids[j]);
                            continue;
                        }
                        const glm::vec3 d = r.start - glm::vec3(s.start[j]);
                        if (j != i && (dense || cellOf(glm::vec3(s.start[j])) == cc) &&
                            glm::dot(d, d) < h2)
                            r.pastMask.push_back(s.ids[j]);
                    }
                }
        r.candidates = c;
    }
    return out;
}

} // namespace sluice::rt::test
