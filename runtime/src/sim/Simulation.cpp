// Simulation: creation from a scene and its colliders, live parameters, and the accessors
// (the state is Simulation::Impl, SimulationImpl.h; the step is SimulationPasses.cpp).
#include "sim/SimulationImpl.h"

#include <chrono>

#include "sluice/format/asset/ShapeCollider.h"
#include "sluice/format/scene/SceneDefaults.h"
#include "sluice/format/scene/SimulationLimits.h"

namespace sluice::rt {
namespace {

// The layouts a caller may force: neighbour lanes and the body pass's work group.
Result<void> checkOptions(const format::Scene& scene, const SimulationOptions& options) {
    if (const std::uint32_t l = options.neighbourLanes; l != 0 && (l > 32 || (l & (l - 1)) != 0))
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + std::to_string(l) +
                        " neighbour lanes; give 0 (chosen for the renderer and the scene), 1, 2, "
                        "4, 8, 16 or 32");
    if (const std::uint32_t g = options.bodyGroupSize;
        g != 0 && (g < shared::kBodyLanesMin || g > shared::kBodyLanesMax || (g & (g - 1)) != 0))
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": a body work group of " + std::to_string(g) +
                        " invocations; give 0 (chosen for the renderer), 8, 16, 32, 64, 128, 256 "
                        "or 512");
    return {};
}

} // namespace

const char* passName(Pass pass) {
    switch (pass) {
    case Pass::Emit:
        return "emit";
    case Pass::Predict:
        return "predict";
    case Pass::Sort:
        return "sort";
    case Pass::Solve:
        return "solve";
    case Pass::Vorticity:
        return "vorticity+xsph";
    case Pass::Bodies:
        return "bodies";
    case Pass::Stats:
        return "stats";
    case Pass::Count:
        break;
    }
    return "?";
}

Result<std::vector<format::ColliderAsset>> loadSceneColliders(const format::Scene& given) {
    // The checks below read the derived parameters (the kernel radius): a scene built in code
    // is completed first, as Simulation::create does.
    format::Scene scene = given;
    if (auto ok = format::completeScene(scene); !ok)
        return ok.error();
    std::vector<format::ColliderAsset> assets;
    for (std::size_t c = 0; c < scene.colliders.size(); ++c) {
        const format::SceneCollider& collider = scene.colliders[c];
        const std::string path =
            collider.resolvedPath.empty() ? collider.asset : collider.resolvedPath;
        auto asset =
            collider.shape ? format::shapeCollider(*collider.shape) : format::readAsset(path);
        if (!asset)
            return fail(asset.error().code, scene.path + ": colliders[" + std::to_string(c) +
                                                "]: " + asset.error().detail);
        assets.push_back(std::move(*asset));
    }
    // Dynamic bodies need a volume and a usable mass, sparse colliders a band as wide as the
    // solver reads: checked here, on the CPU, before any output or GL context exists
    // (Simulation::create sets them up).
    if (auto ok = checkBodies(scene, assets); !ok)
        return ok.error();
    if (auto ok = checkColliderBands(scene, assets); !ok)
        return ok.error();
    return assets;
}

