// PBF step 2 and the counting half of the neighbour sort (docs/pbf.md): apply gravity, predict
// x*, and count every particle into the hash bucket of its cell (the scan of the last substep
// left the counts at zero). A particle removed (in a drain box, its id listed, or removed
// before) counts into the bucket after the last instead, so the sort puts it after the live
// ones (docs/embedding.md, "Removing particles"). Invocation 0 also opens the substep's solve:
// every iteration's indirect group counts, no stop yet, empty error sums; the CPU uploads
// nothing per substep.
#version 450 core

#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPosIn) readonly buffer PosIn { vec4 pos[]; };
layout(std430, binding = kBindVelIn) buffer VelIn { vec4 vel[]; };
layout(std430, binding = kBindPredOut) writeonly buffer PredOut { vec4 pred[]; };
layout(std430, binding = kBindCellCount) buffer CellCount { uint cellCount[]; };
layout(std430, binding = kBindHash) writeonly buffer Hash { uint hash[]; };
layout(std430, binding = kBindRank) writeonly buffer Rank { uint rank[]; };
layout(std430, binding = kBindStats) buffer Stats {
    PbfStats stats;
    PbfIterationStats iterations[];
};
layout(std430, binding = kBindSolveArgs) writeonly buffer SolveArgs { PbfDispatchArgs args[]; };
layout(std430, binding = kBindIdIn) readonly buffer IdIn { uint ids[]; };
layout(std430, binding = kBindRemoveIds) readonly buffer RemoveIds { uint removeIds[]; };

// Whether particle i at x leaves this substep: removed before (marked w = 1 by the reorder),
// inside a drain box, or its id in the ascending removal list.
bool removed(uint i, vec3 x) {
    if (pos[i].w != 0.0)
        return true;
    for (uint d = 0u; d < P.drainCount; ++d)
        if (all(greaterThanEqual(x, P.drainMin[d].xyz)) && all(lessThan(x, P.drainMax[d].xyz)))
            return true;
    uint lo = 0u, hi = P.removeIdCount;
    uint id = ids[i];
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (removeIds[mid] < id)
            lo = mid + 1u;
        else
            hi = mid;
    }
    return lo < P.removeIdCount && removeIds[lo] == id;
}

// What pbf_lambda.comp and pbf_delta.comp start each substep from. Nothing else in this pass
// touches these words.
void openSolve() {
    uint groups = (PBF_COUNT * kPbfLanes + kPbfLocalSize - 1u) / kPbfLocalSize;
    for (uint it = 0u; it < P.maxIterations; ++it) {
        for (uint c = 0u; c < P.solveChunks; ++c) {
            uint first = c * kPbfMaxGroupsPerDispatch;
            uint n = first < groups ? min(groups - first, kPbfMaxGroupsPerDispatch) : 0u;
            args[it * P.solveChunks + c] = PbfDispatchArgs(n, 1u, 1u);
        }
        iterations[it] = PbfIterationStats(0u, 0u, 0u, 0u);
    }
    stats.stopIteration = kPbfNoStop;
}

void main() {
    uint i = SLUICE_GLOBAL_ID.x;
    if (i == 0u)
        openSolve();
    if (i >= PBF_COUNT)
        return;
    if (P.removal != 0u && removed(i, pos[i].xyz)) {
        vel[i] = vec4(0.0);
        pred[i] = vec4(pos[i].xyz, 0.0);
        hash[i] = P.activeBuckets;
        rank[i] = atomicAdd(cellCount[P.activeBuckets], 1u);
        return;
    }
    vec3 v = vel[i].xyz + PBF_DT * P.gravity;
    vec3 x = pos[i].xyz + PBF_DT * v;
    if (!allFinite(x) || !allFinite(v)) {
        // Keep NaN and infinity out of the neighbour search: the particle stays where it was,
        // at rest, and is counted (docs/pbf.md step 5 does the same after the solve).
        x = pos[i].xyz;
        v = vec3(0.0);
        atomicAdd(stats.nonFinite, 1u);
    }
    vel[i] = vec4(v, vel[i].w);
    pred[i] = vec4(x, 0.0);
    uint bucket = cellBucket(cellOf(x));
    hash[i] = bucket;
    // The rank depends on scheduling; pbf_bucket_sort.comp restores a fixed order when the run
    // must be deterministic.
    rank[i] = atomicAdd(cellCount[bucket], 1u);
}
