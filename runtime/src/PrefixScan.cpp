// Recursive block scan: level 0 scans the data, level l + 1 scans level l's block totals.
#include "PrefixScan.h"

#include <string>

#include "shared/Pbf.h"
#include "sluice/rt/RuntimeShaders.h"

namespace sluice::rt {

namespace {
constexpr std::uint64_t kMaxGroupsPerDispatch = 65535;

std::uint32_t blocksFor(std::uint32_t count) {
    return (count + shared::kScanBlock - 1) / shared::kScanBlock;
}
} // namespace

Result<PrefixScan> PrefixScan::create(std::uint32_t maxCount) {
    PrefixScan scan;
    auto block = gpu::Program::compute("scan_block.comp", shaders::shaderSource("scan_block.comp"));
    if (!block)
        return block.error();
    auto add = gpu::Program::compute("scan_add.comp", shaders::shaderSource("scan_add.comp"));
    if (!add)
        return add.error();
    scan.m_block = std::move(*block);
    scan.m_add = std::move(*add);
    std::uint32_t n = maxCount;
    do {
        n = blocksFor(n);
        auto sums = gpu::Buffer::create(std::size_t(n) * sizeof(std::uint32_t),
                                        "scan sums " + std::to_string(scan.m_sums.size()));
        if (!sums)
            return sums.error();
        scan.m_sums.push_back(std::move(*sums));
    } while (n > 1);
    return scan;
}

void PrefixScan::exclusive(const gpu::Buffer& in, const gpu::Buffer& out,
                           std::uint32_t count) const {
    if (count == 0)
        return;
    scanLevel(in, out, count, 0);
}

void PrefixScan::scanLevel(const gpu::Buffer& in, const gpu::Buffer& out, std::uint32_t count,
                           std::size_t level) const {
    SLUICE_ASSERT(level < m_sums.size(), "PrefixScan: more elements than create() allowed");
    const std::uint32_t blocks = blocksFor(count);
    const gpu::Buffer& sums = m_sums[level];
    in.bindStorage(shared::kBindScanInput);
    out.bindStorage(shared::kBindScanData);
    sums.bindStorage(shared::kBindScanSums);
    m_block.set("count", count);
    m_block.dispatchChunked(glm::uvec3(blocks, 1, 1), kMaxGroupsPerDispatch);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    if (blocks == 1)
        return; // one block: its offset is 0
    scanLevel(sums, sums, blocks, level + 1);
    out.bindStorage(shared::kBindScanData);
    sums.bindStorage(shared::kBindScanSums);
    m_add.set("count", count);
    m_add.dispatchChunked(glm::uvec3(blocks, 1, 1), kMaxGroupsPerDispatch);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

} // namespace sluice::rt
