// The C API (sluice/sluice.h) over sluice::rt::Simulation: handles, status codes, the thread's
// last error; no exception crosses it.
#include "sluice/sluice.h"

#include <algorithm>
#include <exception>
#include <string>
#include <vector>

#include "sluice/format/scene/SceneIO.h"
#include "sluice/gpu/Context.h"
#include "sluice/gpu/Gl.h"
#include "sluice/rt/sim/Simulation.h"

struct SluiceContext {
    sluice::gpu::Context context;
};

struct SluiceSimulation {
    sluice::rt::Simulation simulation;
};

namespace {

using sluice::Error;
using sluice::ErrorCode;

thread_local std::string t_lastError;

SluiceStatus statusFor(ErrorCode code) {
    switch (code) {
    case ErrorCode::InvalidArgument:
        return SLUICE_ERROR_INVALID_ARGUMENT;
    case ErrorCode::NonFinite:
        return SLUICE_ERROR_NON_FINITE;
    case ErrorCode::NoGlContext:
        return SLUICE_ERROR_NO_GL_CONTEXT;
    case ErrorCode::ShaderCompile:
    case ErrorCode::ShaderLink:
    case ErrorCode::GpuOutOfMemory:
        return SLUICE_ERROR_GPU;
    default:
        return SLUICE_ERROR_BAD_INPUT;
    }
}

SluiceStatus failWith(const Error& error) {
    t_lastError = error.message();
    return statusFor(error.code);
}

SluiceStatus failWith(SluiceStatus status, std::string message) {
    t_lastError = std::move(message);
    return status;
}

// Runs `body`, turning an escaping exception into SLUICE_ERROR_INTERNAL.
template <class Body> SluiceStatus guarded(const char* call, Body&& body) {
    try {
        return body();
    } catch (const std::exception& e) {
        return failWith(SLUICE_ERROR_INTERNAL, std::string(call) + ": " + e.what());
    } catch (...) {
        return failWith(SLUICE_ERROR_INTERNAL, std::string(call) + ": unknown exception");
    }
}

// Whether Sluice's GL functions are loaded and a context is current on this thread.
SluiceStatus requireContext(const char* call) {
    if (!sluice_GLAD_GL_VERSION_4_5 || sluice_glad_glGetString == nullptr)
        return failWith(SLUICE_ERROR_NO_GL_CONTEXT,
                        std::string(call) +
                            ": no OpenGL 4.5 functions loaded; call sluice_load_gl with the "
                            "window's context current, or sluice_context_create_headless");
    if (glGetString(GL_VERSION) == nullptr)
        return failWith(SLUICE_ERROR_NO_GL_CONTEXT,
                        std::string(call) + ": no OpenGL context is current on this thread");
    return SLUICE_OK;
}

SluiceStatus create(const char* call, sluice::Result<sluice::format::Scene> scene,
                    SluiceSimulation** out) {
    if (!scene)
        return failWith(scene.error());
    if (SluiceStatus s = requireContext(call); s != SLUICE_OK)
        return s;
    auto colliders = sluice::rt::loadSceneColliders(*scene);
    if (!colliders)
        return failWith(colliders.error());
    auto sim = sluice::rt::Simulation::create(*scene, std::move(*colliders));
    if (!sim)
        return failWith(sim.error());
    *out = new SluiceSimulation{std::move(*sim)};
    return SLUICE_OK;
}

SluiceStatus nullArgument(const char* call, const char* name) {
    return failWith(SLUICE_ERROR_INVALID_ARGUMENT, std::string(call) + ": " + name + " is null");
}

} // namespace

