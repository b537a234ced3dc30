// Where a scene is and how to look at it: its bounding box, its camera, its floor.
#pragma once

#include <vector>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/rt/render/OrbitCamera.h"

namespace sluice::rt {

/// The box around everything the scene places at time 0: the domain box, the fluid blocks,
/// the emitter discs and each collider's grid box in the world. `colliders[i]` belongs to
/// scene.colliders[i]; with fewer assets, the colliders without one are left out. A scene with
/// none of these gives the unit box around the origin.
Bounds sceneBounds(const format::Scene& scene, const std::vector<format::ColliderAsset>& colliders);

/// The scene's own camera when the file sets one, else a camera from the front right, above,
/// framing `bounds` in a viewport of this aspect ratio (width / height).
OrbitCamera sceneCamera(const format::Scene& scene, const Bounds& bounds, float aspect);

/// Height of the floor plane drawn under the scene [m]: the bottom of the domain box when the
/// scene has one, else the bottom of `bounds`.
float floorHeight(const format::Scene& scene, const Bounds& bounds);

} // namespace sluice::rt
