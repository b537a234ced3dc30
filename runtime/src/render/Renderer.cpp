// The frame: backdrop, opaque colliders, particles (spheres or fluid surface), glass walls.
#include "sluice/rt/render/Renderer.h"

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <utility>

#include "ColliderPass.h"
#include "FluidSurfacePass.h"
#include "GlObjects.h"
#include "SphereSplatPass.h"
#include "shared/Render.h"
#include "shared/Surface.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/GpuTimer.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/RuntimeShaders.h"
#include "sluice/rt/render/SceneFraming.h"
#include "sluice/rt/sim/Simulation.h"
#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::rt {
namespace {

constexpr std::array<std::string_view, 3> kColourNames{"water", "speed", "density"};
constexpr std::array<std::string_view, 3> kSurfaceNames{"spheres", "fluid", "mesh"};
constexpr std::array<const char*, std::size_t(RenderPass::Count)> kPassNames{
    "backdrop", "colliders", "fluid", "glass", "spheres", "smooth", "shade"};

// Towards the light: above, a little to the front right of the usual cameras.
const glm::vec3 kLight = glm::normalize(glm::vec3(0.35f, 0.85f, 0.4f));

// [m] edge of one floor checker.
constexpr float kCheckerSize = 0.1f;

Result<void> checkSize(glm::uvec2 size) {
    GLint maxTexture = 0;
    GLint maxViewport[2] = {0, 0};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    const std::uint32_t limitX =
        std::min({kMaxImageSide, std::uint32_t(maxTexture), std::uint32_t(maxViewport[0])});
    const std::uint32_t limitY =
        std::min({kMaxImageSide, std::uint32_t(maxTexture), std::uint32_t(maxViewport[1])});
    if (size.x == 0 || size.y == 0 || size.x > limitX || size.y > limitY)
        return fail(ErrorCode::InvalidArgument, "image size " + std::to_string(size.x) + "x" +
                                                    std::to_string(size.y) + " is outside 1x1 .. " +
                                                    std::to_string(limitX) + "x" +
                                                    std::to_string(limitY));
    return {};
}

} // namespace

const char* renderPassName(RenderPass pass) {
    return kPassNames[std::size_t(pass)];
}

std::string_view colourModeName(ColourMode mode) {
    return kColourNames[std::size_t(mode)];
}

std::optional<ColourMode> parseColourMode(std::string_view name) {
    for (std::size_t i = 0; i < kColourNames.size(); ++i)
        if (kColourNames[i] == name)
            return ColourMode(i);
    return std::nullopt;
}

std::string_view surfaceModeName(SurfaceMode mode) {
    return kSurfaceNames[std::size_t(mode)];
}

std::optional<SurfaceMode> parseSurfaceMode(std::string_view name) {
    for (std::size_t i = 0; i < kSurfaceNames.size(); ++i)
        if (kSurfaceNames[i] == name)
            return SurfaceMode(i);
    return std::nullopt;
}

struct Renderer::Impl {
    Bounds bounds;
    float floorY = 0.0f;
    ColliderPass colliders;
    FluidSurfacePass fluid;
    SphereSplatPass splat;
    gpu::Program backdrop;
    gpu::Program particles;
    gpu::Program domainBox;                     ///< the domain box's edges (lines)
    gpu::Program meshProgram;                   ///< the reconstructed surface mesh
    std::optional<SurfaceReconstructor> mesher; ///< made on the first frame in Mesh mode
    std::string meshError;
    std::optional<std::pair<glm::vec3, glm::vec3>> domain; ///< the scene's domain box [m]
    gpu::Buffer frame;
    VertexArrayHandle vertexArray;
    glm::uvec2 size{0};
    TextureHandle sceneColour;
    TextureHandle sceneDepth;
    TextureHandle finalColour;
    TextureHandle finalDepth;
    FramebufferHandle sceneTarget;
    FramebufferHandle finalTarget;
    GLuint output = 0;
    gpu::GpuTimer timer{6};
    std::array<gpu::GpuTimer, std::size_t(RenderPass::Count)> passTimers; // rings of 4

    gpu::GpuTimer& passTimer(RenderPass pass) { return passTimers[std::size_t(pass)]; }
    bool fluidStagesTimed = false; // the latest frame drew the screen-space surface

