// The fluid's surface as a triangle mesh, reconstructed from particles on the GPU: a smooth
// field from the particles (an SPH colour field), sampled only in the blocks of a grid that the
// particles reach, then contoured into a closed, manifold mesh with shared vertices and normals
// (docs/surfaces.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Buffer.h"

namespace sluice::rt {

/// Where a reconstruction's time went [ms, wall clock], each stage ending where the CPU waits
/// for the GPU: the particles' bounds (a reduction on the GPU); the blocks marked and counted;
/// the field splatted; the mesh counted and written; the mesh read back into the vectors.
struct SurfaceTimings {
    double bounds = 0.0;
    double kernels = 0.0; ///< anisotropic kernels: the particles binned, the kernels written
    double blocks = 0.0;
    double field = 0.0;
    double contour = 0.0;
    double download = 0.0;
};

/// The stages' names, in the order they run, with their times: what the run summary,
/// --stats-json and Python's SurfaceMesh.timings report.
inline constexpr std::pair<const char*, double SurfaceTimings::*> kSurfaceStages[] = {
    {"bounds", &SurfaceTimings::bounds},   {"kernels", &SurfaceTimings::kernels},
    {"blocks", &SurfaceTimings::blocks},   {"field", &SurfaceTimings::field},
    {"contour", &SurfaceTimings::contour}, {"download", &SurfaceTimings::download}};

/// A triangle mesh: vertices with unit normals, counter-clockwise triangles seen from outside.
struct SurfaceMesh {
    std::vector<glm::vec3> vertices;   ///< [m]
    std::vector<glm::vec3> normals;    ///< unit, pointing out of the fluid
    std::vector<glm::uvec3> triangles; ///< vertex indices
    glm::vec3 gridOrigin{0.0f};        ///< where the sample grid started [m]
    float cellSize = 0.0f;             ///< its spacing [m]
    std::uint64_t storedSamples = 0;   ///< samples held (blocks the particles reach x 512)
    SurfaceTimings timings;            ///< of the reconstruction that made it
};

/// The anisotropic kernels' default centre smoothing (SurfaceOptions::centreSmoothing).
inline constexpr float kDefaultCentreSmoothing = 0.25f;

/// The field's kernel round each particle (docs/surfaces.md, "The field").
enum class SurfaceFieldKernel {
    /// A Gaussian as wide as poly6 (the same variance): each particle's trilinear weights on
    /// its eight samples, blurred along x, y and z. The same surface within a few hundredths of
    /// a radius, several times faster than poly6 where the GPU is a CPU. Used where the cell
    /// is between a ninth and half the support; poly6 otherwise.
    Gaussian,
    /// poly6 of support smoothingRadius, added by every particle to every sample within it.
    Poly6,
};

/// How a surface is reconstructed. Zeros take the defaults, all derived from the radius.
struct SurfaceOptions {
    float particleRadius = 0.0f; ///< [m], > 0: half the particle spacing
    float cellSize = 0.0f;       ///< sample spacing [m]; 0: the particle radius
    /// The kernel's support [m]; 0: four particle radii (two spacings, the solver's own).
    float smoothingRadius = 0.0f;
    /// The surface's field value, as a share of the field inside a resting block of particles
    /// on their lattice (which is 1): 0.5 puts a flat surface where the block ends, half a
    /// spacing beyond its outer particles' centres. 0: 0.6 when densityNormalised (splashsurf's
    /// default, which puts its flat surface there), 0.5 otherwise.
    float iso = 0.0f;
    /// Anisotropic kernels (Yu & Turk 2013): each particle's kernel follows its neighbours'
    /// spread, flat across a surface or a sheet, round in the bulk (docs/surfaces.md).
    bool anisotropic = false;
    /// The isotropic kernel's shape; anisotropic kernels are always poly6 ellipsoids.
    SurfaceFieldKernel kernel = SurfaceFieldKernel::Gaussian;
    /// Each particle's kernel scaled by the rest density over its own (the field at its centre)
    /// instead of the rest volume alone, as splashsurf's colour field is: a particle with few
    /// neighbours (a thin sheet, a droplet) counts for the volume it has, so splashes stay
    /// whole and a lone particle is a drop of its own, and a ball of particles keeps their own
    /// volume within 0.5 %. Two passes of the field (a quarter more time on a software
    /// renderer). false: each kernel scaled by the rest volume alone, which thins splashes and
    /// moves curved surfaces in or out by up to a fifth of a radius. Unset: on for the isotropic
    /// kernels, off for the anisotropic ones (they keep thin sheets by their shape, and
    /// normalised they pull a box's flat faces in by 4.6 %).
    std::optional<bool> densityNormalised;
    /// With anisotropic kernels, how far each kernel's centre moves to its neighbours' weighted
    /// mean, in [0, 1] (Yu & Turk's lambda). Unset: kDefaultCentreSmoothing.
    std::optional<float> centreSmoothing;
};

/// Whether `o` asks for the density-normalised field: densityNormalised, or where it is unset
/// its default (the isotropic kernels normalised, the anisotropic ones not).
inline bool isDensityNormalised(const SurfaceOptions& o) {
    return o.densityNormalised.value_or(!o.anisotropic);
}

/// The options with every default filled in; InvalidArgument naming the option for a value
/// that is not finite and positive (iso in (0, 4)), or for a cell larger than the support.
Result<SurfaceOptions> resolveSurfaceOptions(const SurfaceOptions& options);

/// A mesh SurfaceReconstructor::build left in GPU memory, valid until the reconstructor's next
/// call: `positions` and `normals` hold three floats per vertex (position [m], unit outward
/// normal), `triangles` three vertex indices (uint) per triangle, as SurfaceMesh's vectors do.
struct SurfaceGpuMesh {
    const gpu::Buffer* positions = nullptr;
    const gpu::Buffer* normals = nullptr;
    const gpu::Buffer* triangles = nullptr;
    std::uint32_t vertexCount = 0;
    std::uint32_t triangleCount = 0;
    glm::vec3 gridOrigin{0.0f};      ///< as in SurfaceMesh
    float cellSize = 0.0f;           ///< as in SurfaceMesh
    std::uint64_t storedSamples = 0; ///< as in SurfaceMesh
    SurfaceTimings timings;          ///< download is 0
};

/// Reconstructs surfaces from particles. Needs a current GL 4.5 context for its whole life.
class SurfaceReconstructor {
public:
    /// Compiles the passes. ShaderCompile / ShaderLink with the driver's log.
    static Result<SurfaceReconstructor> create();

