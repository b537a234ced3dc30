// Private: what the scene reader's parts share (SceneIO.cpp, SceneColliders.cpp): number ranges
// checked as the values are stored, and the colliders' objects.
#pragma once

#include <filesystem>
#include <limits>
#include <string>

#include "sluice/format/scene/Scene.h"
#include "sluice/format/scene/SimulationLimits.h"
#include "support/Json.h"

namespace sluice::format::scene_detail {

namespace rj = detail::rj;
using detail::formatFloat;
using detail::formatNumber;
using detail::JsonObject;
using detail::readFloat;
using detail::readVec3;
using detail::throwAt;

inline constexpr float kInf = std::numeric_limits<float>::infinity();

// Allowed interval of a number; compared in float, as the value is stored.
struct Bounds {
    float lo = -kInf;
    float hi = kInf;
    bool loOpen = false;
    bool hiOpen = false;
};

inline Bounds closed(float lo, float hi) {
    return {lo, hi, false, false};
}
inline Bounds atLeast(float lo) {
    return {lo, kInf, false, false};
}
inline Bounds above(float lo) {
    return {lo, kInf, true, false};
}

/// A float at `path` in `range`, or a JsonError saying "1.5 is out of range [0, 1]" (or "-2 is
/// out of range: must be > 0") with the range's note.
float readFloatIn(const rj::Value& value, const std::string& path, const ParamRange& range);
float readFloatIn(const rj::Value& value, const std::string& path, Bounds b,
                  const std::string& note = {});

/// "[x, y, z]" as the messages show vectors.
std::string vecText(glm::vec3 v);

/// colliders[i] of the scene file `sceneFile` (its asset resolved against the file's folder and,
/// with `checkAssets`, required to exist), its motion or dynamic body included.
SceneCollider readCollider(const rj::Value& value, const std::string& path,
                           const std::filesystem::path& sceneFile, bool checkAssets);

} // namespace sluice::format::scene_detail
