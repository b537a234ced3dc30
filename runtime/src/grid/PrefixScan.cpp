// Block scan: level 0 scans the data; its add pass sums the block totals before each block, or,
// past m_reducedBlocks blocks, level l + 1 scans level l's totals first (recursively).
#include "grid/PrefixScan.h"

#include <algorithm>
#include <string>

#include "shared/Pbf.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {

namespace {
constexpr std::uint64_t kMaxGroupsPerDispatch = shared::kPbfMaxGroupsPerDispatch;

std::uint32_t blocksFor(std::uint32_t count) {
    return (count + shared::kScanBlock - 1) / shared::kScanBlock;
}
} // namespace

Result<PrefixScan> PrefixScan::create(std::uint32_t maxCount, std::uint32_t reducedBlocks) {
    PrefixScan scan;
    scan.m_reducedBlocks = std::max(reducedBlocks, 1u);
    const struct {
        gpu::Program* program;
        const char* name;
    } passes[] = {{&scan.m_block, "scan_block.comp"}, {&scan.m_add, "scan_add.comp"}};
    for (const auto& pass : passes) {
        auto program = gpu::Program::compute(pass.name, shaders::shaderSource(pass.name));
        if (!program)
            return program.error();
        *pass.program = std::move(*program);
    }
    std::uint32_t n = maxCount;
    do {
        n = blocksFor(n);
        auto sums = gpu::Buffer::create(std::size_t(n) * sizeof(std::uint32_t),
                                        "scan sums " + std::to_string(scan.m_sums.size()));
        if (!sums)
            return sums.error();
        scan.m_sums.push_back(std::move(*sums));
    } while (n > scan.m_reducedBlocks); // the add pass sums up to that many totals itself
    return scan;
}

GpuCommandCount PrefixScan::exclusive(const gpu::Buffer& in, const gpu::Buffer& out,
                                      std::uint32_t count) const {
    return exclusive(in, out, ScanInput{count, count, false});
}

GpuCommandCount PrefixScan::exclusive(const gpu::Buffer& in, const gpu::Buffer& out,
                                      const ScanInput& what) const {
    SLUICE_ASSERT(what.inputCount <= what.count, "PrefixScan: more inputs than outputs");
    SLUICE_ASSERT(!what.clearInput || in.id() != out.id(),
                  "PrefixScan: clearing the input needs an output of its own");
    return what.count == 0 ? GpuCommandCount{} : scanLevel(in, out, what, 0);
}

GpuCommandCount PrefixScan::scanLevel(const gpu::Buffer& in, const gpu::Buffer& out,
                                      const ScanInput& what, std::size_t level) const {
    SLUICE_ASSERT(level < m_sums.size(), "PrefixScan: more elements than create() allowed");
    const std::uint32_t blocks = blocksFor(what.count);
    const gpu::Buffer& sums = m_sums[level];
    in.bindStorage(shared::kBindScanInput);
    out.bindStorage(shared::kBindScanData);
    sums.bindStorage(shared::kBindScanSums);
    m_block.set("count", what.count);
    m_block.set("inputCount", what.inputCount);
    m_block.set("clearInput", what.clearInput ? 1u : 0u);
    GpuCommandCount done;
    done.dispatches += m_block.dispatchChunked(glm::uvec3(blocks, 1, 1), kMaxGroupsPerDispatch);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    ++done.barriers;
    if (blocks == 1)
        return done; // one block: its offset is 0
    // Few blocks: each adds up the totals before it (reduce-then-scan); many: the totals are
    // scanned first.
    const bool reduce = blocks <= m_reducedBlocks;
    if (!reduce)
        done += scanLevel(sums, sums, ScanInput{blocks, blocks, false}, level + 1);
    out.bindStorage(shared::kBindScanData);
    sums.bindStorage(shared::kBindScanSums);
    m_add.set("count", what.count);
    m_add.set("reduceTotals", reduce ? 1u : 0u);
    done.dispatches += m_add.dispatchChunked(glm::uvec3(blocks, 1, 1), kMaxGroupsPerDispatch);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    ++done.barriers;
    return done;
}

} // namespace sluice::rt
