// Sparse collider samples in GLSL: NanoVDB float grids read through NanoVDB's own GLSL reader
// (PNanoVDB.h, PNANOVDB_GLSL: the buffer is a uint[] SSBO, 32-bit addresses). GLSL only.
//
// A shader that samples sparse colliders defines SLUICE_SPARSE_COLLIDERS, declares the uint[]
// SSBO that holds the grids and defines pnanovdb_buf_data as its name before including this
// header. Each grid is one format::ColliderAsset::grid, copied byte for byte at a 32-byte
// aligned offset; the CPU checked it (format::checkNanoVdbGrid) before the upload, so every
// node offset inside it stays inside it.
#ifndef SLUICE_SHARED_NANOVDB_GLSL_H
#define SLUICE_SHARED_NANOVDB_GLSL_H

#if !defined(__cplusplus) && defined(SLUICE_SPARSE_COLLIDERS)

#define PNANOVDB_GLSL
#include "nanovdb/PNanoVDB.h"

/// A read accessor on the float grid at `byteOffset` in the buffer. Neighbouring lookups
/// through one accessor reuse its cached leaf and inner nodes.
pnanovdb_readaccessor_t sparseAccessor(uint byteOffset) {
    pnanovdb_buf_t buf;
    pnanovdb_grid_handle_t grid;
    grid.address.byte_offset = byteOffset;
    pnanovdb_root_handle_t root = pnanovdb_tree_get_root(buf, pnanovdb_grid_get_tree(buf, grid));
    pnanovdb_readaccessor_t acc;
    pnanovdb_readaccessor_init(acc, root);
    return acc;
}

/// The value at index (i, j, k): the voxel's own value in the band, the tile's or the
/// background's elsewhere (with the sign of its region).
float sparseValue(inout pnanovdb_readaccessor_t acc, ivec3 ijk) {
    pnanovdb_buf_t buf;
    pnanovdb_address_t address =
        pnanovdb_readaccessor_get_value_address(PNANOVDB_GRID_TYPE_FLOAT, buf, acc, ijk);
    return pnanovdb_read_float(buf, address);
}

/// The background |phi| of the grid at `byteOffset`: what its tiles and its leaves' voxels past
/// the band hold (negative inside).
float sparseBackground(uint byteOffset) {
    pnanovdb_buf_t buf;
    pnanovdb_grid_handle_t grid;
    grid.address.byte_offset = byteOffset;
    pnanovdb_root_handle_t root = pnanovdb_tree_get_root(buf, pnanovdb_grid_get_tree(buf, grid));
    return pnanovdb_read_float(
        buf, pnanovdb_address_offset(root.address, PNANOVDB_GRID_TYPE_GET(PNANOVDB_GRID_TYPE_FLOAT,
                                                                          root_off_background)));
}

/// Leaf n (in the tree's order) of the grid at `byteOffset`.
pnanovdb_leaf_handle_t sparseLeaf(uint byteOffset, uint n) {
    pnanovdb_buf_t buf;
    pnanovdb_grid_handle_t grid;
    grid.address.byte_offset = byteOffset;
    pnanovdb_tree_handle_t tree = pnanovdb_grid_get_tree(buf, grid);
    pnanovdb_leaf_handle_t leaf;
    leaf.address =
        pnanovdb_address_offset64(tree.address, pnanovdb_tree_get_node_offset_leaf(buf, tree));
    leaf.address.byte_offset += n * PNANOVDB_GRID_TYPE_GET(PNANOVDB_GRID_TYPE_FLOAT, leaf_size);
    return leaf;
}

/// The index of voxel n (64 x + 8 y + z within the 8^3 block, NanoVDB's order) of leaf `leaf`.
ivec3 sparseLeafVoxel(uint byteOffset, uint leaf, uint n) {
    pnanovdb_buf_t buf;
    ivec3 origin = pnanovdb_leaf_get_bbox_min(buf, sparseLeaf(byteOffset, leaf)) & ivec3(~7);
    return origin + ivec3(n >> 6u, (n >> 3u) & 7u, n & 7u);
}

/// The eight values of the cell with lower corner b, as v[x + 2y + 4z], through `acc`.
void sparseCorners(inout pnanovdb_readaccessor_t acc, ivec3 b, out float v[8]) {
    for (int k = 0; k < 8; ++k)
        v[k] = sparseValue(acc, b + ivec3(k & 1, (k >> 1) & 1, k >> 2));
}

/// Where voxel ijk lies among all leaves' voxels, leaf * 512 + its place in the leaf, as a
/// per-leaf channel stores it (a volume map, BoundaryVolumeGlsl.h); false when ijk is in no leaf
/// (a tile or the background). `firstLeaf`: sparseLeaf(grid, 0u).address.byte_offset.
bool sparseLeafSlot(inout pnanovdb_readaccessor_t acc, uint firstLeaf, ivec3 ijk, out uint slot) {
    pnanovdb_buf_t buf;
    uint level;
    pnanovdb_readaccessor_get_value_address_and_level(PNANOVDB_GRID_TYPE_FLOAT, buf, acc, ijk,
                                                      level);
    slot = 0u;
    if (level != 0u)
        return false;
    uint leaf = (acc.leaf.address.byte_offset - firstLeaf) /
                PNANOVDB_GRID_TYPE_GET(PNANOVDB_GRID_TYPE_FLOAT, leaf_size);
    slot = leaf * 512u + pnanovdb_leaf_coord_to_offset(ijk);
    return true;
}

#endif // !__cplusplus && SLUICE_SPARSE_COLLIDERS

#endif // SLUICE_SHARED_NANOVDB_GLSL_H
