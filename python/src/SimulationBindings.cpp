// Bindings of the runtime: a PBF Simulation in its own headless GL context, stepped from Python.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>

#include <Python.h>

#include "Errors.h"
#include "output/StatsReport.h"
#include "play/RunProgress.h"
#include "sluice/format/scene/SceneIO.h"
#include "sluice/format/scene/SimulationLimits.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/sim/Simulation.h"

namespace sluice::py {
namespace {

/// The context comes first so that it is destroyed last (GL objects before their context).
struct PySimulation {
    std::optional<gpu::Context> context;
    std::unique_ptr<rt::Simulation> sim;
    std::string sceneJson; ///< the scene's path (for messages)

    PySimulation() = default;
    PySimulation(const PySimulation&) = delete;
    PySimulation& operator=(const PySimulation&) = delete;
    ~PySimulation() {
        // Its GL objects are deleted in its own context: with another one current (a surface
        // mesher's), their names would delete that context's objects. Where it cannot be made
        // current (a copy inherited across fork(), whose objects are the parent's; a context
        // still current on another thread) they are left to the context's end.
        if (sim && !(context && context->tryMakeCurrent()))
            (void)sim.release();
        sim.reset();
    }

    rt::Simulation& current() {
        if (gpu::forkedFromGlProcess())
            throw SluiceError(Family::Simulation, ErrorCode::NoGlContext,
                              sceneJson +
                                  ": this Simulation's OpenGL context belongs to the process "
                                  "this one was forked from; create the Simulation here instead "
                                  "[NoGlContext]");
        context->makeCurrent();
        return *sim;
    }
};

std::unique_ptr<PySimulation> create(Result<format::Scene> scene, bool deterministic) {
    if (!scene)
        raise(scene.error().code == ErrorCode::Io ? Family::File : Family::Scene, scene.error());
    auto out = std::make_unique<PySimulation>();
    Result<std::vector<format::ColliderAsset>> colliders = rt::loadSceneColliders(*scene);
    if (!colliders)
        raise(Family::Asset, colliders.error());
    Result<gpu::Context> context = gpu::Context::createHeadless();
    if (!context)
        raise(Family::Simulation, context.error());
    out->context.emplace(std::move(*context));
    if (scene->namesRemovedBoundaryModel)
        nb::module_::import_("warnings")
            .attr("warn")(scene->path + ": " + format::removedBoundaryModelWarning());
    if (auto warning = rt::slowLoadWarning(*scene, *colliders))
        nb::module_::import_("warnings").attr("warn")(*warning);
    rt::SimulationOptions options;
    options.deterministic = deterministic;
    Result<rt::Simulation> sim = rt::Simulation::create(*scene, std::move(*colliders), options);
    if (!sim)
        raise(Family::Simulation, sim.error());
    out->sim = std::make_unique<rt::Simulation>(std::move(*sim));
    out->sceneJson = scene->path;
    return out;
}

using Vec3Array = nb::ndarray<nb::numpy, float, nb::shape<-1, 3>>;

Vec3Array vec3Array(const std::vector<rt::ParticleState>& particles, bool velocity) {
    const std::size_t n = particles.size();
    auto* data = new float[n * 3];
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 v = velocity ? particles[i].velocity : particles[i].position;
        data[3 * i] = v.x, data[3 * i + 1] = v.y, data[3 * i + 2] = v.z;
    }
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<float*>(p); });
    return Vec3Array(data, {n, 3}, owner);
}

// Replaces the particles with (N, 3) positions and velocities and (N,) ids.
void setParticles(
    PySimulation& s, nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu> pos,
    nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu> vel,
    nb::ndarray<const std::uint32_t, nb::ndim<1>, nb::c_contig, nb::device::cpu> ids) {
    const std::size_t n = pos.shape(0);
    if (vel.shape(0) != n || ids.shape(0) != n)
        throw SluiceError(Family::Argument, ErrorCode::InvalidArgument,
                          "set_particles: positions, velocities and ids differ in "
                          "length [InvalidArgument]");
    std::vector<rt::ParticleState> p(n);
    for (std::size_t i = 0; i < n; ++i) {
        p[i].position = {pos(i, 0), pos(i, 1), pos(i, 2)};
        p[i].velocity = {vel(i, 0), vel(i, 1), vel(i, 2)};
        p[i].id = ids(i);
    }
    if (Result<void> ok = s.current().setParticles(p); !ok)
        raise(Family::Argument, ok.error());
}

// The particles as (positions (N, 3), velocities (N, 3), ids (N,)).
nb::tuple particles(PySimulation& s) {
    const std::vector<rt::ParticleState> p = s.current().downloadParticles();
    auto* ids = new std::uint32_t[p.size()];
    for (std::size_t i = 0; i < p.size(); ++i)
        ids[i] = p[i].id;
    nb::capsule owner(ids, [](void* q) noexcept { delete[] static_cast<std::uint32_t*>(q); });
    return nb::make_tuple(
        vec3Array(p, false), vec3Array(p, true),
        nb::ndarray<nb::numpy, std::uint32_t, nb::ndim<1>>(ids, {p.size()}, owner));
}

