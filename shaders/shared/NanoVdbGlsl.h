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

#endif // !__cplusplus && SLUICE_SPARSE_COLLIDERS

#endif // SLUICE_SHARED_NANOVDB_GLSL_H
