// The surface's sample grid and the options' defaults (SurfaceGrid.h).
#include "surface/SurfaceGrid.h"

#include <cmath>
#include <string>

#include <glm/common.hpp>

#include "shared/Surface.h"

namespace sluice::rt {
namespace {

namespace sh = shared;

/// How far a kernel reaches at most, in supports: an anisotropic one is longest along a line
/// of particles, its other two axes kSurfaceAnisotropyRatio times shorter, with the sphere's
/// volume.
float kernelReach(const SurfaceOptions& o) {
    return o.anisotropic ? std::cbrt(sh::kSurfaceAnisotropyRatio * sh::kSurfaceAnisotropyRatio)
                         : 1.0f;
}

bool positiveFinite(float v) {
    return std::isfinite(v) && v > 0.0f;
}

} // namespace

Result<SurfaceGrid> gridOver(glm::vec3 lo, glm::vec3 hi, const SurfaceOptions& o) {
    const float margin = o.smoothingRadius * kernelReach(o) + 3.0f * o.cellSize;
    SurfaceGrid g;
    const glm::vec3 first = glm::floor((lo - margin) / o.cellSize);
    g.origin = first * o.cellSize;
    const glm::vec3 last = glm::ceil((hi + margin) / o.cellSize);
    const glm::dvec3 samples = glm::dvec3(last) - glm::dvec3(first) + 1.0;
    const glm::dvec3 blocks = glm::ceil(samples / double(sh::kSurfaceBlockSide));
    const double blockCount = blocks.x * blocks.y * blocks.z;
    if (!(blockCount <= double(kMaxBlocks)))
        return fail(ErrorCode::SizeOverflow,
                    "surface: the particles span " + std::to_string(hi.x - lo.x) + " x " +
                        std::to_string(hi.y - lo.y) + " x " + std::to_string(hi.z - lo.z) +
                        " m, more than " + std::to_string(kMaxBlocks) + " blocks of " +
                        std::to_string(sh::kSurfaceBlockSide) + "^3 cells of " +
                        std::to_string(o.cellSize) + " m; use a larger cell size");
    g.samples = glm::ivec3(samples);
    g.blocks = glm::ivec3(blocks);
    g.blockCount = std::uint64_t(blockCount);
    return g;
}

Result<SurfaceOptions> resolveSurfaceOptions(const SurfaceOptions& options) {
    SurfaceOptions o = options;
    if (!positiveFinite(o.particleRadius))
        return fail(ErrorCode::InvalidArgument, "surface: the particle radius " +
                                                    std::to_string(o.particleRadius) +
                                                    " is not a positive number");
    const auto orDefault = [](float& value, float fallback, const char* name) -> Result<void> {
        if (value == 0.0f)
            value = fallback;
        if (!positiveFinite(value))
            return fail(ErrorCode::InvalidArgument, std::string("surface: ") + name + " " +
                                                        std::to_string(value) +
                                                        " is not a positive number");
        return {};
    };
    if (auto ok = orDefault(o.cellSize, o.particleRadius, "the cell size"); !ok)
        return ok.error();
    if (auto ok = orDefault(o.smoothingRadius, 4.0f * o.particleRadius, "the smoothing radius");
        !ok)
        return ok.error();
    if (auto ok = orDefault(o.iso, 0.5f, "the iso value"); !ok)
        return ok.error();
    if (o.iso >= 4.0f)
        return fail(ErrorCode::InvalidArgument,
                    "surface: the iso value " + std::to_string(o.iso) +
                        " is not below 4 (it is a share of the field inside the fluid, 1)");
    if (!o.centreSmoothing)
        o.centreSmoothing = kDefaultCentreSmoothing;
    if (!(*o.centreSmoothing >= 0.0f && *o.centreSmoothing <= 1.0f))
        return fail(ErrorCode::InvalidArgument, "surface: the centre smoothing " +
                                                    std::to_string(*o.centreSmoothing) +
                                                    " is not in [0, 1]");
    if (o.cellSize > o.smoothingRadius)
        return fail(ErrorCode::InvalidArgument,
                    "surface: the cell size " + std::to_string(o.cellSize) +
                        " is larger than the smoothing radius " +
                        std::to_string(o.smoothingRadius) + ": the field would be missed");
    return o;
}

} // namespace sluice::rt
