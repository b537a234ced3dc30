// The progress line and the slow-run and slow-load estimates.
#include "play/RunProgress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <thread>

#include <unistd.h>

#include "colliders/VolumeMapSize.h"
#include "sluice/format/support/NumberText.h"
#include "sluice/gpu/Gl.h"

namespace sluice::rt {
namespace {

// [us] CPU time of one particle through one substep on llvmpipe, all passes: 10.7 to 14.2 for
// the shipped fluid scenes (dam-break, drop, martin-moyce, wave-sphere; 22 with crates) on a
// 2-vCPU AMD EPYC (docs/performance.md, "What a run costs on llvmpipe"). A run's wall time is
// about this x particles x substeps x steps / cores.
constexpr double kLlvmpipeCoreMicrosPerParticleSubstep = 13.0;

// [ns] CPU time per nominal read of a volume map's quadrature on llvmpipe (2-vCPU AMD EPYC,
// 2026-11-28, docs/performance.md "Volume maps at load"): tank.slc (dense, 514,596 points at
// 5.3 cells per h) built in 2.1 s wall, 12.8 ns; terrain.slc (sparse, 14.3 M leaf voxels at 6
// cells per h) in about 347 s, 54 ns (the same tank baked sparse: 0.73 M leaf voxels in about
// 11.5 s, 49 ns). How many points a map skips as flat or too deep varies with the shape, so this
// is the order of the wait, not a prediction to the second.
constexpr double kLlvmpipeCoreNanosPerDenseMapRead = 13.0;
constexpr double kLlvmpipeCoreNanosPerSparseMapRead = 54.0;

} // namespace

RunProgress::RunProgress(std::uint64_t totalSteps, bool show)
    : m_total(totalSteps), m_show(show), m_start(std::chrono::steady_clock::now()),
      m_lastDraw(m_start) {}

bool RunProgress::stderrIsTerminal() {
    return ::isatty(STDERR_FILENO) == 1;
}

void RunProgress::update(std::uint64_t step) {
    if (!m_show)
        return;
    const auto now = std::chrono::steady_clock::now();
    if (now - m_lastDraw < std::chrono::milliseconds(500) && step != m_total)
        return;
    m_lastDraw = now;
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    const double rate = elapsed > 0.0 ? double(step) / elapsed : 0.0;
    const double left = rate > 0.0 ? double(m_total - std::min(step, m_total)) / rate : 0.0;
    std::fprintf(stderr, "\r\033[Ksluice-play: step %llu / %llu (%.0f %%), %.3g steps/s, %s left",
                 static_cast<unsigned long long>(step), static_cast<unsigned long long>(m_total),
                 100.0 * double(step) / double(std::max<std::uint64_t>(m_total, 1)), rate,
                 formatDuration(left).c_str());
    std::fflush(stderr);
    m_drawn = true;
}

void RunProgress::clear() {
    if (!m_drawn)
        return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    m_drawn = false;
}

std::string formatDuration(double seconds) {
    if (!(seconds >= 0.0) || !std::isfinite(seconds))
        return "?";
    const auto total = static_cast<unsigned long long>(std::llround(seconds));
    char text[48];
    if (total < 60)
        std::snprintf(text, sizeof text, "%llu s", total);
    else if (total < 3600)
        std::snprintf(text, sizeof text, "%llu:%02llu", total / 60, total % 60);
    else
        std::snprintf(text, sizeof text, "%llu:%02llu:%02llu", total / 3600, total / 60 % 60,
                      total % 60);
    return text;
}

bool isSoftwareRenderer(const std::string& renderer) {
    for (const char* name : {"llvmpipe", "softpipe", "SwiftShader", "lavapipe"})
        if (renderer.find(name) != std::string::npos)
            return true;
    return false;
}

std::optional<std::string> slowRunWarning(const std::string& renderer, std::uint64_t particles,
                                          std::uint64_t substeps, std::uint64_t steps,
                                          unsigned cores) {
    if (!isSoftwareRenderer(renderer))
        return std::nullopt;
    const double seconds = kLlvmpipeCoreMicrosPerParticleSubstep * 1e-6 * double(particles) *
                           double(substeps) * double(steps) / double(std::max(cores, 1u));
    if (seconds <= kSlowRunSeconds)
        return std::nullopt;
    return "this run would take about " + formatDuration(seconds) + " on " + renderer +
           " (software OpenGL on " + std::to_string(cores) +
           " CPU cores: " + std::to_string(particles) + " particles x " + std::to_string(steps) +
           " steps of " + std::to_string(substeps) +
           " substeps); fewer --steps or particles, or a GPU, make "
           "it shorter";
}

VolumeMapWork volumeMapWork(const format::Scene& scene,
                            const std::vector<format::ColliderAsset>& colliders) {
    VolumeMapWork work;
    const double h = scene.simulation.kernelRadius; // set by readScene
    for (std::size_t c = 0; c < colliders.size() && c < scene.colliders.size(); ++c) {
        const format::ColliderAsset& asset = colliders[c];
        if (scene.colliders[c].dynamic)
            continue;
        const std::uint64_t points = volumeMapPoints(asset);
        const double support = h / double(scene.colliders[c].scale);
        if (points > shared::kVolumeMapMaxPoints || asset.volumeMapFor(support))
            continue; // no map, or one baked with the collider
        // The quadrature's cells per h: every stride-th grid value, one read each, or
        // kVolumeMapSteps cells, each a trilinear read of 8 values.
        const double stride = volumeMapStride(support, asset.meta.voxelSize);
        const double cells = support / asset.meta.voxelSize;
        const double perH = stride > 0.0 ? cells / stride : double(shared::kVolumeMapSteps);
        const double reads = double(points) * 4.0 / 3.0 * std::numbers::pi * perH * perH * perH *
                             (stride > 0.0 ? 1.0 : 8.0);
        work.points += points;
        (asset.sparse() ? work.sparseReads : work.denseReads) += reads;
    }
    return work;
}

std::optional<std::string> slowLoadWarning(const std::string& renderer, const VolumeMapWork& work,
                                           unsigned cores) {
    if (!isSoftwareRenderer(renderer))
        return std::nullopt;
    const double seconds = 1e-9 *
                           (kLlvmpipeCoreNanosPerDenseMapRead * work.denseReads +
                            kLlvmpipeCoreNanosPerSparseMapRead * work.sparseReads) /
                           double(std::max(cores, 1u));
    if (seconds <= kSlowLoadSeconds)
        return std::nullopt;
    return "building the colliders' volume maps (" + std::to_string(work.points) +
           " grid points) would take about " + formatDuration(seconds) + " on " + renderer +
           " (software OpenGL on " + std::to_string(cores) +
           " CPU cores) before the first step; maps baked with the " +
           "colliders (sluice-bake bake --volume-map), a GPU or a coarser bake make it "
           "shorter";
}

std::optional<std::string> volumeMapNote(const format::Scene& scene, const VolumeMapLoad& load) {
    if (load.built == 0)
        return std::nullopt;
    std::string which;
    for (std::uint32_t c : load.builtFor) {
        const double support =
            double(scene.simulation.kernelRadius) / double(scene.colliders[c].scale);
        which += (which.empty() ? "" : ", ") + format::colliderName(scene.colliders[c]) +
                 " (--volume-map " + format::significant(support) + ")";
    }
    return "built " + std::to_string(load.built) + " volume map" + (load.built == 1 ? "" : "s") +
           " at load in " + formatDuration(load.seconds) + ": " + which +
           "; baked with the collider (sluice-bake bake --volume-map), a map loads at once";
}

std::optional<std::string> slowLoadWarning(const format::Scene& scene,
                                           const std::vector<format::ColliderAsset>& colliders) {
    const VolumeMapWork work = volumeMapWork(scene, colliders);
    if (work.points == 0)
        return std::nullopt;
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return slowLoadWarning(renderer ? renderer : "", work, std::thread::hardware_concurrency());
}

} // namespace sluice::rt