    /// The domain box's edges, against the depth of the opaque scene (edges behind a wall or
    /// the floor are hidden), into the bound framebuffer.
    void drawDomainBox() {
        if (!domain)
            return;
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
        glDepthMask(GL_FALSE);
        domainBox.set("uDomainMin", domain->first);
        domainBox.set("uDomainMax", domain->second);
        domainBox.use();
        glDrawArrays(GL_LINES, 0, 24);
        glDepthMask(GL_TRUE);
        glDepthFunc(GL_LESS);
    }

    /// The particles as spheres into the scene target: the small ones in compute where asked
    /// and the list of large ones fits, else every sphere rasterised.
    void drawSpheres(std::uint32_t count, float radius, bool computeSmall) {
        if (!computeSmall || !splat.drawSpheres(count, radius, sceneDepth.id())) {
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(GL_LESS);
            particles.use();
            glDrawArrays(GL_TRIANGLES, 0, GLsizei(6 * std::uint64_t(count)));
        }
        output = sceneTarget.id();
    }

    /// Reconstructs the surface of the particles and draws it into the scene target; false
    /// (with meshError) when the reconstruction failed, and the caller draws spheres.
    bool drawMesh(const Simulation& sim, const SurfaceOptions& meshOptions) {
        if (!mesher) {
            auto created = SurfaceReconstructor::create();
            if (!created) {
                meshError = created.error().message();
                return false;
            }
            mesher.emplace(std::move(*created));
        }
        SurfaceOptions options = meshOptions;
        options.particleRadius = sim.constants().radius;
        // Drawn from the reconstructor's own buffers: nothing read back but the sizes.
        auto mesh = mesher->build(sim.positionBuffer(), sim.liveParticleCount(), options);
        if (!mesh) {
            meshError = mesh.error().message();
            return false;
        }
        if (mesh->triangleCount == 0)
            return true;
        // The reconstruction bound its own programs and buffers: the frame's again.
        frame.bindBase(GL_UNIFORM_BUFFER, shared::kRenderBindFrame);
        sim.positionBuffer().bindStorage(shared::kRenderBindPositions);
        sim.velocityBuffer().bindStorage(shared::kRenderBindVelocities);
        glBindVertexArray(vertexArray.id());
        glBindFramebuffer(GL_FRAMEBUFFER, sceneTarget.id());
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        mesh->positions->bindStorage(shared::kRenderBindMeshPositions);
        mesh->normals->bindStorage(shared::kRenderBindMeshNormals);
        mesh->triangles->bindStorage(shared::kRenderBindMeshTriangles);
        meshProgram.use();
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(3 * std::uint64_t(mesh->triangleCount)));
        return true;
    }

    Result<void> resize(glm::uvec2 newSize) {
        if (newSize == size)
            return {};
        if (auto ok = checkSize(newSize); !ok)
            return ok;
        auto colour = createTexture2D(GL_RGBA8, newSize, "scene colour", true);
        if (!colour)
            return colour.error();
        auto depth = createTexture2D(GL_DEPTH_COMPONENT32F, newSize, "scene depth");
        if (!depth)
            return depth.error();
        auto finalC = createTexture2D(GL_RGBA8, newSize, "final colour");
        if (!finalC)
            return finalC.error();
        auto finalD = createTexture2D(GL_DEPTH_COMPONENT32F, newSize, "final depth");
        if (!finalD)
            return finalD.error();
        auto sceneFb = createFramebuffer(colour->id(), depth->id(), "scene");
        if (!sceneFb)
            return sceneFb.error();
        auto finalFb = createFramebuffer(finalC->id(), finalD->id(), "final");
        if (!finalFb)
            return finalFb.error();
        if (auto ok = fluid.resize(newSize); !ok)
            return ok;
        if (auto ok = splat.resize(newSize); !ok)
            return ok;
        sceneColour = std::move(*colour);
        sceneDepth = std::move(*depth);
        finalColour = std::move(*finalC);
        finalDepth = std::move(*finalD);
        sceneTarget = std::move(*sceneFb);
        finalTarget = std::move(*finalFb);
        output = sceneTarget.id();
        size = newSize;
        return {};
    }

    void uploadFrame(const Simulation& sim, const OrbitCamera& camera,
                     const RenderSettings& settings) {
        const float aspect = float(size.x) / float(size.y);
        shared::RenderFrame f{};
        f.view = camera.view();
        f.proj = camera.projection(aspect);
        f.invView = glm::inverse(f.view);
        f.invProj = glm::inverse(f.proj);
        f.viewportSize = {float(size.x), float(size.y)};
        f.invViewportSize = {1.0f / float(size.x), 1.0f / float(size.y)};
        f.eye = camera.eye();
        f.nearPlane = camera.nearPlane();
        f.lightDirection = kLight;
        f.farPlane = camera.farPlane();
        f.particleRadius = sim.constants().radius;
        f.colourMode = std::uint32_t(settings.colour);
        f.speedRange = std::max(settings.speedRange, 1e-6f);
        f.densityErrorRange = std::max(settings.densityErrorRange, 1e-6f);
        f.floorY = floorY;
        f.checkerSize = kCheckerSize;
        f.drawFloor = settings.drawFloor ? 1u : 0u;
        f.particleCount = sim.particleCount();
        f.waterColour = settings.waterColour;
        f.fluidAbsorption = settings.absorption;
        f.fluidRefraction = settings.refraction;
        f.fluidFresnelF0 = 0.02f;
        f.fluidSphereRadius = settings.fluidSphereScale * sim.constants().radius;
        // The solver keeps the particles sorted by cell, z slowest: drawn first to last they
        // run along +z, so a camera looking down -z draws them nearer to front to back reversed.
        f.reverseOrder = glm::dot(camera.target() - camera.eye(), glm::vec3(0, 0, 1)) < 0.0f;
        frame.upload(&f, sizeof f);
    }
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

