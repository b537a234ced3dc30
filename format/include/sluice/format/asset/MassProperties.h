// Mass properties of a collider's solid integrated from its distance field.
#pragma once

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::format {

/// Integrates the field itself: the smoothed Heaviside H(-phi) (width 1.5 voxels each side of
/// the surface) over the grid, trilinear cells, so it works for any asset, meshes with holes
/// included as far as their field has an inside. Fails with InvalidArgument when the field
/// encloses no volume (no point with phi < 0 away from the surface band).
Result<MassProperties> massPropertiesFromField(const ColliderAsset& asset);

} // namespace sluice::format
