// A scene's derived defaults and its whole check, in one place: the scene reader fills a file's
// missing keys with them, and a program that builds a Scene in code completes it with
// completeScene (Simulation::create does so itself).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sluice/format/scene/Scene.h"
#include "sluice/format/support/Result.h"

namespace sluice::format {

/// [s] an emitter's stop when none is given: start + this.
inline constexpr float kDefaultEmitterDuration = 10.0f;

/// The derived kernel radius: 2 * spacing [m].
float defaultKernelRadius(float spacing);
/// The derived s_corr delta q: 0.2 * h [m].
float defaultScorrDeltaQ(float kernelRadius);
/// The derived vorticity confinement epsilon: 0.01 * sqrt(9.81 * h) [m/s].
float defaultVorticity(float kernelRadius);

/// The derived voxel of a shape collider's field: spacing / 2 [m].
float defaultShapeVoxel(float spacing);

/// Substeps from a CFL estimate (docs/scene-format.md "Derived defaults"): the fastest a particle
/// is likely to move is its start or exit speed plus a free fall over the scene's height, and one
/// substep moves it at most 0.4 h; 1 to 64. Precondition: timeStep and kernelRadius > 0.
std::uint32_t defaultSubsteps(const Scene& scene);

/// The derived capacity: the fluid blocks' particles plus everything each emitter emits between
/// its start and stop. SizeOverflow (the message says what to change) beyond kMaxSceneParticles.
/// Precondition: spacing > 0 and every block and emitter finite.
Result<std::uint32_t> defaultCapacity(const Scene& scene);

/// Every drain a box with finite corners and max > min on each axis, at most kMaxDrains of them:
/// NonFinite or InvalidArgument, the detail naming the drain ("[1].box.max: ...") after `what`'s
/// count for too many.
Result<void> checkDrains(const std::vector<Drain>& drains, const std::string& what);

/// Completes a scene built in code as readScene completes a file: every derived field of the
/// parameters (0 or kDerived, Scene.h) gets its default, every emitter direction is made a unit
/// vector, and an emitter's stop of 0 becomes start + kDefaultEmitterDuration. Then checks the
/// whole scene against the ranges the reader enforces (docs/scene-format.md): NonFinite for a
/// number that is not finite, InvalidArgument naming the field (`fluid[0].max`, `colliders[2]
/// .scale`, `simulation.capacity`) and its range, SizeOverflow for more particles than the limit.
/// A scene with neither fluid nor emitters is valid when it gives a capacity (a game adds its
/// water). Nothing in `scene` changes on failure. Idempotent: a read scene stays as it is.
Result<void> completeScene(Scene& scene);

} // namespace sluice::format