// Adds (N, 3) positions with (N, 3) velocities (or none: at rest); the first new id.
std::uint32_t addParticles(
    PySimulation& s, nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu> pos,
    std::optional<nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>> vel) {
    std::vector<glm::vec3> positions(pos.shape(0)), velocities(vel ? vel->shape(0) : 0);
    for (std::size_t i = 0; i < positions.size(); ++i)
        positions[i] = {pos(i, 0), pos(i, 1), pos(i, 2)};
    for (std::size_t i = 0; i < velocities.size(); ++i)
        velocities[i] = {(*vel)(i, 0), (*vel)(i, 1), (*vel)(i, 2)};
    auto first = s.current().addParticles(positions, velocities);
    if (!first)
        raise(Family::Argument, first.error());
    return *first;
}

// Places collider `index` at `translation` [m] and the quaternion `rotation` (x, y, z, w).
void setColliderPose(PySimulation& s, std::uint32_t index, std::array<float, 3> translation,
                     std::array<float, 4> rotation) {
    const glm::quat q(rotation[3], rotation[0], rotation[1], rotation[2]);
    if (auto ok = s.current().setColliderPose(
            index, glm::vec3(translation[0], translation[1], translation[2]), q);
        !ok)
        raise(Family::Argument, ok.error());
}

// The measured colliders' forces of the newest completed step, without waiting: None until
// there is one, else {"step", "time", "colliders": {index: (force (3,), torque (3,))}}.
nb::object latestForces(PySimulation& s) {
    const std::optional<rt::ForcesReading> reading = s.current().latestForces();
    if (!reading)
        return nb::none();
    nb::dict colliders;
    for (const rt::ColliderForce& f : reading->colliders)
        colliders[nb::int_(f.collider)] =
            nb::make_tuple(nb::make_tuple(f.force.x, f.force.y, f.force.z),
                           nb::make_tuple(f.torque.x, f.torque.y, f.torque.z));
    nb::dict out;
    out["step"] = reading->step;
    out["time"] = reading->time;
    out["colliders"] = colliders;
    return out;
}

// The walls' and static colliders' boundary share at (N, 3) points: (shares (N,), gradients
// (N, 3)), float32 (rt::Simulation::solidBoundaryAt).
nb::tuple
solidBoundaryAt(PySimulation& s,
                nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu> pts) {
    std::vector<glm::vec3> points(pts.shape(0));
    for (std::size_t i = 0; i < points.size(); ++i)
        points[i] = {pts(i, 0), pts(i, 1), pts(i, 2)};
    auto probed = s.current().solidBoundaryAt(points);
    if (!probed)
        raise(Family::Simulation, probed.error());
    const std::size_t n = probed->size();
    auto* share = new float[n];
    auto* slope = new float[n * 3];
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec4 v = (*probed)[i];
        share[i] = v.w;
        slope[3 * i] = v.x, slope[3 * i + 1] = v.y, slope[3 * i + 2] = v.z;
    }
    nb::capsule shareOwner(share, [](void* q) noexcept { delete[] static_cast<float*>(q); });
    nb::capsule slopeOwner(slope, [](void* q) noexcept { delete[] static_cast<float*>(q); });
    return nb::make_tuple(nb::ndarray<nb::numpy, float, nb::ndim<1>>(share, {n}, shareOwner),
                          Vec3Array(slope, {n, 3}, slopeOwner));
}

void step(PySimulation& s, std::uint64_t n) {
    // One step at a time with the GIL released, checking for Ctrl-C between steps.
    for (std::uint64_t i = 0; i < n; ++i) {
        {
            nb::gil_scoped_release release;
            s.current().step();
            if (i + 1 == n)
                s.sim->readStats(); // wait for the GPU here, not in the next Python call
        }
        if (PyErr_CheckSignals() != 0)
            throw nb::python_error();
    }
}

/// Writable SimulationParams fields by their scene-file key (docs/scene-format.md).
bool setParam(format::SimulationParams& p, const std::string& key, nb::handle value) {
    auto f = [&](float& field) { field = nb::cast<float>(value); };
    auto u = [&](std::uint32_t& field) {
        const long long v = nb::cast<long long>(value);
        if (v < 0 || v > 0xffffffffll)
            throw SluiceError(Family::Argument, ErrorCode::InvalidArgument,
                              "simulation." + key + ": " + std::to_string(v) +
                                  " is out of range [InvalidArgument]");
        field = std::uint32_t(v);
    };
    if (key == "kernelRadius")
        f(p.kernelRadius);
    else if (key == "timeStep")
        f(p.timeStep);
    else if (key == "substeps")
        u(p.substeps);
    else if (key == "minIterations")
        u(p.minIterations);
    else if (key == "maxIterations")
        u(p.maxIterations);
    else if (key == "targetDensityError")
        f(p.targetDensityError);
    else if (key == "relaxation")
        f(p.relaxation);
    else if (key == "scorrK")
        f(p.scorrK);
    else if (key == "scorrN")
        f(p.scorrN);
    else if (key == "scorrDeltaQ")
        f(p.scorrDeltaQ);
    else if (key == "xsph")
        f(p.xsph);
    else if (key == "vorticity")
        f(p.vorticity);
    else if (key == "gravity") {
        nb::sequence g = nb::cast<nb::sequence>(value);
        if (nb::len(g) != 3)
            throw SluiceError(Family::Argument, ErrorCode::InvalidArgument,
                              "simulation.gravity: expected 3 numbers [InvalidArgument]");
        p.gravity = glm::vec3(nb::cast<float>(g[0]), nb::cast<float>(g[1]), nb::cast<float>(g[2]));
    } else
        return false;
    return true;
}

