// The triangle soup of a GPU bake, prepared as the CGAL reference prepares it.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/bake/cgal/CgalReference.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// The triangles a GPU bake uses and how it signs them.
struct GpuSoup {
    std::vector<glm::dvec3> points;                    ///< [world units]
    std::vector<std::array<std::size_t, 3>> triangles; ///< non-degenerate, oriented
    format::SignMethod method = format::SignMethod::Winding;
    bool cycle = false; ///< the triangles are a cycle: the winding number is an integer off them
};

/// Prepares `soup` as the CGAL reference does: triangles with a repeated corner left out; the
/// sign method chosen by chooseSignMethod; for parity, the soup oriented with CGAL's
/// orient_polygon_soup (skipped when it is already a closed, consistently oriented surface),
/// falling back to the winding number when no closed polygon mesh can be made of it; triangles
/// of zero area left out with CGAL's exact collinearity test; a closed soup wound inward turned
/// outward. Errors: those of chooseSignMethod; EmptyMesh when no triangle has a non-zero area.
/// CGAL may throw (broken preconditions, allocation failures); the caller catches.
Result<GpuSoup> prepareGpuSoup(const TriangleSoup& soup, const format::MeshDiagnostics& diagnostics,
                               SignMode mode);

} // namespace sluice::bake