extern "C" {

const char* sluice_last_error(void) {
    return t_lastError.c_str();
}

SluiceStatus sluice_context_create_headless(SluiceContext** out) {
    return guarded("sluice_context_create_headless", [&] {
        if (!out)
            return nullArgument("sluice_context_create_headless", "out");
        auto context = sluice::gpu::Context::createHeadless();
        if (!context)
            return failWith(context.error());
        *out = new SluiceContext{std::move(*context)};
        return SLUICE_OK;
    });
}

void sluice_context_destroy(SluiceContext* context) {
    delete context;
}

SluiceStatus sluice_load_gl(SluiceGetProcAddress getProcAddress) {
    return guarded("sluice_load_gl", [&] {
        if (!getProcAddress)
            return nullArgument("sluice_load_gl", "getProcAddress");
        const int version = sluice_gladLoadGL(reinterpret_cast<GLADloadfunc>(getProcAddress));
        if (version == 0 || !sluice_GLAD_GL_VERSION_4_5)
            return failWith(SLUICE_ERROR_NO_GL_CONTEXT,
                            "sluice_load_gl: the current context is not OpenGL 4.5 core (got " +
                                std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
                                std::to_string(GLAD_VERSION_MINOR(version)) + ")");
        return SLUICE_OK;
    });
}

SluiceStatus sluice_simulation_create_from_file(const char* scenePath, SluiceSimulation** out) {
    return guarded("sluice_simulation_create_from_file", [&] {
        if (!scenePath || !out)
            return nullArgument("sluice_simulation_create_from_file", !out ? "out" : "scenePath");
        return create("sluice_simulation_create_from_file", sluice::format::readScene(scenePath),
                      out);
    });
}

SluiceStatus sluice_simulation_create_from_json(const char* json, const char* sceneFile,
                                                SluiceSimulation** out) {
    return guarded("sluice_simulation_create_from_json", [&] {
        if (!json || !sceneFile || !out)
            return nullArgument("sluice_simulation_create_from_json",
                                !out ? "out" : (!json ? "json" : "sceneFile"));
        return create("sluice_simulation_create_from_json",
                      sluice::format::parseScene(json, sceneFile), out);
    });
}

void sluice_simulation_destroy(SluiceSimulation* simulation) {
    delete simulation;
}

SluiceStatus sluice_step(SluiceSimulation* simulation) {
    return guarded("sluice_step", [&] {
        if (!simulation)
            return nullArgument("sluice_step", "simulation");
        simulation->simulation.step();
        return SLUICE_OK;
    });
}

SluiceStatus sluice_advance(SluiceSimulation* simulation, double seconds, uint32_t maxSteps,
                            SluiceFrameAdvance* out) {
    return guarded("sluice_advance", [&] {
        if (!simulation)
            return nullArgument("sluice_advance", "simulation");
        auto done = simulation->simulation.advance(seconds, maxSteps);
        if (!done)
            return failWith(done.error());
        if (out)
            *out = SluiceFrameAdvance{done->steps, done->remainder, done->alpha, done->dropped};
        return SLUICE_OK;
    });
}

SluiceStatus sluice_set_collider_pose(SluiceSimulation* simulation, uint32_t collider,
                                      const float translation[3], const float rotation[4]) {
    return guarded("sluice_set_collider_pose", [&] {
        if (!simulation || !translation || !rotation)
            return nullArgument("sluice_set_collider_pose",
                                !simulation ? "simulation"
                                            : (!translation ? "translation" : "rotation"));
        // glm::quat takes w first.
        auto done = simulation->simulation.setColliderPose(
            collider, glm::vec3(translation[0], translation[1], translation[2]),
            glm::quat(rotation[3], rotation[0], rotation[1], rotation[2]));
        return done ? SLUICE_OK : failWith(done.error());
    });
}

SluiceStatus sluice_teleport_body(SluiceSimulation* simulation, uint32_t collider,
                                  const float translation[3], const float rotation[4],
                                  const float linearVelocity[3], const float angularVelocity[3]) {
    return guarded("sluice_teleport_body", [&] {
        if (!simulation || !translation || !rotation)
            return nullArgument("sluice_teleport_body",
                                !simulation ? "simulation"
                                            : (!translation ? "translation" : "rotation"));
        const auto vec = [](const float* v) {
            return v ? glm::vec3(v[0], v[1], v[2]) : glm::vec3(0.0f);
        };
        auto done = simulation->simulation.teleportBody(
            collider, vec(translation),
            glm::quat(rotation[3], rotation[0], rotation[1], rotation[2]), vec(linearVelocity),
            vec(angularVelocity));
        return done ? SLUICE_OK : failWith(done.error());
    });
}

SluiceStatus sluice_set_body_kinematic(SluiceSimulation* simulation, uint32_t collider,
                                       int kinematic) {
    return guarded("sluice_set_body_kinematic", [&] {
        if (!simulation)
            return nullArgument("sluice_set_body_kinematic", "simulation");
        auto done = simulation->simulation.setBodyKinematic(collider, kinematic != 0);
        return done ? SLUICE_OK : failWith(done.error());
    });
}

SluiceStatus sluice_add_particles(SluiceSimulation* simulation, const float* positions,
                                  const float* velocities, uint32_t count, uint32_t* firstId) {
    return guarded("sluice_add_particles", [&] {
        if (!simulation || (!positions && count > 0))
            return nullArgument("sluice_add_particles", !simulation ? "simulation" : "positions");
        std::vector<glm::vec3> p(count), v(velocities ? count : 0);
        for (std::uint32_t i = 0; i < count; ++i) {
            p[i] = glm::vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
            if (velocities)
                v[i] = glm::vec3(velocities[3 * i], velocities[3 * i + 1], velocities[3 * i + 2]);
        }
        auto first = simulation->simulation.addParticles(p, v);
        if (!first)
            return failWith(first.error());
        if (firstId)
            *firstId = *first;
        return SLUICE_OK;
    });
}

SluiceStatus sluice_remove_particles(SluiceSimulation* simulation, const uint32_t* ids,
                                     uint32_t count) {
    return guarded("sluice_remove_particles", [&] {
        if (!simulation || (!ids && count > 0))
            return nullArgument("sluice_remove_particles", !simulation ? "simulation" : "ids");
        auto done =
            simulation->simulation.removeParticles(std::vector<std::uint32_t>(ids, ids + count));
        return done ? SLUICE_OK : failWith(done.error());
    });
}

SluiceStatus sluice_remove_particles_in(SluiceSimulation* simulation, const float min[3],
                                        const float max[3]) {
    return guarded("sluice_remove_particles_in", [&] {
        if (!simulation || !min || !max)
            return nullArgument("sluice_remove_particles_in",
                                !simulation ? "simulation" : (!min ? "min" : "max"));
        auto done = simulation->simulation.removeParticlesIn(glm::vec3(min[0], min[1], min[2]),
                                                             glm::vec3(max[0], max[1], max[2]));
        return done ? SLUICE_OK : failWith(done.error());
    });
}

SluiceStatus sluice_set_drains(SluiceSimulation* simulation, const float* boxes, uint32_t count) {
    return guarded("sluice_set_drains", [&] {
        if (!simulation || (!boxes && count > 0))
            return nullArgument("sluice_set_drains", !simulation ? "simulation" : "boxes");
        std::vector<sluice::format::Drain> drains(count);
        for (std::uint32_t d = 0; d < count; ++d) {
            const float* b = boxes + 6 * std::size_t(d);
            drains[d] = {glm::vec3(b[0], b[1], b[2]), glm::vec3(b[3], b[4], b[5])};
        }
        auto done = simulation->simulation.setDrains(drains);
        return done ? SLUICE_OK : failWith(done.error());
    });
}

SluiceStatus sluice_particle_view(const SluiceSimulation* simulation, SluiceParticleView* out) {
    return guarded("sluice_particle_view", [&] {
        if (!simulation || !out)
            return nullArgument("sluice_particle_view", !out ? "out" : "simulation");
        const sluice::rt::ParticleView v = simulation->simulation.particleView();
        *out = SluiceParticleView{v.positions,      v.velocities,     v.ids,      v.count,
                                  v.positionStride, v.velocityStride, v.idStride, v.drawArgs};
        return SLUICE_OK;
    });
}

SluiceStatus sluice_copy_particles_by_id(SluiceSimulation* simulation, uint32_t positions,
                                         uint32_t velocities, uint32_t firstId, uint32_t count) {
    return guarded("sluice_copy_particles_by_id", [&] {
        if (!simulation)
            return nullArgument("sluice_copy_particles_by_id", "simulation");
        auto done = simulation->simulation.copyParticlesById(
            sluice::rt::ParticleCopyTarget{positions, velocities, firstId, count});
        return done ? SLUICE_OK : failWith(done.error());
    });
}

SluiceStatus sluice_read_particles(const SluiceSimulation* simulation, float* positions,
                                   uint32_t* ids, uint32_t capacity, uint32_t* count) {
    return guarded("sluice_read_particles", [&] {
        if (!simulation || !count)
            return nullArgument("sluice_read_particles", !count ? "count" : "simulation");
        const std::vector<sluice::rt::ParticleState> particles =
            simulation->simulation.downloadParticles();
        const std::size_t n = std::min<std::size_t>(capacity, particles.size());
        for (std::size_t i = 0; i < n; ++i) {
            if (positions)
                for (int a = 0; a < 3; ++a)
                    positions[3 * i + a] = particles[i].position[a];
            if (ids)
                ids[i] = particles[i].id;
        }
        *count = std::uint32_t(particles.size());
        return SLUICE_OK;
    });
}

SluiceStatus sluice_latest_bodies(const SluiceSimulation* simulation, SluiceBody* out,
                                  uint32_t capacity, uint32_t* count, uint64_t* step) {
    return guarded("sluice_latest_bodies", [&] {
        if (!simulation || !count || (!out && capacity > 0))
            return nullArgument("sluice_latest_bodies",
                                !simulation ? "simulation" : (!count ? "count" : "out"));
        *count = 0;
        const auto reading = simulation->simulation.latestBodies();
        if (!reading)
            return SLUICE_OK;
        *count = std::uint32_t(reading->bodies.size());
        if (step)
            *step = reading->step;
        for (std::size_t b = 0; b < std::min<std::size_t>(capacity, reading->bodies.size()); ++b) {
            const sluice::rt::BodyState& body = reading->bodies[b];
            SluiceBody& o = out[b];
            o.collider = body.collider;
            for (int a = 0; a < 3; ++a) {
                o.force[a] = body.force[a];
                o.torque[a] = body.torque[a];
                o.centreOfMass[a] = body.position[a];
                o.linearVelocity[a] = body.linearVelocity[a];
            }
            const glm::quat q = body.orientation;
            o.orientation[0] = q.x;
            o.orientation[1] = q.y;
            o.orientation[2] = q.z;
            o.orientation[3] = q.w;
        }
        return SLUICE_OK;
    });
}

SluiceStatus sluice_measure_force(SluiceSimulation* simulation, uint32_t collider, int on) {
    return guarded("sluice_measure_force", [&] {
        if (!simulation)
            return nullArgument("sluice_measure_force", "simulation");
        auto done = simulation->simulation.measureForce(collider, on != 0);
        return done ? SLUICE_OK : failWith(done.error());
    });
}

SluiceStatus sluice_latest_forces(const SluiceSimulation* simulation, SluiceColliderForce* out,
                                  uint32_t capacity, uint32_t* count, uint64_t* step) {
    return guarded("sluice_latest_forces", [&] {
        if (!simulation || !count || (!out && capacity > 0))
            return nullArgument("sluice_latest_forces",
                                !simulation ? "simulation" : (!count ? "count" : "out"));
        *count = 0;
        const auto reading = simulation->simulation.latestForces();
        if (!reading)
            return SLUICE_OK;
        *count = std::uint32_t(reading->colliders.size());
        if (step)
            *step = reading->step;
        for (std::size_t c = 0; c < std::min<std::size_t>(capacity, reading->colliders.size());
             ++c) {
            const sluice::rt::ColliderForce& f = reading->colliders[c];
            out[c].collider = f.collider;
            for (int a = 0; a < 3; ++a) {
                out[c].force[a] = f.force[a];
                out[c].torque[a] = f.torque[a];
            }
        }
        return SLUICE_OK;
    });
}

uint32_t sluice_particle_count(const SluiceSimulation* simulation) {
    return simulation ? simulation->simulation.particleCount() : 0;
}

double sluice_time(const SluiceSimulation* simulation) {
    return simulation ? simulation->simulation.time() : 0.0;
}

} // extern "C"
