// Scene files: the colliders' objects (placement, motion, dynamic body) and the readers of
// ranged numbers the whole scene reader shares.
#include "scene/SceneReading.h"

#include <string>

namespace sluice::format::scene_detail {
namespace {

namespace fs = std::filesystem;

// "1.5 is out of range [0, 1]" or "-2 is out of range: must be > 0", plus an optional note.
void checkRange(double value, const std::string& shown, const std::string& path,
                const ParamRange& range) {
    std::string problem = rangeProblem(value, shown, range);
    if (!problem.empty())
        throwAt(ErrorCode::InvalidArgument, path, std::move(problem));
}

DynamicBody readDynamic(const rj::Value& value, const std::string& path) {
    const JsonObject o(
        value, path,
        {"density", "mass", "linearVelocity", "angularVelocity", "friction", "restitution"});
    DynamicBody d;
    if (o.has("density") == o.has("mass"))
        throwAt(ErrorCode::BadMetadata, path,
                "needs exactly one of \"density\" [kg/m^3] and \"mass\" [kg]");
    if (const rj::Value* v = o.find("density"))
        d.density = readFloatIn(*v, o.pathOf("density"), above(0.0f));
    if (const rj::Value* v = o.find("mass"))
        d.mass = readFloatIn(*v, o.pathOf("mass"), above(0.0f));
    if (const rj::Value* v = o.find("linearVelocity"))
        d.linearVelocity = readVec3(*v, o.pathOf("linearVelocity"));
    if (const rj::Value* v = o.find("angularVelocity"))
        d.angularVelocityDegrees = readVec3(*v, o.pathOf("angularVelocity"));
    if (const rj::Value* v = o.find("friction"))
        d.friction = readFloatIn(*v, o.pathOf("friction"), closed(0.0f, 2.0f));
    if (const rj::Value* v = o.find("restitution"))
        d.restitution = readFloatIn(*v, o.pathOf("restitution"), closed(0.0f, 1.0f));
    return d;
}

// motion.keyframes: at least one key, strictly increasing times, each a full placement.
void readKeyframes(const JsonObject& o, const JsonObject& m, const rj::Value& value,
                   SceneCollider& c) {
    if (m.has("linearVelocity") || m.has("angularVelocity"))
        throwAt(ErrorCode::BadMetadata, m.path(),
                "has both \"keyframes\" and velocities; a collider moves by one or the "
                "other");
    // The keys give the whole placement (docs/pbf.md), so a rest pose would be ignored.
    for (const std::string_view key : {"translation", "rotation"})
        if (o.has(key))
            throwAt(ErrorCode::BadMetadata, o.pathOf(key),
                    "not allowed with motion.keyframes: the keys place the collider "
                    "(give \"" +
                        std::string(key) + "\" in each key)");
    const std::string keysPath = m.pathOf("keyframes");
    const rj::Value& keys = detail::requireArray(value, keysPath);
    if (keys.Empty())
        throwAt(ErrorCode::BadMetadata, keysPath, "needs at least 1 key, got none");
    for (rj::SizeType i = 0; i < keys.Size(); ++i) {
        const JsonObject k(keys[i], detail::joinIndex(keysPath, i),
                           {"time", "translation", "rotation"});
        ColliderKey key;
        key.time = readFloat(k.require("time"), k.pathOf("time"));
        if (!c.keys.empty() && !(key.time > c.keys.back().time))
            throwAt(ErrorCode::InvalidArgument, k.pathOf("time"),
                    formatNumber(k.require("time").GetDouble()) +
                        " is not after the previous key's time " + formatFloat(c.keys.back().time) +
                        " (times must strictly increase)");
        key.translation = readVec3(k.require("translation"), k.pathOf("translation"));
        if (const rj::Value* r = k.find("rotation"))
            key.rotationDegrees = readVec3(*r, k.pathOf("rotation"));
        c.keys.push_back(key);
    }
}

// The collider's "motion": constant velocities or keyframes, one or the other.
void readMotion(const JsonObject& o, const rj::Value& mv, SceneCollider& c) {
    const JsonObject m(mv, o.pathOf("motion"), {"linearVelocity", "angularVelocity", "keyframes"});
    if (const rj::Value* v = m.find("linearVelocity"))
        c.linearVelocity = readVec3(*v, m.pathOf("linearVelocity"));
    if (const rj::Value* v = m.find("angularVelocity"))
        c.angularVelocityDegrees = readVec3(*v, m.pathOf("angularVelocity"));
    if (const rj::Value* kv = m.find("keyframes"))
        readKeyframes(o, m, *kv, c);
}

// The collider's asset exists and is a file (else the error says to bake it).
void checkAssetFile(const JsonObject& o, const std::string& resolved) {
    std::error_code ec;
    const fs::file_status st = fs::status(resolved, ec);
    if (!fs::exists(st))
        throwAt(ErrorCode::Io, o.pathOf("asset"),
                "collider asset not found: " + resolved + " (bake it with sluice-bake)");
    if (!fs::is_regular_file(st))
        throwAt(ErrorCode::Io, o.pathOf("asset"), "collider asset is not a file: " + resolved);
}

// "shape": one key naming the kind, as a fluid block's: {"sphere": {"radius"}}, {"box":
// {"size"}} or {"capsule": {"radius", "height"}}, each with an optional "voxel".
ColliderShape readShape(const rj::Value& value, const std::string& path) {
    const JsonObject o(value, path, {"sphere", "box", "capsule"});
    if (int(o.has("sphere")) + int(o.has("box")) + int(o.has("capsule")) != 1)
        throwAt(ErrorCode::BadMetadata, path,
                "needs exactly one of \"sphere\", \"box\" and \"capsule\"");
    ColliderShape shape;
    shape.kind = o.has("sphere") ? ColliderShape::Kind::Sphere
                 : o.has("box")  ? ColliderShape::Kind::Box
                                 : ColliderShape::Kind::Capsule;
    const char* kind = shapeName(shape.kind);
    // Each kind's own keys: another kind's key is unknown here.
    const std::string at = o.pathOf(kind);
    const JsonObject k = shape.kind == ColliderShape::Kind::Box
                             ? JsonObject(o.require(kind), at, {"size", "voxel"})
                         : shape.kind == ColliderShape::Kind::Sphere
                             ? JsonObject(o.require(kind), at, {"radius", "voxel"})
                             : JsonObject(o.require(kind), at, {"radius", "height", "voxel"});
    if (shape.kind == ColliderShape::Kind::Box) {
        shape.size = readVec3(k.require("size"), k.pathOf("size"));
        for (int a = 0; a < 3; ++a)
            if (!(shape.size[a] > 0.0f))
                throwAt(ErrorCode::InvalidArgument, k.pathOf("size"),
                        vecText(shape.size) + " must be > 0 on every axis");
    } else {
        shape.radius = readFloatIn(k.require("radius"), k.pathOf("radius"), above(0.0f));
    }
    if (shape.kind == ColliderShape::Kind::Capsule)
        shape.height =
            readFloatIn(k.require("height"), k.pathOf("height"), atLeast(2.0f * shape.radius),
                        "at least 2 * radius: the capsule's length tip to tip");
    if (const rj::Value* v = k.find("voxel"))
        shape.voxelSize = readFloatIn(*v, k.pathOf("voxel"), above(0.0f));
    return shape;
}

} // namespace

float readFloatIn(const rj::Value& value, const std::string& path, const ParamRange& range) {
    const float f = readFloat(value, path);
    checkRange(f, formatNumber(value.GetDouble()), path, range);
    return f;
}

float readFloatIn(const rj::Value& value, const std::string& path, Bounds b,
                  const std::string& note) {
    return readFloatIn(value, path, ParamRange{b.lo, b.hi, b.loOpen, b.hiOpen, note});
}

std::string vecText(glm::vec3 v) {
    return "[" + formatFloat(v.x) + ", " + formatFloat(v.y) + ", " + formatFloat(v.z) + "]";
}

SceneCollider readCollider(const rj::Value& value, const std::string& path,
                           const fs::path& sceneFile, bool checkAssets) {
    const JsonObject o(value, path,
                       {"asset", "shape", "translation", "rotation", "scale", "friction", "motion",
                        "dynamic", "measureForce"});
    SceneCollider c;
    if (o.has("asset") == o.has("shape"))
        throwAt(ErrorCode::BadMetadata, path,
                o.has("asset") ? "has both \"asset\" and \"shape\"; a collider is one of them"
                               : "missing required key \"asset\" (a baked collider) or \"shape\"");
    if (const rj::Value* v = o.find("shape")) {
        c.shape = readShape(*v, o.pathOf("shape"));
    } else {
        c.asset = detail::readString(o.require("asset"), o.pathOf("asset"));
        if (c.asset.empty() || c.asset.find('\0') != std::string::npos)
            throwAt(ErrorCode::BadMetadata, o.pathOf("asset"),
                    "expected a file path, got an empty string or one with a NUL byte");
        c.resolvedPath = (sceneFile.parent_path() / fs::path(c.asset)).lexically_normal().string();
    }
    if (const rj::Value* v = o.find("translation"))
        c.translation = readVec3(*v, o.pathOf("translation"));
    if (const rj::Value* v = o.find("rotation"))
        c.rotationDegrees = readVec3(*v, o.pathOf("rotation"));
    if (const rj::Value* v = o.find("scale"))
        c.scale = readFloatIn(*v, o.pathOf("scale"), above(0.0f));
    if (const rj::Value* v = o.find("friction"))
        c.friction = readFloatIn(*v, o.pathOf("friction"), closed(0.0f, 1.0f));

    if (const rj::Value* mv = o.find("motion"))
        readMotion(o, *mv, c);

    if (const rj::Value* dv = o.find("dynamic")) {
        if (o.has("motion"))
            throwAt(ErrorCode::BadMetadata, o.pathOf("dynamic"),
                    "not allowed with \"motion\": a collider is moved by the fluid (dynamic) or "
                    "by its motion (kinematic), not both");
        c.dynamic = readDynamic(*dv, o.pathOf("dynamic"));
    }

    if (const rj::Value* v = o.find("measureForce")) {
        if (!v->IsBool())
            throwAt(ErrorCode::BadMetadata, o.pathOf("measureForce"), "expected true or false");
        c.measureForce = v->GetBool();
        if (c.measureForce && c.dynamic)
            throwAt(ErrorCode::BadMetadata, o.pathOf("measureForce"),
                    "not allowed on a dynamic body: its force is always reported");
    }
    if (checkAssets && !c.shape)
        checkAssetFile(o, c.resolvedPath);
    return c;
}

} // namespace sluice::format::scene_detail
