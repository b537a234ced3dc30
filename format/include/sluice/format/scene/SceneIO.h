// Reading scene files (JSON, docs/scene-format.md) into format::Scene, with derived defaults.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"

namespace sluice::format {

/// [bytes] largest scene file readScene / parseScene accept (SizeOverflow beyond); real scenes
/// are a few kB.
inline constexpr std::uint64_t kMaxSceneFileBytes = std::uint64_t(16) << 20;

/// How readScene / parseScene treat what the scene refers to.
struct SceneReadOptions {
    /// Check that every collider's asset file exists (Io error "collider asset not found"
    /// otherwise). False parses a scene whose baked .slc colliders are not built yet.
    bool checkAssets = true;
    /// What messages and Scene::path call the scene instead of the file's path, for a scene that
    /// is no file (a Python dict: "<scene dict>"); empty: the file's path. Collider assets are
    /// still relative to the file's folder, and the default name is still its stem.
    std::string label;
};

/// Reads and validates a scene file. Every SimulationParams field holds a value afterwards (the
/// defaults derived from `spacing` are filled in, docs/scene-format.md "Derived defaults"); every
/// emitter direction is a unit vector; every collider's resolvedPath is its asset path resolved
/// against the scene file's folder. Errors name the file, the JSON path and the problem
/// ("scene.json: colliders[1].friction: 1.5 is out of range [0, 1]"): Io (cannot read the file,
/// or a collider asset is missing), SizeOverflow (file over kMaxSceneFileBytes, or more than
/// kMaxSceneParticles particles), UnsupportedVersion ("version" > kSceneVersion), BadMetadata
/// (not JSON, unknown or duplicate key, wrong type, missing required key), NonFinite (NaN,
/// infinity, a number beyond the float range), InvalidArgument (a value out of its range).
Result<Scene> readScene(const std::filesystem::path& file, const SceneReadOptions& options = {});

/// readScene on text already in memory. `fileForMessagesAndRelativePaths` names the scene in
/// messages and in Scene::path (unless options.label does), gives the default name (its stem),
/// and is the file collider asset paths are relative to (its folder); it need not exist.
Result<Scene> parseScene(std::string_view json,
                         const std::filesystem::path& fileForMessagesAndRelativePaths,
                         const SceneReadOptions& options = {});

/// Particles a fluid block holds at rest spacing `spacing` [m], by the lattice rule of
/// docs/pbf.md "Initial state" (float arithmetic as written there). Exact up to
/// kMaxSceneParticles; a block that would hold more returns some larger count without
/// enumerating it. Precondition: spacing > 0, the block's numbers finite.
std::uint64_t blockParticleCount(const FluidBlock& block, float spacing);

/// Points in one emitter disc of radius `radius` [m] at spacing `spacing` [m]: integers (a, b)
/// with spacing^2 (a^2 + b^2) <= radius^2 (docs/pbf.md step 1). Exact up to kMaxSceneParticles,
/// some larger count beyond. Precondition: spacing > 0, radius finite.
std::uint64_t emitterDiscCount(float radius, float spacing);

} // namespace sluice::format
