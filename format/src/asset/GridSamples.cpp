// The leaves of a sparse asset's NanoVDB tree, for code that must not include NanoVDB.
#include "sluice/format/asset/GridSamples.h"

#include <nanovdb/NanoVDB.h>

#include "sluice/format/support/Assert.h"

namespace sluice::format {

namespace {
const nanovdb::NanoTree<float>& treeOf(const ColliderAsset& asset) {
    SLUICE_ASSERT(asset.grid.size() >= sizeof(nanovdb::GridData) + sizeof(nanovdb::TreeData<3>),
                  "sparseLeaves: sparse asset without a grid");
    return reinterpret_cast<const nanovdb::NanoGrid<float>*>(asset.grid.data())->tree();
}
} // namespace

std::uint32_t sparseLeafCount(const ColliderAsset& asset) {
    return asset.sparse() ? treeOf(asset).nodeCount(0) : 0;
}

std::vector<SparseLeaf> sparseLeaves(const ColliderAsset& asset) {
    std::vector<SparseLeaf> out;
    if (!asset.sparse())
        return out;
    const nanovdb::NanoTree<float>& tree = treeOf(asset);
    const std::uint32_t count = tree.nodeCount(0);
    out.reserve(count);
    const nanovdb::NanoLeaf<float>* leaf = tree.getFirstNode<0>();
    for (std::uint32_t n = 0; n < count; ++n, ++leaf) {
        const nanovdb::Coord o = leaf->origin();
        out.push_back({glm::ivec3(o[0], o[1], o[2]), leaf->data()->mValues});
    }
    return out;
}

} // namespace sluice::format
