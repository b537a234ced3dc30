// The Gaussian field's blur on the GPU (surface_blur.comp, docs/surfaces.md "The mesh, step by
// step"): the deposit in the field buffer blurred along x, y and z into the field.
#ifndef SLUICE_RT_SURFACE_SURFACE_BLUR_H
#define SLUICE_RT_SURFACE_SURFACE_BLUR_H

#include <array>
#include <cstdint>
#include <map>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"
#include "surface/SurfaceGrid.h"

namespace sluice::rt {

/// The blur's programs, one per axis and number of taps (compiled in, so the shader's loops
/// unroll), made at first use, and its two float buffers, kept between reconstructions.
class GaussianBlurPasses {
public:
    /// Compiles the three programs of `radius` taps unless they are. ShaderCompile /
    /// ShaderLink with the driver's log.
    Result<void> prepare(int radius);

    /// Blurs the deposit in `field` (kSurfaceDepositScale per particle) along x, y and z into
    /// the field (kSurfaceFixedScale per unit), over `activeBlocks` stored blocks. The grid's
    /// block flags, slots and stored-block list must be bound. Errors: prepare's, or a buffer's.
    Result<void> run(const SurfaceBlur& blur, const SurfaceGrid& g, const SurfaceOptions& o,
                     const gpu::Buffer& field, std::uint32_t activeBlocks);

private:
    std::map<int, std::array<gpu::Program, 3>> m_programs;
    gpu::Buffer m_blurred[2]; ///< after the passes along x and along y
};

} // namespace sluice::rt

#endif // SLUICE_RT_SURFACE_SURFACE_BLUR_H
