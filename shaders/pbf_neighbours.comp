// Neighbour mask of each particle (docs/pbf.md step 3), once per substep after the sort: one
// bit per candidate of its cell ranges, set for the candidates in N(i). Every later neighbour
// pass of the substep visits only those (PBF_NEIGHBOURS_BEGIN).
#version 450 core

#include "shared/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPredStart) readonly buffer PredStart { vec4 predStart[]; };
layout(std430, binding = kBindCellCount) readonly buffer CellCount { uint cellCount[]; };
layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindNeighbourMask) writeonly buffer Mask { uint mask[]; };
layout(std430, binding = kBindStats) buffer Stats { PbfStats stats; };

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i >= PBF_COUNT)
        return;
    vec3 startI = predStart[i].xyz;
    uint maskBase = i * kNeighbourMaskWords;
    // Candidates come in increasing order, so each word is complete when the next begins.
    uint word = 0u, bits = 0u, neighbours = 0u;
    PBF_RANGES_BEGIN(predStart, i)
        for (uint j = begin_; j < end_; ++j) {
            uint c = pbfBase_ + (j - begin_);
            if (c >= kNeighbourMaskBits)
                break;
            if ((c >> 5u) != word) {
                mask[maskBase + word] = bits;
                word = c >> 5u;
                bits = 0u;
            }
            if (pbfIsNeighbour(startI, predStart[j].xyz, i, j, pbfDense_, cc_)) {
                bits |= 1u << (c & 31u);
                ++neighbours;
            }
        }
    PBF_RANGES_END
    uint candidates = pbfBase_;
    // The words after the last candidate: the one being filled, then zeros.
    for (; word < kNeighbourMaskWords; ++word) {
        mask[maskBase + word] = bits;
        bits = 0u;
    }
    if (candidates > kNeighbourMaskBits)
        atomicAdd(stats.maskOverflow, 1u);
    atomicMax(stats.maxCandidates, candidates);
    atomicMax(stats.maxNeighbours, neighbours);
}
