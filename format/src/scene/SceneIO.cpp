// Scene files: JSON (read with cereal's rapidjson) to format::Scene, validated, defaults derived.
#include "sluice/format/scene/SceneIO.h"
#include "sluice/format/scene/SceneDefaults.h"
#include "sluice/format/scene/SimulationLimits.h"
#include "sluice/format/scene/SolverReach.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <new>
#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "scene/SceneReading.h"
#include "support/Json.h"

namespace sluice::format {

namespace {

using namespace scene_detail;
namespace fs = std::filesystem;
using detail::readNumber;

constexpr detail::JsonFileKind kSceneKind{"the scene", "the scene file", "scene-file limit",
                                          kMaxSceneFileBytes};

// Reads {"min": [..], "max": [..]} with max > min on every axis.
void readMinMax(const rj::Value& value, const std::string& path, glm::vec3& min, glm::vec3& max) {
    const JsonObject o(value, path, {"min", "max"});
    min = readVec3(o.require("min"), o.pathOf("min"));
    max = readVec3(o.require("max"), o.pathOf("max"));
    for (int a = 0; a < 3; ++a)
        if (!(max[a] > min[a]))
            throwAt(ErrorCode::InvalidArgument, o.pathOf("max"),
                    vecText(max) + " must exceed min " + vecText(min) + " on every axis (" +
                        "xyz"[a] + ": " + formatFloat(max[a]) + " <= " + formatFloat(min[a]) + ")");
}

// Builds a Scene from a parsed document; every problem is thrown as a JsonError.
class SceneParser {
public:
    SceneParser(const fs::path& file, const SceneReadOptions& options)
        : m_file(file), m_options(options) {}

    Scene parse(const rj::Value& root);

private:
    void readVersion(const rj::Value& root);
    void readSimulation(const rj::Value* value);
    FluidBlock readBlock(const rj::Value& value, const std::string& path);
    Emitter readEmitter(const rj::Value& value, const std::string& path);
    void readCamera(const rj::Value& value, const std::string& path);
    void deriveCapacity();

