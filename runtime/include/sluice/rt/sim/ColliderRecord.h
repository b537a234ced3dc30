// The solver's GPU record of a collider (shared/Pbf.h, GpuCollider) built from its asset: the
// one rule the solver, its parity tests and the collider benchmark use.
#pragma once

#include <cstdint>

#include "shared/Pbf.h"
#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::rt {

/// The record of `asset` at the identity placement (unit scale, no rotation or motion), static
/// (`body` = kNoBody) and without friction, its samples at `sdfOffset` in the SDF buffer:
/// [words] for a dense grid, [bytes] for a sparse one. The caller places it and sets friction
/// and the body.
shared::GpuCollider colliderRecord(const format::ColliderAsset& asset, std::uint32_t sdfOffset);

} // namespace sluice::rt
