// Draws a running Simulation: particles as ray-cast sphere impostors or as a screen-space fluid
// surface, the colliders by ray marching their distance grids, over a sky and a floor, into an
// offscreen framebuffer that a window shows or the capture code reads back (docs/rendering.md).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"
#include "sluice/gpu/Gl.h"
#include "sluice/rt/render/Image.h"
#include "sluice/rt/render/OrbitCamera.h"
#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt {

class Simulation;

/// How the particles are coloured (sphere mode).
enum class ColourMode : std::uint32_t {
    Water,        ///< shaded water blue
    Speed,        ///< |v| on a colour map, 0 .. RenderSettings::speedRange
    DensityError, ///< C_i = max(rho / rho0 - 1, 0) on a colour map, 0 .. densityErrorRange
};

/// How the fluid is drawn.
enum class SurfaceMode : std::uint32_t {
    Spheres, ///< one shaded sphere per particle (with its colour mode)
    Fluid,   ///< the screen-space fluid surface (van der Laan et al. 2009)
    Mesh,    ///< the reconstructed surface mesh, as --surface-mesh exports it (docs/surfaces.md)
};

/// "water" | "speed" | "density", as the command line spells them.
std::string_view colourModeName(ColourMode mode);
std::optional<ColourMode> parseColourMode(std::string_view name);
/// "spheres" | "fluid" | "mesh".
std::string_view surfaceModeName(SurfaceMode mode);
std::optional<SurfaceMode> parseSurfaceMode(std::string_view name);

/// What a frame shows. Everything may change from one frame to the next.
struct RenderSettings {
    SurfaceMode surface = SurfaceMode::Spheres;
    ColourMode colour = ColourMode::Water;
    float speedRange = 2.0f;                    ///< speed at the top of the colour map [m/s]
    float densityErrorRange = 0.05f;            ///< density error at the top of the colour map
    glm::vec3 waterColour{0.10f, 0.42f, 0.80f}; ///< display values
    bool drawColliders = true;
    /// Draw the near walls of containers (tank, funnel, tube: a surface with more of the same
    /// collider behind it) as glass, so the fluid inside stays visible.
    bool glassWalls = true;
    bool drawFloor = true;
    /// The domain box's twelve edges as lines, so water the box's walls hold does not float in
    /// space (a scene without a domain box has none to draw). --no-domain-box turns them off.
    bool drawDomainBox = true;
    /// Spheres: the ones that cover at most 8 x 8 pixels drawn by a compute pass (the same
    /// pixels as the rasterised impostors, at a fraction of the cost where the GPU has little
    /// rasteriser or the spheres are tiny); false rasterises every sphere.
    bool computeSmallSpheres = true;
    /// Mesh: how it is reconstructed, as the --surface-* options say (the particle radius is
    /// the simulation's), so that what the window shows is what --surface-mesh writes.
    SurfaceOptions mesh;
    /// Screen-space fluid: the spheres of its depth and thickness passes in particle radii
    /// (above 1.42 the rest lattice leaves no gaps), filter passes, filter radius and depth
    /// falloff in particle radii, absorption of the thickness [1/m], refraction offset
    /// [pixels per m of thickness].
    float fluidSphereScale = 1.5f;
    std::uint32_t smoothingIterations = 4;
    float filterRadius = 4.0f;
    float depthFalloff = 3.0f;
    float absorption = 30.0f;
    float refraction = 60.0f;
};

/// The render passes timed per frame, in order. The last three are parts of Fluid in the
/// screen-space surface mode (its spheres' depth and thickness, the depth's smoothing, the
/// shading), timed inside it; they have no time in the other modes.
enum class RenderPass : std::uint32_t {
    Backdrop,
    Colliders,
    Fluid,
    Glass,
    FluidSpheres,
    FluidSmooth,
    FluidShade,
    Count
};

/// Short name of a render pass ("colliders"); Fluid is the particles in either surface mode.
const char* renderPassName(RenderPass pass);

/// GPU time per render pass of the latest measured frame [ms]; negative where none is known.
using RenderPassTimes = std::array<double, std::size_t(RenderPass::Count)>;

/// Albedo of the collider at `index` in a scene (display values): a short fixed palette,
/// repeated (stone, terracotta, sage, lilac).
glm::vec3 colliderColour(std::size_t index);

/// Largest image side the renderer accepts [pixels] (the GL limits may be lower).
inline constexpr std::uint32_t kMaxImageSide = 8192;

/// The renderer of one scene. Needs a current GL 4.5 context (the simulation's) for its whole
/// life. Rendering only queues GPU work; nothing waits for the GPU except readPixels().
class Renderer {
public:
    /// Uploads the colliders (`colliders[i]` belongs to scene.colliders[i]) as 3D textures and
    /// compiles the render programs; the image size starts at `size` pixels. InvalidArgument
    /// for a size of zero or above the limits, GpuOutOfMemory when the targets do not fit;
    /// ShaderCompile / ShaderLink with the driver's log.
    static Result<Renderer> create(const format::Scene& scene,
                                   const std::vector<format::ColliderAsset>& colliders,
                                   glm::uvec2 size);

    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;
    ~Renderer();

    /// Changes the image size [pixels] (a window was resized); nothing happens when it is the
    /// same. Errors as create(); the old targets stay on failure.
    Result<void> resize(glm::uvec2 size);
    glm::uvec2 size() const;

    /// Draws the simulation's current particles and colliders (posed at sim.time()) as seen by
    /// `camera` into the output framebuffer. Leaves GL_FRAMEBUFFER bound to it.
    void render(const Simulation& sim, const OrbitCamera& camera, const RenderSettings& settings);

    /// The framebuffer holding the latest frame: colour attachment 0 (RGBA8) and depth.
    GLuint outputFramebuffer() const;

    /// The latest frame, top row first. Waits for the GPU (glReadPixels).
    Image readPixels() const;

    /// GPU time of the latest measured frame [ms], a few frames late; never waits. Empty until
    /// the first measurement arrives.
    std::optional<double> gpuMilliseconds();
    /// Mean GPU time of every frame measured so far [ms]; 0 before the first. Never waits.
    double gpuAverageMilliseconds();
    /// GPU time of each pass of the latest measured frame [ms]; never waits.
    RenderPassTimes passTimes();

    /// Why the latest frame in SurfaceMode::Mesh drew spheres instead (the reconstruction
    /// failed: too large a region for its cell size, out of memory); empty when it did not.
    const std::string& meshError() const;

    /// The scene's bounds (SceneFraming.h), for framing the camera.
    const Bounds& bounds() const;

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

} // namespace sluice::rt