    const fs::path& m_file;
    const SceneReadOptions& m_options;
    Scene m_scene;
    bool m_givenSubsteps = false;
    bool m_givenCapacity = false;
    std::uint64_t m_blockParticles = 0;
};

void SceneParser::readVersion(const rj::Value& root) {
    // Before the key check: a newer file may well have keys this build does not know.
    if (!root.IsObject())
        throwAt(ErrorCode::BadMetadata, "", "expected an object, got " + detail::describe(root));
    const auto it = root.FindMember("version");
    if (it == root.MemberEnd())
        return;
    const double v = readNumber(it->value, "version");
    if (v != std::floor(v))
        throwAt(ErrorCode::BadMetadata, "version", "expected an integer, got " + formatNumber(v));
    if (v > double(kSceneVersion))
        throwAt(ErrorCode::UnsupportedVersion, "version",
                "version " + formatNumber(v) + " is newer than this build reads (" +
                    std::to_string(kSceneVersion) + "); update Sluice");
    if (v < 1)
        throwAt(ErrorCode::InvalidArgument, "version",
                formatNumber(v) + " is out of range [1, " + std::to_string(kSceneVersion) + "]");
}

void SceneParser::readSimulation(const rj::Value* value) {
    SimulationParams& p = m_scene.simulation;
    static const rj::Value kEmpty(rj::kObjectType);
    const JsonObject o(value ? *value : kEmpty, "simulation",
                       {"spacing", "kernelRadius", "restDensity", "timeStep", "substeps",
                        "minIterations", "maxIterations", "targetDensityError", "relaxation",
                        "scorrK", "scorrN", "scorrDeltaQ", "xsph", "vorticity", "gravity",
                        "capacity", "boundary"});
    // Ranges from the one table (SimulationLimits.h); spacing first, as the kernel radius's
    // range and every default are in units of it, then the kernel radius, which bounds
    // scorrDeltaQ.
    auto rangeOf = [&](std::string_view key) {
        return simulationParamRange(key, p.spacing, p.kernelRadius);
    };
    auto floatIn = [&](std::string_view key, float& out) {
        const rj::Value* v = o.find(key);
        if (v)
            out = readFloatIn(*v, o.pathOf(key), rangeOf(key));
        return v != nullptr;
    };
    auto intIn = [&](std::string_view key, std::uint32_t& out) {
        const rj::Value* v = o.find(key);
        if (v) {
            const ParamRange r = rangeOf(key);
            out = std::uint32_t(
                detail::readInteger(*v, o.pathOf(key), std::int64_t(r.lo), std::int64_t(r.hi)));
        }
        return v != nullptr;
    };

    floatIn("spacing", p.spacing);
    const float s = p.spacing;
    p.kernelRadius = defaultKernelRadius(s); // the default, unless given
    floatIn("kernelRadius", p.kernelRadius);
    const float h = p.kernelRadius;
    floatIn("restDensity", p.restDensity);
    floatIn("timeStep", p.timeStep);
    m_givenSubsteps = intIn("substeps", p.substeps);
    intIn("minIterations", p.minIterations);
    const bool givenMax = intIn("maxIterations", p.maxIterations);
    if (p.maxIterations < p.minIterations)
        throwAt(ErrorCode::InvalidArgument, o.pathOf("maxIterations"),
                std::to_string(p.maxIterations) + (givenMax ? "" : " (the default)") +
                    " is less than minIterations " + std::to_string(p.minIterations));
    floatIn("targetDensityError", p.targetDensityError);
    floatIn("relaxation", p.relaxation);
    floatIn("scorrK", p.scorrK);
    floatIn("scorrN", p.scorrN);
    if (!floatIn("scorrDeltaQ", p.scorrDeltaQ))
        p.scorrDeltaQ = defaultScorrDeltaQ(h);
    floatIn("xsph", p.xsph);
    if (!floatIn("vorticity", p.vorticity))
        p.vorticity = defaultVorticity(h);
    if (const rj::Value* g = o.find("gravity"))
        p.gravity = readVec3(*g, o.pathOf("gravity"));
    m_givenCapacity = intIn("capacity", p.capacity);
    if (const rj::Value* v = o.find("boundary")) {
        const std::string text = detail::readString(*v, o.pathOf("boundary"));
        const BoundaryModelName model = boundaryModelNamed(text);
        if (model == BoundaryModelName::Unknown)
            throwAt(ErrorCode::InvalidArgument, o.pathOf("boundary"), unknownBoundaryModel(text));
        m_scene.namesRemovedBoundaryModel = model == BoundaryModelName::Removed;
    }
}

FluidBlock SceneParser::readBlock(const rj::Value& value, const std::string& path) {
    const JsonObject o(value, path, {"box", "sphere", "velocity"});
    const float s = m_scene.simulation.spacing;
    FluidBlock b;
    if (o.has("box") == o.has("sphere"))
        throwAt(ErrorCode::BadMetadata, path,
                o.has("box") ? "has both \"box\" and \"sphere\"; a fluid block is one of them"
                             : "missing required key \"box\" or \"sphere\"");
    std::string shapePath;
    if (const rj::Value* box = o.find("box")) {
        shapePath = o.pathOf("box");
        b.shape = FluidBlock::Shape::Box;
        readMinMax(*box, shapePath, b.min, b.max);
    } else {
        shapePath = o.pathOf("sphere");
        const JsonObject sphere(o.require("sphere"), shapePath, {"center", "radius"});
        b.shape = FluidBlock::Shape::Sphere;
        b.center = readVec3(sphere.require("center"), sphere.pathOf("center"));
        b.radius = readFloatIn(sphere.require("radius"), sphere.pathOf("radius"), above(0.0f));
    }
    if (const rj::Value* v = o.find("velocity"))
        b.velocity = readVec3(*v, o.pathOf("velocity"));

    const std::uint64_t n = blockParticleCount(b, s);
    if (n == 0)
        throwAt(ErrorCode::InvalidArgument, shapePath,
                "holds no particles at spacing " + formatFloat(s) +
                    (b.shape == FluidBlock::Shape::Box
                         ? " (every side must be at least one spacing long)"
                         : " (the radius must be at least spacing / 2)"));
    if (n > kMaxSceneParticles)
        throwAt(ErrorCode::SizeOverflow, shapePath,
                "holds more than " + std::to_string(kMaxSceneParticles) +
                    " particles (the limit) at spacing " + formatFloat(s));
    m_blockParticles += n;
    return b;
}

Emitter SceneParser::readEmitter(const rj::Value& value, const std::string& path) {
    const JsonObject o(value, path,
                       {"position", "direction", "radius", "speed", "rate", "start", "stop"});
    const float s = m_scene.simulation.spacing;
    Emitter e;
    e.position = readVec3(o.require("position"), o.pathOf("position"));
    const glm::vec3 d = readVec3(o.require("direction"), o.pathOf("direction"));
    // Normalised in double: a float length of a tiny vector would underflow to 0.
    const glm::dvec3 dd(d);
    const double length = std::sqrt(glm::dot(dd, dd));
    if (!(length > 0.0))
        throwAt(ErrorCode::InvalidArgument, o.pathOf("direction"),
                vecText(d) + " has no direction (zero vector)");
    e.direction = glm::vec3(dd / length);
    e.radius = readFloatIn(o.require("radius"), o.pathOf("radius"), atLeast(0.5f * s),
                           "at least spacing / 2");
    e.speed = readFloatIn(o.require("speed"), o.pathOf("speed"), above(0.0f));
    if (const rj::Value* v = o.find("rate"))
        e.rate = readFloatIn(*v, o.pathOf("rate"), atLeast(0.0f));
    if (const rj::Value* v = o.find("start"))
        e.start = readFloatIn(*v, o.pathOf("start"), atLeast(0.0f));
    if (const rj::Value* v = o.find("stop"))
        e.stop = readFloatIn(*v, o.pathOf("stop"), above(e.start),
                             "after start " + formatFloat(e.start));
    else
        e.stop = e.start + kDefaultEmitterDuration;
    if (emitterDiscCount(e.radius, s) > kMaxSceneParticles)
        throwAt(ErrorCode::SizeOverflow, o.pathOf("radius"),
                "a disc of radius " + formatFloat(e.radius) + " holds more than " +
                    std::to_string(kMaxSceneParticles) + " particles (the limit) at spacing " +
                    formatFloat(s));
    return e;
}

void SceneParser::readCamera(const rj::Value& value, const std::string& path) {
    const JsonObject o(value, path, {"position", "target", "fov"});
    Camera& cam = m_scene.camera;
    cam.position = readVec3(o.require("position"), o.pathOf("position"));
    cam.target = readVec3(o.require("target"), o.pathOf("target"));
    if (cam.target == cam.position)
        throwAt(ErrorCode::InvalidArgument, o.pathOf("target"),
                vecText(cam.target) + " equals the position; the camera needs a direction");
    if (const rj::Value* v = o.find("fov"))
        cam.fovDegrees = readFloatIn(*v, o.pathOf("fov"), Bounds{1.0f, 179.0f, true, true});
    cam.set = true;
}

// Capacity: the blocks' particles plus everything each emitter emits between start and stop
// (SceneDefaults.h, as for a scene built in code).
void SceneParser::deriveCapacity() {
    SimulationParams& p = m_scene.simulation;
    if (m_blockParticles > kMaxSceneParticles)
        throwAt(ErrorCode::SizeOverflow, "fluid",
                "the fluid blocks hold " + std::to_string(m_blockParticles) +
                    " particles, more than the limit " + std::to_string(kMaxSceneParticles));
    if (m_givenCapacity) {
        if (p.capacity < m_blockParticles)
            throwAt(ErrorCode::InvalidArgument, "simulation.capacity",
                    std::to_string(p.capacity) + " is smaller than the " +
                        std::to_string(m_blockParticles) + " particles the fluid blocks hold");
        return;
    }
    const Result<std::uint32_t> capacity = defaultCapacity(m_scene);
    if (!capacity)
        throwAt(capacity.error().code, "simulation.capacity", capacity.error().detail);
    p.capacity = *capacity;
}

Scene SceneParser::parse(const rj::Value& root) {
    readVersion(root);
    const JsonObject o(root, "",
                       {"version", "name", "description", "simulation", "fluid", "emitters",
                        "colliders", "drains", "domain", "camera"});
    m_scene.path = m_options.label.empty() ? m_file.string() : m_options.label;
    m_scene.name = m_file.stem().string();
    if (const rj::Value* v = o.find("name"))
        m_scene.name = detail::readString(*v, "name");
    if (const rj::Value* v = o.find("description"))
        (void)detail::readString(*v, "description");
    readSimulation(o.find("simulation"));

    if (const rj::Value* v = o.find("domain")) {
        glm::vec3 min, max;
        readMinMax(*v, "domain", min, max);
        const float s = m_scene.simulation.spacing;
        for (int a = 0; a < 3; ++a)
            if (max[a] - min[a] < s)
                throwAt(ErrorCode::InvalidArgument, "domain.max",
                        std::string("the domain is ") + formatFloat(max[a] - min[a]) + " wide on " +
                            "xyz"[a] + ", less than one spacing " + formatFloat(s));
        m_scene.domainMin = min;
        m_scene.domainMax = max;
    }
    if (const rj::Value* v = o.find("fluid")) {
        const rj::Value& blocks = detail::requireArray(*v, "fluid");
        for (rj::SizeType i = 0; i < blocks.Size(); ++i)
            m_scene.blocks.push_back(readBlock(blocks[i], detail::joinIndex("fluid", i)));
    }
    if (const rj::Value* v = o.find("emitters")) {
        const rj::Value& emitters = detail::requireArray(*v, "emitters");
        for (rj::SizeType i = 0; i < emitters.Size(); ++i)
            m_scene.emitters.push_back(readEmitter(emitters[i], detail::joinIndex("emitters", i)));
    }
    if (m_scene.blocks.empty() && m_scene.emitters.empty())
        throwAt(ErrorCode::BadMetadata, "fluid",
                "a scene needs at least one fluid block (\"fluid\") or one emitter "
                "(\"emitters\")");
    if (const rj::Value* v = o.find("colliders")) {
        const rj::Value& colliders = detail::requireArray(*v, "colliders");
        if (colliders.Size() > kMaxSceneColliders)
            throwAt(ErrorCode::InvalidArgument, "colliders",
                    std::to_string(colliders.Size()) + " colliders, more than the limit " +
                        std::to_string(kMaxSceneColliders));
        for (rj::SizeType i = 0; i < colliders.Size(); ++i)
            m_scene.colliders.push_back(readCollider(
                colliders[i], detail::joinIndex("colliders", i), m_file, m_options.checkAssets));
        for (SceneCollider& c : m_scene.colliders)
            if (c.shape && c.shape->voxelSize == 0.0f)
                c.shape->voxelSize = defaultShapeVoxel(m_scene.simulation.spacing);
    }
    if (const rj::Value* v = o.find("drains")) {
        const rj::Value& drains = detail::requireArray(*v, "drains");
        if (drains.Size() > kMaxDrains)
            throwAt(ErrorCode::InvalidArgument, "drains",
                    std::to_string(drains.Size()) + " drains, more than the limit " +
                        std::to_string(kMaxDrains));
        for (rj::SizeType i = 0; i < drains.Size(); ++i) {
            const std::string path = detail::joinIndex("drains", i);
            const JsonObject d(drains[i], path, {"box"});
            Drain drain;
            readMinMax(d.require("box"), d.pathOf("box"), drain.min, drain.max);
            m_scene.drains.push_back(drain);
        }
    }
    if (const rj::Value* v = o.find("camera"))
        readCamera(*v, "camera");

    deriveCapacity();
    if (!m_givenSubsteps)
        m_scene.simulation.substeps = defaultSubsteps(m_scene);
    return std::move(m_scene);
}

} // namespace

Result<Scene> parseScene(std::string_view json, const std::filesystem::path& file,
                         const SceneReadOptions& options) {
    const std::filesystem::path shown =
        options.label.empty() ? file : std::filesystem::path(options.label);
    return detail::parseJsonText<Scene>(json, shown, kSceneKind, [&](const rj::Document& doc) {
        return SceneParser(file, options).parse(doc);
    });
}

Result<Scene> readScene(const std::filesystem::path& file, const SceneReadOptions& options) {
    return detail::readJsonFile<Scene>(file, kSceneKind, [&](const rj::Document& doc) {
        return SceneParser(file, options).parse(doc);
    });
}

} // namespace sluice::format
