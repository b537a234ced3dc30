// The surface's sample grid and the options' defaults (SurfaceGrid.h).
#include "surface/SurfaceGrid.h"

#include <algorithm>
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

void setGridUniforms(const gpu::Program& p, const SurfaceGrid& g, const SurfaceOptions& o) {
    const float volume = particleVolume(o);
    const auto iso = std::uint32_t(std::floor(double(o.iso) * sh::kSurfaceFixedScale));
    p.set("uOrigin", g.origin);
    p.set("uCell", o.cellSize);
    p.set("uSamples", g.samples);
    p.set("uBlocks", g.blocks);
    p.set("uSupport", o.smoothingRadius);
    p.set("uVolume", volume);
    p.set("uIsoFixed", iso);
    p.set("uAnisotropic", std::int32_t(o.anisotropic ? 1 : 0));
}

std::optional<SurfaceBlur> gaussianBlur(const SurfaceOptions& o) {
    if (o.anisotropic || o.kernel != SurfaceFieldKernel::Gaussian)
        return std::nullopt;
    const double supportInCells = double(o.smoothingRadius) / double(o.cellSize);
    const double variance = supportInCells * supportInCells / 11.0 - 1.0 / 6.0; // [cells^2]
    const double sigma = std::sqrt(std::max(variance, 0.0));
    // 3.5 sigma each way leaves 5e-4 of the weight out, before the taps are normalised.
    constexpr double kTailSigmas = 3.5;
    const int radius = int(std::ceil(kTailSigmas * sigma));
    if (sigma < 0.5 || 3.0 * sigma > double(sh::kSurfaceBlurRadiusMax))
        return std::nullopt;
    SurfaceBlur blur;
    blur.radius = std::min(radius, int(sh::kSurfaceBlurRadiusMax));
    double sum = 0.0;
    std::array<double, sh::kSurfaceBlurRadiusMax + 1> w{};
    for (int k = 0; k <= blur.radius; ++k) {
        w[std::size_t(k)] = std::exp(-0.5 * double(k * k) / variance);
        sum += (k == 0 ? 1.0 : 2.0) * w[std::size_t(k)];
    }
    for (int k = 0; k <= blur.radius; ++k)
        blur.weights[std::size_t(k)] = float(w[std::size_t(k)] / sum);
    return blur;
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
    o.densityNormalised = isDensityNormalised(o);
    if (auto ok = orDefault(o.iso, *o.densityNormalised ? 0.6f : 0.5f, "the iso value"); !ok)
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
