// What a long headless run tells the person waiting for it: a progress line on a terminal, and
// before it starts, a warning when a software renderer would take minutes.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::rt {

/// A one-line "step S / N, R steps/s, T left" on stderr, redrawn in place at most twice a
/// second, only when stderr is a terminal (a log file or a pipe gets none of it).
class RunProgress {
public:
    /// `show` false: every call does nothing.
    RunProgress(std::uint64_t totalSteps, bool show);

    /// After step `step` of the run.
    void update(std::uint64_t step);
    /// Erases the line, so that what is printed next starts on a clean line.
    void clear();

    /// True when stderr is a terminal (isatty).
    static bool stderrIsTerminal();

private:
    std::uint64_t m_total;
    bool m_show;
    bool m_drawn = false;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_lastDraw;
};

/// "1:05:09", "4:07" or "12 s": a duration for people.
std::string formatDuration(double seconds);

/// Software OpenGL (Mesa's llvmpipe or softpipe, SwiftShader) by its GL_RENDERER string.
bool isSoftwareRenderer(const std::string& renderer);

/// Above this many seconds a run on a software renderer is warned about before it starts.
inline constexpr double kSlowRunSeconds = 180.0;

/// The warning for a run of `steps` steps of `substeps` substeps over `particles` particles on
/// `renderer` with `cores` CPU cores when its estimated time passes kSlowRunSeconds; nothing on
/// a GPU or for a shorter run. The estimate is linear in particles x substeps x steps, with the
/// cost per particle-substep measured on llvmpipe (docs/performance.md), shared over the cores.
std::optional<std::string> slowRunWarning(const std::string& renderer, std::uint64_t particles,
                                          std::uint64_t substeps, std::uint64_t steps,
                                          unsigned cores);

/// Above this many seconds, the volume maps a scene builds when it loads on a software renderer
/// are warned about before they are built (the load says nothing while it works).
inline constexpr double kSlowLoadSeconds = 30.0;

/// The volume maps a scene builds at load (docs/pbf.md, "Volume maps"):
/// their points, and the quadrature's nominal reads (points x the support ball in its cells),
/// dense and sparse grids apart (a sparse read goes through NanoVDB's accessor).
struct VolumeMapWork {
    std::uint64_t points = 0;
    double denseReads = 0.0;
    double sparseReads = 0.0;
};

/// What the scene's static and kinematic colliders' maps would be (a map baked with the
/// collider for the scene's support is not built, nor one over kVolumeMapMaxPoints). Colliders as
/// loadSceneColliders gives them.
VolumeMapWork volumeMapWork(const format::Scene& scene,
                            const std::vector<format::ColliderAsset>& colliders);

/// The warning for building `work` on `renderer` with `cores` CPU cores when its estimated time
/// passes kSlowLoadSeconds; nothing on a GPU or for less. The cost per read was measured on
/// llvmpipe (docs/performance.md, "Volume maps at load").
std::optional<std::string> slowLoadWarning(const std::string& renderer, const VolumeMapWork& work,
                                           unsigned cores);

/// What a load that built volume maps says (nothing when all were baked or none is needed):
/// how many, how long, and for each collider the bake option that would have saved it.
std::optional<std::string> volumeMapNote(const format::Scene& scene, const VolumeMapLoad& load);

/// slowLoadWarning for `scene` and its colliders on the current GL context's renderer, with the
/// machine's cores: what sluice-play (headless and the window) and Python's Simulation say before
/// they build a scene.
std::optional<std::string> slowLoadWarning(const format::Scene& scene,
                                           const std::vector<format::ColliderAsset>& colliders);

} // namespace sluice::rt