// The calls a game loop makes (docs/embedding.md): particles added, colliders placed, bodies
// held, forces measured and read.
void bindGameCalls(nb::class_<PySimulation>& cls) {
    cls.def("add_particles", &addParticles, nb::arg("positions"),
            nb::arg("velocities").none() = nb::none())
        .def("set_collider_pose", &setColliderPose, nb::arg("index"), nb::arg("translation"),
             nb::arg("rotation"))
        .def(
            "set_body_kinematic",
            [](PySimulation& s, std::uint32_t index, bool kinematic) {
                if (auto ok = s.current().setBodyKinematic(index, kinematic); !ok)
                    raise(Family::Argument, ok.error());
            },
            nb::arg("index"), nb::arg("kinematic") = true)
        .def(
            "measure_force",
            [](PySimulation& s, std::uint32_t index, bool on) {
                if (auto ok = s.current().measureForce(index, on); !ok)
                    raise(Family::Argument, ok.error());
            },
            nb::arg("index"), nb::arg("on") = true)
        .def("latest_forces", &latestForces);
}

} // namespace

void bindSimulation(nb::module_& m) {
    nb::class_<PySimulation> cls(m, "SimulationCore",
                                 "A PBF simulation on the GPU in its own headless GL context.");
    cls.def_static(
           "from_file",
           [](const std::string& path, bool deterministic) {
               return create(format::readScene(path), deterministic);
           },
           nb::arg("path"), nb::arg("deterministic") = false)
        .def_static(
            "from_json",
            [](const std::string& text, const std::string& path, bool deterministic,
               const std::string& label) {
                format::SceneReadOptions options;
                options.label = label;
                return create(format::parseScene(text, path, options), deterministic);
            },
            nb::arg("text"), nb::arg("path"), nb::arg("deterministic") = false,
            nb::arg("label") = "",
            "A scene from JSON text: collider assets relative to the folder of `path`, messages "
            "naming it `label` (empty: `path`).")
        .def("step", &step, nb::arg("n") = 1)
        .def("stats_json",
             [](PySimulation& s) {
                 // As each row of sluice-play --stats-json: with bodies, their state too.
                 nlohmann::json row = rt::statsJson(s.current().readStats());
                 const std::vector<rt::BodyState> bodies = s.current().bodies();
                 if (!bodies.empty())
                     row["bodies"] = rt::bodiesJson(bodies);
                 return row.dump();
             })
        .def("bodies_json",
             [](PySimulation& s) { return rt::bodiesJson(s.current().bodies()).dump(); })
        .def("parameters_json",
             [](PySimulation& s) {
                 rt::Simulation& sim = s.current();
                 return rt::parametersJson(sim.parameters(), sim.constants()).dump();
             })
        .def("set_parameters",
             [](PySimulation& s, nb::dict kw) {
                 format::SimulationParams p = s.current().parameters();
                 for (auto [k, v] : kw) {
                     const std::string key = nb::cast<std::string>(k);
                     if (!setParam(p, key, v))
                         throw SluiceError(Family::Argument, ErrorCode::InvalidArgument,
                                           "simulation." + key +
                                               ": not a parameter that can change while running "
                                               "[InvalidArgument]");
                 }
                 if (Result<void> ok = s.current().setParameters(p); !ok)
                     raise(Family::Argument, ok.error());
             })
        .def("positions",
             [](PySimulation& s) { return vec3Array(s.current().downloadParticles(), false); })
        .def("velocities",
             [](PySimulation& s) { return vec3Array(s.current().downloadParticles(), true); })
        .def("particles", &particles)
        .def("solid_boundary_at", &solidBoundaryAt, nb::arg("points"))
        .def("set_particles", &setParticles, nb::arg("positions"), nb::arg("velocities"),
             nb::arg("ids"))
        .def_prop_ro("particle_count", [](PySimulation& s) { return s.sim->liveParticleCount(); })
        .def_prop_ro("capacity", [](PySimulation& s) { return s.sim->capacity(); })
        .def_prop_ro("time", [](PySimulation& s) { return s.sim->time(); })
        .def_prop_ro("steps", [](PySimulation& s) { return s.sim->steps(); })
        .def_prop_ro("scene_path", [](PySimulation& s) { return s.sceneJson; })
        .def_prop_ro("renderer", [](PySimulation& s) { return s.context->info().renderer; });
    bindGameCalls(cls);
}

} // namespace sluice::py