    SurfaceReconstructor(SurfaceReconstructor&&) noexcept;
    SurfaceReconstructor& operator=(SurfaceReconstructor&&) noexcept;
    ~SurfaceReconstructor();

    /// The surface of `count` particles whose positions are the xyz of the vec4s in
    /// `positions` (the solver's layout). Waits for the GPU (it reads back the sizes and the
    /// mesh). InvalidArgument for bad options or non-finite positions; SizeOverflow when the
    /// grid over the particles' bounds would pass 2^24 blocks of 8^3 samples (the particles
    /// spread over too large a region for this cell size) or a buffer its GL's limit;
    /// GpuOutOfMemory when the GL cannot allocate it. No particles: an empty mesh.
    Result<SurfaceMesh> reconstruct(const gpu::Buffer& positions, std::uint32_t count,
                                    const SurfaceOptions& options);

    /// The same surface left in GPU memory, for drawing it: no mesh is read back (only its
    /// sizes), same errors.
    Result<SurfaceGpuMesh> build(const gpu::Buffer& positions, std::uint32_t count,
                                 const SurfaceOptions& options);

    /// The same for positions on the CPU (uploaded first).
    Result<SurfaceMesh> reconstruct(std::span<const glm::vec3> points,
                                    const SurfaceOptions& options);

private:
    struct Impl;
    explicit SurfaceReconstructor(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

/// Writes `mesh` as a binary little-endian PLY (float x y z nx ny nz per vertex, a uchar count
/// and uint indices per face), atomically: Blender, Houdini and MeshLab read it. Io on failure.
Result<void> writeSurfacePly(const std::filesystem::path& path, const SurfaceMesh& mesh);

} // namespace sluice::rt