Result<Renderer> Renderer::create(const format::Scene& scene,
                                  const std::vector<format::ColliderAsset>& colliders,
                                  glm::uvec2 size) {
    if (auto ok = checkSize(size); !ok)
        return ok.error();
    auto impl = std::make_unique<Impl>();
    impl->bounds = sceneBounds(scene, colliders);
    impl->floorY = floorHeight(scene, impl->bounds);
    auto colliderPass = ColliderPass::create(scene, colliders);
    if (!colliderPass)
        return colliderPass.error();
    impl->colliders = std::move(*colliderPass);
    auto fluid = FluidSurfacePass::create();
    if (!fluid)
        return fluid.error();
    impl->fluid = std::move(*fluid);
    auto splat = SphereSplatPass::create();
    if (!splat)
        return splat.error();
    impl->splat = std::move(*splat);
    auto backdrop =
        gpu::Program::graphics("render_backdrop", shaders::shaderSource("render_fullscreen.vert"),
                               shaders::shaderSource("render_backdrop.frag"));
    if (!backdrop)
        return backdrop.error();
    impl->backdrop = std::move(*backdrop);
    auto particles =
        gpu::Program::graphics("render_particles", shaders::shaderSource("render_particles.vert"),
                               shaders::shaderSource("render_particles.frag"));
    if (!particles)
        return particles.error();
    impl->particles = std::move(*particles);
    auto domainBox =
        gpu::Program::graphics("render_domain_box", shaders::shaderSource("render_domain_box.vert"),
                               shaders::shaderSource("render_domain_box.frag"));
    if (!domainBox)
        return domainBox.error();
    impl->domainBox = std::move(*domainBox);
    if (scene.domainMin && scene.domainMax)
        impl->domain.emplace(*scene.domainMin, *scene.domainMax);
    auto meshProgram = gpu::Program::graphics("render_surface_mesh",
                                              shaders::shaderSource("render_surface_mesh.vert"),
                                              shaders::shaderSource("render_surface_mesh.frag"));
    if (!meshProgram)
        return meshProgram.error();
    impl->meshProgram = std::move(*meshProgram);
    auto frame = gpu::Buffer::create(sizeof(shared::RenderFrame), "render frame");
    if (!frame)
        return frame.error();
    impl->frame = std::move(*frame);
    impl->vertexArray = createEmptyVertexArray();
    if (auto ok = impl->resize(size); !ok)
        return ok.error();
    return Renderer(std::move(impl));
}

Result<void> Renderer::resize(glm::uvec2 size) {
    return m_impl->resize(size);
}

const std::string& Renderer::meshError() const {
    return m_impl->meshError;
}

glm::uvec2 Renderer::size() const {
    return m_impl->size;
}

