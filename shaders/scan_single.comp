// Exclusive prefix sum of up to kScanSingleThreads x kScanSingleRun uints in one work group and
// one dispatch, for the small grids where the block scan's three dispatches and barriers cost
// more than the work: each invocation sums a run of consecutive elements, the runs' totals are
// scanned in shared memory (Hillis and Steele 1986), and each invocation writes its run's
// prefixes. Same inputs as scan_block.comp: elements from inputCount on read as 0, and with
// clearInput each input element is zeroed once read.
#version 450 core

#include "shared/Pbf.h"

layout(local_size_x = kScanSingleThreads) in;

layout(std430, binding = kBindScanInput) buffer Input { uint src[]; };
layout(std430, binding = kBindScanData) writeonly buffer Data { uint data[]; };

uniform uint count;      // elements in data, at most kScanSingleThreads x kScanSingleRun
uniform uint inputCount; // elements of src read, at most count
uniform uint clearInput; // 1: zero each src element read (src is not data)

shared uint runTotal[kScanSingleThreads];

void main() {
    uint t = gl_LocalInvocationID.x;
    uint run = (count + kScanSingleThreads - 1u) / kScanSingleThreads;
    uint first = t * run;
    uint last = min(first + run, inputCount);
    uint sum = 0u;
    for (uint a = first; a < last; ++a)
        sum += src[a];
    runTotal[t] = sum;
    for (uint offset = 1u; offset < kScanSingleThreads; offset <<= 1u) {
        barrier();
        uint add = t >= offset ? runTotal[t - offset] : 0u;
        barrier();
        runTotal[t] += add;
    }
    barrier();
    uint prefix = t > 0u ? runTotal[t - 1u] : 0u;
    uint end = min(first + run, count);
    for (uint a = first; a < end; ++a) {
        uint value = a < inputCount ? src[a] : 0u; // read before data[a], which may be src[a]
        if (clearInput != 0u && a < inputCount)
            src[a] = 0u;
        data[a] = prefix;
        prefix += value;
    }
}
