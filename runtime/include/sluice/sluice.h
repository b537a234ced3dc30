/* The C API of Sluice's runtime: a simulation an engine drives every frame, for engines that bind
 * C (Unity native plug-ins, Godot GDExtension, Unreal). Opaque handles, status codes, no
 * exceptions across it; the same calls as sluice::rt::Simulation (docs/embedding.md).
 *
 * Every call that can fail returns a SluiceStatus; on failure it changes nothing, and
 * sluice_last_error() says what was wrong on the calling thread until its next failing call.
 * Calls on a simulation need its GL context current on the calling thread. */
#ifndef SLUICE_SLUICE_H
#define SLUICE_SLUICE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** What a call did: SLUICE_OK, or why it changed nothing. */
typedef enum SluiceStatus {
    SLUICE_OK = 0,
    SLUICE_ERROR_INVALID_ARGUMENT =
        1,                          /**< a value out of range, an unknown index, a null pointer */
    SLUICE_ERROR_NON_FINITE = 2,    /**< NaN or infinity where a finite number is needed */
    SLUICE_ERROR_BAD_INPUT = 3,     /**< a scene or collider file that cannot be used */
    SLUICE_ERROR_NO_GL_CONTEXT = 4, /**< no current OpenGL 4.5 context with compute shaders */
    SLUICE_ERROR_GPU = 5,           /**< the GPU ran out of memory or refused a shader */
    SLUICE_ERROR_INTERNAL = 6       /**< a bug in Sluice */
} SluiceStatus;

/** A headless OpenGL 4.5 context (EGL), for programs without a window of their own. */
typedef struct SluiceContext SluiceContext;
/** One simulation: particles, colliders and the solver's GPU buffers. */
typedef struct SluiceSimulation SluiceSimulation;

/** A GL function's address by name, as the program's window library gives it
 * (glfwGetProcAddress, SDL_GL_GetProcAddress, eglGetProcAddress). */
typedef void (*(*SluiceGetProcAddress)(const char* name))(void);

/** The particle buffers after a step, valid until the next step or sluice_add_particles. */
typedef struct SluiceParticleView {
    uint32_t positions;      /**< GL buffer: vec4 per slot, xyz [m] */
    uint32_t velocities;     /**< GL buffer: vec4 per slot, xyz [m/s], w the density error */
    uint32_t ids;            /**< GL buffer: uint per slot, the particle's id */
    uint32_t count;          /**< slots in use */
    uint32_t positionStride; /**< [bytes] */
    uint32_t velocityStride; /**< [bytes] */
    uint32_t idStride;       /**< [bytes] */
    uint32_t drawArgs;       /**< GL buffer: DrawArraysIndirectCommand {live particles, 1, 0, 0}
                                  for glDrawArraysIndirect (the live particles lead the slots) */
} SluiceParticleView;

/** What sluice_advance did with one frame's time. */
typedef struct SluiceFrameAdvance {
    uint32_t steps;   /**< whole steps taken */
    double remainder; /**< time carried to the next frame [s] */
    double alpha;     /**< remainder / time step, in [0, 1) */
    double dropped;   /**< time dropped past maxSteps [s] */
} SluiceFrameAdvance;

/** One dynamic body after a completed step: the fluid's force and torque on it and its pose. */
typedef struct SluiceBody {
    uint32_t collider;       /**< its index among the scene's colliders */
    float force[3];          /**< the fluid's force, mean over the step [N] */
    float torque[3];         /**< the fluid's torque about the centre of mass [N m] */
    float centreOfMass[3];   /**< [m] */
    float orientation[4];    /**< quaternion x y z w, asset frame to world */
    float linearVelocity[3]; /**< [m/s] */
} SluiceBody;

/** The fluid's force on a static or kinematic collider whose force is measured. */
typedef struct SluiceColliderForce {
    uint32_t collider; /**< its index among the scene's colliders */
    float force[3];    /**< mean over the step [N] */
    float torque[3];   /**< about the collider's origin (its pose's translation) [N m] */
} SluiceColliderForce;

/** This thread's last failure: what and where, as a person reads it ("" if none). */
const char* sluice_last_error(void);

/** Opens a headless context and makes it current on this thread. */
SluiceStatus sluice_context_create_headless(SluiceContext** out);
/** Releases a context (null is ignored). Destroy its simulations first. */
void sluice_context_destroy(SluiceContext* context);

/** Loads Sluice's own GL function pointers from the program's current context. Call once after
 * the program's window context is current, before creating a simulation in it. */
SluiceStatus sluice_load_gl(SluiceGetProcAddress getProcAddress);

/** Reads a scene file (docs/scene-format.md) and its colliders and creates the simulation. */
SluiceStatus sluice_simulation_create_from_file(const char* scenePath, SluiceSimulation** out);
/** The same from JSON text; collider paths are relative to `sceneFile`'s folder, which also
 * names the scene in messages (the file need not exist). */
SluiceStatus sluice_simulation_create_from_json(const char* json, const char* sceneFile,
                                                SluiceSimulation** out);
/** Releases a simulation (null is ignored). Its context must be current. */
void sluice_simulation_destroy(SluiceSimulation* simulation);