Result<Simulation> Simulation::create(const format::Scene& given,
                                      std::vector<format::ColliderAsset> colliders,
                                      const SimulationOptions& options) {
    // A scene built in code gets the reader's defaults and checks; a read one is unchanged.
    format::Scene scene = given;
    if (auto ok = format::completeScene(scene); !ok)
        return ok.error();
    if (colliders.size() != scene.colliders.size())
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + std::to_string(scene.colliders.size()) +
                        " colliders in the scene but " + std::to_string(colliders.size()) +
                        " assets given");
    if (auto ok = checkOptions(scene, options); !ok)
        return ok.error();
    // The reach a sparse collider's band must hold (setUpBodies checks the bodies' volumes).
    if (auto ok = checkColliderBands(scene, colliders); !ok)
        return ok.error();
    auto impl = std::make_unique<Impl>(scene);
    if (auto ok = impl->size(options); !ok)
        return ok.error();
    impl->colliderAssets = std::move(colliders);
    auto bodies = setUpBodies(scene, impl->colliderAssets, impl->k);
    if (!bodies)
        return bodies.error();
    impl->bodySetup = std::move(*bodies);
    impl->bodyCount = std::uint32_t(impl->bodySetup.records.size());
    impl->kinematic.resize(impl->bodyCount);
    impl->forceMeter.reset(scene.colliders.size(), impl->bodyCount);

    if (auto ok = impl->compilePasses(); !ok)
        return ok.error();
    auto scan = PrefixScan::create(impl->tableSize + 2);
    if (!scan)
        return scan.error();
    impl->scan = std::make_unique<PrefixScan>(std::move(*scan));
    if (auto ok = impl->allocate(); !ok)
        return ok.error();
    if (impl->bodyCount > 0)
        if (auto ok = impl->allocateBodySnapshots(); !ok)
            return ok.error();
    if (auto ok = impl->allocateRemoval(1); !ok)
        return ok.error();

    for (std::size_t c = 0; c < scene.colliders.size(); ++c)
        if (scene.colliders[c].measureForce)
            if (auto ok = impl->forceMeter.set(c, true, impl->colliderDefines()); !ok)
                return ok.error();
    impl->uploadColliderGrids();
    const auto mapsStart = std::chrono::steady_clock::now();
    if (auto ok = impl->buildVolumeMaps(); !ok)
        return ok.error();
    if (impl->volumeMapLoad.built > 0) {
        glFinish(); // the load's report says how long building them took
        impl->volumeMapLoad.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - mapsStart).count();
    }

    const std::size_t ring = 8 + 2 * std::size_t(std::max(1u, scene.simulation.substeps));
    for (std::size_t p = 0; p < std::size_t(Pass::Count); ++p)
        impl->timers.emplace_back(ring);

    if (auto ok = impl->fillBlocks(); !ok)
        return ok.error();
    impl->updateDrawArgs();
    const std::uint32_t zero = 0;
    glClearNamedBufferData(impl->statsBuf.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    // Empty buckets: from here on, every scan leaves them so.
    glClearNamedBufferData(impl->cellCount.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    impl->uploadParams();
    return Simulation(std::move(impl));
}

Simulation::Simulation(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;
Simulation::~Simulation() = default;

Result<void> Simulation::setParameters(const format::SimulationParams& params) {
    Impl& s = *m_impl;
    format::SimulationParams p = params;
    const format::SimulationParams& now = s.scene.simulation;
    p.spacing = now.spacing;
    p.restDensity = now.restDensity;
    p.capacity = now.capacity;
    // The scene reader's ranges (format/SimulationLimits.h): what a file may not hold, a
    // panel or a script may not set either.
    if (auto ok = format::checkSimulationParams(p); !ok)
        return fail(ok.error().code, "simulation parameters: " + ok.error().detail);
    // A larger h reads a dynamic body's distances further out: its sparse band must still hold
    // them, as when the scene was loaded.
    format::Scene changed = s.scene;
    changed.simulation = p;
    if (auto ok = checkColliderBands(changed, s.colliderAssets); !ok)
        return ok;
    if (p.maxIterations > s.maxIterations) {
        // The per-iteration statistics slots and the solve args grow with the cap. Both are
        // allocated before either replaces its buffer, so a failure leaves nothing changed.
        auto stats = gpu::Buffer::create(
            kStatsHeaderBytes + p.maxIterations * sizeof(shared::PbfIterationStats), "stats");
        if (!stats)
            return stats.error();
        auto args = gpu::Buffer::create(s.solveArgsBytes(p.maxIterations), "solve dispatch args");
        if (!args)
            return args.error();
        const std::uint32_t zero = 0;
        glClearNamedBufferData(stats->id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        s.statsBuf = std::move(*stats);
        s.solveArgs = std::move(*args);
    }
    s.maxIterations = p.maxIterations;
    s.scene.simulation = p;
    s.k = deriveConstants(p);
    if (s.volumeMapsH != s.k.h) // the maps integrate over the kernel's support
        return s.buildVolumeMaps();
    return {};
}

const format::SimulationParams& Simulation::parameters() const {
    return m_impl->scene.simulation;
}

void Simulation::setEmittersEnabled(bool enabled) {
    m_impl->emittersOn = enabled;
}
bool Simulation::emittersEnabled() const {
    return m_impl->emittersOn;
}

Result<void> Simulation::setParticles(const std::vector<ParticleState>& particles) {
    Impl& s = *m_impl;
    if (particles.size() > s.capacity)
        return fail(ErrorCode::InvalidArgument, std::to_string(particles.size()) +
                                                    " particles do not fit the capacity " +
                                                    std::to_string(s.capacity));
    s.count = 0;
    s.append(particles);
    for (const ParticleState& p : particles)
        s.nextId = std::max(s.nextId, p.id + 1);
    return {};
}

std::uint32_t Simulation::particleCount() const {
    return m_impl->count;
}
std::uint32_t Simulation::capacity() const {
    return m_impl->capacity;
}
double Simulation::time() const {
    return m_impl->time;
}
std::uint64_t Simulation::steps() const {
    return m_impl->steps;
}
const gpu::Buffer& Simulation::positionBuffer() const {
    return m_impl->pos[m_impl->cur];
}
const gpu::Buffer& Simulation::velocityBuffer() const {
    return m_impl->vel[m_impl->cur];
}
std::uint64_t Simulation::gpuBytes() const {
    return m_impl->gpuBytes;
}
std::uint64_t Simulation::bytesPerParticle() const {
    return m_impl->bytesPerParticle;
}
GpuCommandCount Simulation::commandCount() const {
    return m_impl->commands;
}
std::uint32_t Simulation::neighbourLanes() const {
    return m_impl->lanes;
}

bool Simulation::neighbourTexels() const {
    return m_impl->neighboursAsTexels;
}

glm::uvec3 Simulation::neighbourGridCells() const {
    return m_impl->denseGridDims();
}

Result<void> Simulation::setDrag(const std::optional<BodyDrag>& drag) {
    Impl& s = *m_impl;
    if (drag) {
        if (drag->body >= s.bodyCount)
            return fail(ErrorCode::InvalidArgument, "drag: body " + std::to_string(drag->body) +
                                                        " of " + std::to_string(s.bodyCount));
        const float values[] = {drag->anchor.x, drag->anchor.y, drag->anchor.z,
                                drag->target.x, drag->target.y, drag->target.z};
        for (float v : values)
            if (!std::isfinite(v))
                return fail(ErrorCode::NonFinite, "drag: a point is not finite");
    }
    s.drag = drag;
    return {};
}

std::uint32_t Simulation::particlesRemovedAtSpawn() const {
    return m_impl->removedAtSpawn;
}

const PbfConstants& Simulation::constants() const {
    return m_impl->k;
}
const format::Scene& Simulation::scene() const {
    return m_impl->scene;
}

} // namespace sluice::rt
