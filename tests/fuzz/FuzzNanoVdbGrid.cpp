// libFuzzer target: the NanoVDB grid validator (checkNanoVdbGrid) on untrusted bytes.
//
// Each input is checked twice: as it is, and with its mGridSize set to the input's length, so
// that mutations get past the size check to the tree walk. A grid the validator accepts must be
// safe to walk: NanoVDB.h's lookups through SdfSampler return finite values inside the grid's
// box, and no single allocation may exceed what the input's size justifies.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "FuzzSupport.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/asset/NanoVdbCheck.h"
#include "sluice/format/asset/SdfSampler.h"

namespace {

using namespace sluice;
using namespace sluice::format;

constexpr std::size_t kGridSizeOffset = 32; // GridData::mGridSize, NanoVDB 32.x

void checkAccepted(const GridBytes& grid, const NanoVdbTreeStats& stats) {
    SLUICE_FUZZ_CHECK(stats.bytes == grid.size(), "stats name the whole buffer");
    SLUICE_FUZZ_CHECK(std::isfinite(stats.background), "background finite");
    // Sample it as a collider would, over the box of its active values (clamped to a size any
    // bake makes) and around it.
    ColliderAsset asset;
    asset.meta.layout = Layout::Sparse;
    asset.meta.bandWidth = 3.0;
    asset.meta.voxelSize = stats.voxelSize.x;
    asset.meta.origin = stats.translation;
    asset.meta.dims = {64, 64, 64};
    asset.grid = grid;
    const SdfSampler sampler(asset);
    const glm::dvec3 lo = asset.meta.origin;
    const glm::dvec3 hi = sampler.boxMax();
    for (const double t : {0.0, 0.13, 0.5, 0.77, 1.0}) {
        const glm::dvec3 p = lo + (hi - lo) * t;
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            continue;
        SLUICE_FUZZ_CHECK(std::isfinite(sampler.value(p)), "sampled value finite in the box");
        (void)sampler.gradient(p);
    }
}

void checkOnce(std::span<const std::byte> bytes) {
    GridBytes grid(bytes.begin(), bytes.end());
    bool ok = false;
    NanoVdbTreeStats stats;
    {
        fuzz::AllocationWatch watch;
        Result<NanoVdbTreeStats> r = checkNanoVdbGrid(grid, "fuzz/grid.nvdb");
        watch.check(bytes.size() + (std::size_t(64) << 10), "checkNanoVdbGrid");
        ok = fuzz::takeResult(r, stats, "fuzz/grid.nvdb: ");
    }
    if (ok)
        checkAccepted(grid, stats);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // The repaired copy states its own size, so the check goes on to the tree.
    return fuzz::checkAsIsAndRepaired(data, size, checkOnce, [](std::vector<std::byte>& b) {
        if (b.size() < kGridSizeOffset + 8)
            return false;
        const std::uint64_t n = b.size();
        std::memcpy(b.data() + kGridSizeOffset, &n, 8); // little-endian hosts
        return true;
    });
}
