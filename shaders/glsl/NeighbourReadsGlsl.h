// GLSL only: how the neighbour passes read other particles' data (PbfGlsl.h's neighbour
// macros call these accessors). Included by glsl/PbfGlsl.h after the parameter block.
#ifndef SLUICE_SHARED_NEIGHBOUR_READS_GLSL_H
#define SLUICE_SHARED_NEIGHBOUR_READS_GLSL_H

#ifndef __cplusplus

// What the neighbour passes read at other particles' indices (their start positions, positions,
// velocities and vorticities, the neighbour masks and the cell ranges), a pass that defines
// PBF_NEIGHBOUR_PASS fetches through texel views of those buffers (Simulation::Impl::
// bindNeighbourTexels): on llvmpipe a storage read at an index that differs between lanes is a
// loop over the lanes with a bounds test for each component, a texel fetch one gather; on a GPU
// it goes through the texture cache. Where a buffer holds more texels than the GL allows, the
// programs are built with SLUICE_NEIGHBOURS_STORAGE and read the storage blocks named in the
// accessors' first argument. A view returns the bits the block holds (the lambda pass writes
// only w of the buffer whose xyz it fetches, so a fetch in that pass sees the xyz it reads).
#ifdef PBF_NEIGHBOUR_PASS
#ifndef SLUICE_NEIGHBOURS_STORAGE
layout(binding = kUnitStartTexels) uniform samplerBuffer startTexels;
layout(binding = kUnitPosTexels) uniform samplerBuffer posTexels;
layout(binding = kUnitVelTexels) uniform samplerBuffer velTexels;
layout(binding = kUnitOmegaTexels) uniform samplerBuffer omegaTexels;
layout(binding = kUnitMaskTexels) uniform usamplerBuffer maskTexels;
layout(binding = kUnitCellStartTexels) uniform usamplerBuffer cellStartTexels;
#define PBF_START_AT(START, j) texelFetch(startTexels, int(j))
#define PBF_POS_AT(POS, j) texelFetch(posTexels, int(j))
#define PBF_VEL_AT(VEL, j) texelFetch(velTexels, int(j))
#define PBF_OMEGA_AT(OMEGA, j) texelFetch(omegaTexels, int(j))
#define PBF_MASK_AT(MASK, w) texelFetch(maskTexels, int(w)).x
#define PBF_CELL_START_AT(b) texelFetch(cellStartTexels, int(b)).x
#else
#define PBF_START_AT(START, j) START[j]
#define PBF_POS_AT(POS, j) POS[j]
#define PBF_VEL_AT(VEL, j) VEL[j]
#define PBF_OMEGA_AT(OMEGA, j) OMEGA[j]
#define PBF_MASK_AT(MASK, w) MASK[w]
#define PBF_CELL_START_AT(b) cellStart[b]
#endif
// The particles live in this substep: the slots before the removal bucket's (the bucket after
// the last, where the predict pass sends the particles removed), once any particle may have been
// removed (docs/embedding.md, "Removing particles"); every slot otherwise.
#define PBF_LIVE (P.removal != 0u ? PBF_CELL_START_AT(P.activeBuckets) : PBF_COUNT)
#endif

#endif

#endif
