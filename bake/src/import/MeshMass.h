// Exact volume, centre of mass and inertia tensor of the solid a closed triangle mesh bounds.
#pragma once

#include <optional>

#include "sluice/bake/import/TriangleSoup.h"
#include "sluice/format/asset/ColliderAsset.h"

namespace sluice::bake {

/// Mass properties at unit density of the polyhedron `soup` bounds, by the divergence theorem
/// over its triangles (Mirtich 1996), in the soup's units: volume [units^3], centre of mass
/// [units], inertia about the centre of mass [units^5]. The result is only meaningful for a
/// closed, consistently oriented soup; an inward-facing one (negative signed volume) is
/// treated as if its winding were flipped, so the volume is >= 0. A soup enclosing no volume
/// gives volume 0, the centre of its box as centre of mass, and a zero inertia tensor.
format::MassProperties polyhedronMassProperties(const TriangleSoup& soup);

/// polyhedronMassProperties for a mesh the diagnostics call closed, when its volume is finite
/// and > 0: what the baker stores as ColliderMeta::meshMass. Empty otherwise (open or
/// non-manifold meshes, flat ones).
std::optional<format::MassProperties> closedMeshMass(const TriangleSoup& soup,
                                                     const format::MeshDiagnostics& diagnostics);

} // namespace sluice::bake