/** One step of the scene's time step. Queues GPU work only. */
SluiceStatus sluice_step(SluiceSimulation* simulation);
/** Whole steps for a frame of `seconds`, at most `maxSteps`, the rest carried (`out` may be
 * null). */
SluiceStatus sluice_advance(SluiceSimulation* simulation, double seconds, uint32_t maxSteps,
                            SluiceFrameAdvance* out);
/** Places a static or kinematic collider, or a body the game holds (sluice_set_body_kinematic),
 * from the next step on, moving there across the step:
 * `translation` x y z [m], `rotation` the quaternion x y z w (asset frame to world). */
SluiceStatus sluice_set_collider_pose(SluiceSimulation* simulation, uint32_t collider,
                                      const float translation[3], const float rotation[4]);
/** Moves a dynamic body at once (a respawn): its asset frame to `translation` x y z [m] and
 * `rotation` x y z w, its centre of mass moving at `linearVelocity` [m/s] and turning at
 * `angularVelocity` [rad/s] (either may be null: at rest), from the next step. */
SluiceStatus sluice_teleport_body(SluiceSimulation* simulation, uint32_t collider,
                                  const float translation[3], const float rotation[4],
                                  const float linearVelocity[3], const float angularVelocity[3]);
/** Hands dynamic body `collider` to the game (`kinematic` non-zero: from the next step it goes
 * only where sluice_set_collider_pose puts it, the water still feeling it and reporting its
 * force) or back to the water (0: it keeps its last step's velocity). Taking it waits for the GPU
 * once. */
SluiceStatus sluice_set_body_kinematic(SluiceSimulation* simulation, uint32_t collider,
                                       int kinematic);
/** Adds `count` particles: `positions` x y z each [m], `velocities` x y z [m/s] or null for at
 * rest. Their ids are *firstId, *firstId + 1, ... (`firstId` may be null). */
SluiceStatus sluice_add_particles(SluiceSimulation* simulation, const float* positions,
                                  const float* velocities, uint32_t count, uint32_t* firstId);
/** Removes the particles with these `count` ids at the next step (an id already removed is
 * ignored; one never given out is an error). */
SluiceStatus sluice_remove_particles(SluiceSimulation* simulation, const uint32_t* ids,
                                     uint32_t count);
/** Removes the particles inside the box [min, max) (x y z each [m]) at the next step. */
SluiceStatus sluice_remove_particles_in(SluiceSimulation* simulation, const float min[3],
                                        const float max[3]);
/** Replaces the drains: `count` boxes (at most 8), min x y z then max x y z each [m], that
 * remove every particle entering them from the next step on. */
SluiceStatus sluice_set_drains(SluiceSimulation* simulation, const float* boxes, uint32_t count);
/** The buffers to draw now. A slot whose position has w = 1 holds a removed particle not yet
 * compacted away: skip it. */
SluiceStatus sluice_particle_view(const SluiceSimulation* simulation, SluiceParticleView* out);
/** Copies the particles with ids firstId .. firstId + count - 1 into GL buffers the program
 * owns, in id order, on the GPU without waiting: entry k of `positions` (vec4: xyz [m]) and of
 * `velocities` (vec4: xyz [m/s]; 0 for none) is id firstId + k with w = 1 where that particle is
 * live, all zero where it is not. Each buffer needs count * 16 bytes. */
SluiceStatus sluice_copy_particles_by_id(SluiceSimulation* simulation, uint32_t positions,
                                         uint32_t velocities, uint32_t firstId, uint32_t count);
/** Copies up to `capacity` particles to the CPU (positions x y z, ids; either may be null) and
 * sets *count to how many there are. Waits for the GPU: for tools and tests, not every frame. */
SluiceStatus sluice_read_particles(const SluiceSimulation* simulation, float* positions,
                                   uint32_t* ids, uint32_t capacity, uint32_t* count);
/** The dynamic bodies as the newest completed step left them, without waiting for the GPU:
 * up to `capacity` of them into `out`, *count how many there are (0 until a step completed, and
 * in a scene without bodies), *step which step they are from (`step` may be null). */
SluiceStatus sluice_latest_bodies(const SluiceSimulation* simulation, SluiceBody* out,
                                  uint32_t capacity, uint32_t* count, uint64_t* step);
/** Starts (on != 0) or stops measuring the fluid's force on a static or kinematic collider
 * (the scene's "measureForce"), from the next step. A dynamic body is an error: its force is in
 * sluice_latest_bodies. */
SluiceStatus sluice_measure_force(SluiceSimulation* simulation, uint32_t collider, int on);
/** The measured colliders' forces as the newest completed step left them, without waiting: up
 * to `capacity` into `out`, *count how many there are (0 until a step completed, and while none
 * is measured), *step which step they are from (`step` may be null). */
SluiceStatus sluice_latest_forces(const SluiceSimulation* simulation, SluiceColliderForce* out,
                                  uint32_t capacity, uint32_t* count, uint64_t* step);
/** Slots in use: the live particles and, for a step or two after a removal, removed ones not
 * yet compacted away (0 for null). */
uint32_t sluice_particle_count(const SluiceSimulation* simulation);
/** Simulated time [s] (0 for null). */
double sluice_time(const SluiceSimulation* simulation);

#ifdef __cplusplus
}
#endif

#endif /* SLUICE_SLUICE_H */