void Renderer::render(const Simulation& sim, const OrbitCamera& camera,
                      const RenderSettings& settings) {
    Impl& r = *m_impl;
    // The solver wrote the particle buffers with compute shaders.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    // Polling keeps the rings free, so begin() never waits.
    r.timer.poll();
    for (gpu::GpuTimer& timer : r.passTimers)
        timer.poll();
    r.timer.begin();
    r.uploadFrame(sim, camera, settings);
    r.frame.bindBase(GL_UNIFORM_BUFFER, shared::kRenderBindFrame);
    sim.positionBuffer().bindStorage(shared::kRenderBindPositions);
    sim.velocityBuffer().bindStorage(shared::kRenderBindVelocities);
    glBindVertexArray(r.vertexArray.id());
    glViewport(0, 0, GLsizei(r.size.x), GLsizei(r.size.y));
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);

    // Backdrop: writes every pixel's colour and depth, so no clear is needed.
    glBindFramebuffer(GL_FRAMEBUFFER, r.sceneTarget.id());
    r.passTimer(RenderPass::Backdrop).begin();
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    r.backdrop.use();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthFunc(GL_LESS);
    r.passTimer(RenderPass::Backdrop).end();

    r.passTimer(RenderPass::Colliders).begin();
    const std::vector<ColliderPose> poses =
        settings.drawColliders ? sim.colliderPoses() : std::vector<ColliderPose>{};
    if (settings.drawColliders)
        r.colliders.drawOpaque(poses, settings.glassWalls);
    r.passTimer(RenderPass::Colliders).end();

    const std::uint32_t count = sim.particleCount();
    r.passTimer(RenderPass::Fluid).begin();
    r.meshError.clear();
    r.fluidStagesTimed = false;
    if (settings.surface == SurfaceMode::Mesh && r.drawMesh(sim, settings.mesh)) {
        r.output = r.sceneTarget.id();
    } else if (settings.surface == SurfaceMode::Fluid) {
        const float radius = sim.constants().radius;
        FluidSurfaceParams params;
        params.smoothingIterations = settings.smoothingIterations;
        params.filterRadius = settings.filterRadius * radius;
        params.depthFalloff = std::max(settings.depthFalloff * radius, 1e-6f);
        const FluidSurfaceTimers timers{&r.passTimer(RenderPass::FluidSpheres),
                                        &r.passTimer(RenderPass::FluidSmooth),
                                        &r.passTimer(RenderPass::FluidShade)};
        r.fluid.draw(count, r.sceneColour.id(), r.sceneDepth.id(), r.finalTarget.id(), params,
                     settings.computeSmallSpheres ? &r.splat : nullptr,
                     settings.fluidSphereScale * radius, timers);
        r.fluidStagesTimed = true;
        r.output = r.finalTarget.id();
    } else {
        r.drawSpheres(count, sim.constants().radius, settings.computeSmallSpheres);
    }
    r.passTimer(RenderPass::Fluid).end();

    glBindFramebuffer(GL_FRAMEBUFFER, r.output);
    if (settings.drawDomainBox)
        r.drawDomainBox();
    r.passTimer(RenderPass::Glass).begin();
    if (settings.drawColliders && settings.glassWalls)
        r.colliders.drawGlass(poses);
    r.passTimer(RenderPass::Glass).end();
    r.timer.end();
    glBindVertexArray(0);
}

GLuint Renderer::outputFramebuffer() const {
    return m_impl->output;
}

Image Renderer::readPixels() const {
    Image image = Image::blank(m_impl->size.x, m_impl->size.y);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_impl->output);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, GLsizei(image.width), GLsizei(image.height), GL_RGB, GL_UNSIGNED_BYTE,
                 image.rgb.data());
    flipRows(image.rgb.data(), std::size_t(image.width) * 3, image.height);
    return image;
}

std::optional<double> Renderer::gpuMilliseconds() {
    m_impl->timer.poll();
    if (const auto ns = m_impl->timer.latestNs())
        return double(*ns) * 1e-6;
    return std::nullopt;
}

double Renderer::gpuAverageMilliseconds() {
    m_impl->timer.poll();
    const std::uint64_t frames = m_impl->timer.completed();
    return frames > 0 ? double(m_impl->timer.totalNs()) * 1e-6 / double(frames) : 0.0;
}

RenderPassTimes Renderer::passTimes() {
    RenderPassTimes times;
    for (std::size_t p = 0; p < times.size(); ++p) {
        m_impl->passTimers[p].poll();
        const auto ns = m_impl->passTimers[p].latestNs();
        const bool stage = p >= std::size_t(RenderPass::FluidSpheres);
        times[p] = ns && (!stage || m_impl->fluidStagesTimed) ? double(*ns) * 1e-6 : -1.0;
    }
    return times;
}

const Bounds& Renderer::bounds() const {
    return m_impl->bounds;
}

} // namespace sluice::rt
