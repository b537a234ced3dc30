// Bounding box of a triangle soup.
#include "sluice/bake/import/TriangleSoup.h"

#include <glm/common.hpp>

namespace sluice::bake {

Box TriangleSoup::bounds() const {
    // Only referenced positions count: an importer may keep vertices no triangle uses.
    Box box;
    for (const glm::uvec3& t : triangles)
        for (int c = 0; c < 3; ++c) {
            const glm::dvec3& p = positions[t[c]];
            box.lo = glm::min(box.lo, p);
            box.hi = glm::max(box.hi, p);
        }
    return box;
}

} // namespace sluice::bake
