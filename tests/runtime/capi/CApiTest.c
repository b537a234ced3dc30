/* The C API from C (sluice/sluice.h): no context, a headless one, a scene from JSON with a
 * baked ball as a kinematic collider, steps, poses, added particles, the view and bad input. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sluice/sluice.h"

static int g_passed = 0;
static int g_failed = 0;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (cond) {                                                                                \
            ++g_passed;                                                                            \
        } else {                                                                                   \
            ++g_failed;                                                                            \
            fprintf(stderr, "%s:%d: CHECK(%s) failed; last error: %s\n", __FILE__, __LINE__,       \
                    #cond, sluice_last_error());                                                   \
        }                                                                                          \
    } while (0)

/* A 6 x 4 x 6 block beside sphere.slc scaled to a 10 cm ball, in a 40 x 40 x 24 cm box. */
static const char* kScene =
    "{\"simulation\": {\"spacing\": 0.02, \"capacity\": 400},"
    " \"fluid\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [0.12, 0.08, 0.12]}}],"
    " \"colliders\": [{\"asset\": \"sphere.slc\", \"translation\": [0.3, 0.1, 0.06],"
    "                  \"scale\": 0.4}],"
    " \"domain\": {\"min\": [0, 0, 0], \"max\": [0.4, 0.4, 0.24]}}";

static void refusesWithoutContext(const char* sceneFile) {
    SluiceSimulation* sim = NULL;
    CHECK(sluice_simulation_create_from_json(kScene, sceneFile, &sim) ==
          SLUICE_ERROR_NO_GL_CONTEXT);
    CHECK(sim == NULL);
    CHECK(strstr(sluice_last_error(), "sluice_load_gl") != NULL);
}

static void refusesBadScenes(const char* sceneFile) {
    SluiceSimulation* sim = NULL;
    CHECK(sluice_simulation_create_from_json("{\"fluid\": 3}", sceneFile, &sim) ==
          SLUICE_ERROR_BAD_INPUT);
    CHECK(strstr(sluice_last_error(), "fluid") != NULL);
    CHECK(sluice_simulation_create_from_json("{\"simulation\": {\"spacing\": -1}, \"fluid\": []}",
                                             sceneFile, &sim) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_simulation_create_from_file("/nonexistent/scene.json", &sim) ==
          SLUICE_ERROR_BAD_INPUT);
    CHECK(strstr(sluice_last_error(), "/nonexistent/scene.json") != NULL);
    CHECK(sluice_simulation_create_from_json(NULL, sceneFile, &sim) ==
          SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sim == NULL);
}

static void movesAddsAndViews(SluiceSimulation* sim) {
    const uint32_t start = sluice_particle_count(sim);
    CHECK(start == 144);
    SluiceFrameAdvance frame;
    CHECK(sluice_advance(sim, 1.0 / 60.0, 4, &frame) == SLUICE_OK);
    CHECK(frame.steps == 1);

    /* Bad poses change nothing: an unknown collider, a NaN, a zero quaternion. */
    const float unit[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    const float there[3] = {0.25f, 0.1f, 0.06f};
    const float nanAt[3] = {0.25f, NAN, 0.06f};
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    CHECK(sluice_set_collider_pose(sim, 1, there, unit) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_set_collider_pose(sim, 0, nanAt, unit) == SLUICE_ERROR_NON_FINITE);
    CHECK(sluice_set_collider_pose(sim, 0, there, zero) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_set_collider_pose(sim, 0, there, NULL) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_set_collider_pose(sim, 0, there, unit) == SLUICE_OK);
    CHECK(sluice_step(sim) == SLUICE_OK);

    /* Eight particles in the air: new ids after the block's. */
    float positions[8 * 3];
    float velocities[8 * 3];
    for (int i = 0; i < 8; ++i) {
        positions[3 * i + 0] = 0.03f + 0.02f * (float)(i % 4);
        positions[3 * i + 1] = 0.3f;
        positions[3 * i + 2] = 0.05f + 0.02f * (float)(i / 4);
        velocities[3 * i + 0] = 0.0f;
        velocities[3 * i + 1] = -0.5f;
        velocities[3 * i + 2] = 0.0f;
    }
    uint32_t first = 0;
    CHECK(sluice_add_particles(sim, positions, velocities, 8, &first) == SLUICE_OK);
    CHECK(first == start);
    CHECK(sluice_particle_count(sim) == start + 8);
    CHECK(sluice_add_particles(sim, positions, NULL, 300, &first) ==
          SLUICE_ERROR_INVALID_ARGUMENT); /* past the capacity of 400 */
    positions[4] = INFINITY;
    CHECK(sluice_add_particles(sim, positions, NULL, 8, &first) == SLUICE_ERROR_NON_FINITE);
    CHECK(sluice_particle_count(sim) == start + 8);
    CHECK(sluice_step(sim) == SLUICE_OK);

    static uint32_t ids[400];
    static float read[400 * 3];
    uint32_t count = 0;
    CHECK(sluice_read_particles(sim, read, ids, 400, &count) == SLUICE_OK);
    CHECK(count == start + 8);
    int added = 0;
    for (uint32_t i = 0; i < count; ++i) {
        CHECK(isfinite(read[3 * i + 1]));
        if (ids[i] >= start && ids[i] < start + 8) {
            ++added;
            CHECK(read[3 * i + 1] < 0.3f); /* falling */
        }
    }
    CHECK(added == 8);

    SluiceParticleView view;
    CHECK(sluice_particle_view(sim, &view) == SLUICE_OK);
    CHECK(view.count == start + 8);

    /* Drain what was added: two by id, the rest by a box over the air above the block. */
    const uint32_t two[2] = {first, first + 1};
    const uint32_t never[1] = {100000};
    CHECK(sluice_remove_particles(sim, never, 1) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_remove_particles(sim, two, 2) == SLUICE_OK);
    const float lo[3] = {-1.0f, 0.12f, -1.0f};
    const float hi[3] = {1.0f, 1.0f, 1.0f};
    const float flipped[3] = {1.0f, 0.0f, 1.0f};
    CHECK(sluice_remove_particles_in(sim, flipped, lo) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_remove_particles_in(sim, lo, hi) == SLUICE_OK);
    CHECK(sluice_step(sim) == SLUICE_OK);
    CHECK(sluice_read_particles(sim, read, ids, 400, &count) == SLUICE_OK);
    CHECK(count == start);
    for (uint32_t i = 0; i < count; ++i)
        CHECK(ids[i] < first);
    const float drain[6] = {0.2f, 0.0f, 0.0f, 0.4f, 0.4f, 0.24f};
    CHECK(sluice_set_drains(sim, drain, 1) == SLUICE_OK);
    CHECK(sluice_set_drains(sim, NULL, 1) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_set_drains(sim, NULL, 0) == SLUICE_OK);
    CHECK(view.positions != 0 && view.velocities != 0 && view.ids != 0);
    CHECK(view.positionStride == 16 && view.idStride == 4);
    CHECK(sluice_advance(sim, -1.0, 4, &frame) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_time(sim) > 0.06 && sluice_time(sim) < 0.07); /* four steps of 1/60 s */
}

/* The ball dropped as a dynamic body half as dense as water: its force, read without waiting. */
static void readsBodiesWithoutWaiting(const char* sceneFile) {
    static const char* kBodyScene =
        "{\"simulation\": {\"spacing\": 0.02},"
        " \"fluid\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [0.24, 0.1, 0.24]}}],"
        " \"colliders\": [{\"asset\": \"sphere.slc\", \"translation\": [0.12, 0.12, 0.12],"
        "                  \"scale\": 0.3, \"dynamic\": {\"density\": 500}}],"
        " \"domain\": {\"min\": [0, 0, 0], \"max\": [0.24, 0.3, 0.24]}}";
    SluiceSimulation* sim = NULL;
    CHECK(sluice_simulation_create_from_json(kBodyScene, sceneFile, &sim) == SLUICE_OK);
    if (!sim)
        return;
    SluiceBody bodies[2];
    uint32_t count = 7;
    uint64_t step = 0;
    CHECK(sluice_latest_bodies(sim, bodies, 2, &count, &step) == SLUICE_OK);
    CHECK(count == 0); /* no step yet */
    /* A copy completes a step or two behind; llvmpipe finishes each step before it returns. */
    for (int i = 0; i < 6 && count == 0; ++i) {
        CHECK(sluice_step(sim) == SLUICE_OK);
        CHECK(sluice_latest_bodies(sim, bodies, 2, &count, &step) == SLUICE_OK);
    }
    CHECK(count == 1);
    CHECK(step >= 1);
    CHECK(bodies[0].collider == 0);
    CHECK(isfinite(bodies[0].force[1]) && isfinite(bodies[0].centreOfMass[1]));
    CHECK(fabsf(bodies[0].orientation[3]) > 0.9f);
    CHECK(sluice_latest_bodies(sim, NULL, 2, &count, &step) == SLUICE_ERROR_INVALID_ARGUMENT);
    {
        const float to[3] = {0.12f, 0.2f, 0.12f}, turn[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        const float up[3] = {0.0f, 0.5f, 0.0f};
        CHECK(sluice_teleport_body(sim, 0, to, turn, up, NULL) == SLUICE_OK);
        CHECK(sluice_teleport_body(sim, 3, to, turn, NULL, NULL) == SLUICE_ERROR_INVALID_ARGUMENT);
        CHECK(sluice_teleport_body(sim, 0, NULL, turn, NULL, NULL) ==
              SLUICE_ERROR_INVALID_ARGUMENT);
        CHECK(sluice_step(sim) == SLUICE_OK);
        /* Held by the game, the body goes where it is put and stays there. */
        const float held[3] = {0.1f, 0.2f, 0.1f};
        CHECK(sluice_set_body_kinematic(sim, 3, 1) == SLUICE_ERROR_INVALID_ARGUMENT);
        CHECK(sluice_set_collider_pose(sim, 0, held, turn) == SLUICE_ERROR_INVALID_ARGUMENT);
        CHECK(sluice_set_body_kinematic(sim, 0, 1) == SLUICE_OK);
        CHECK(sluice_set_collider_pose(sim, 0, held, turn) == SLUICE_OK);
        CHECK(sluice_step(sim) == SLUICE_OK);
        CHECK(sluice_step(sim) == SLUICE_OK);
        CHECK(sluice_step(sim) == SLUICE_OK);
        count = 0;
        CHECK(sluice_latest_bodies(sim, bodies, 2, &count, &step) == SLUICE_OK);
        CHECK(count == 1 && step >= 2); /* a step after the one that moved it */
        CHECK(fabsf(bodies[0].centreOfMass[1] - held[1]) < 1e-3f); /* falling, 12 mm */
        CHECK(sluice_set_body_kinematic(sim, 0, 0) == SLUICE_OK);
        CHECK(sluice_step(sim) == SLUICE_OK);
    }
    sluice_simulation_destroy(sim);
}

/* Water resting on a measured box floor given by its shape, beside a capsule: the floor's force,
 * read without waiting, carries the water down; a body cannot be measured. */
static void measuresAShapeFloor(const char* sceneFile) {
    static const char* kFloorScene =
        "{\"simulation\": {\"spacing\": 0.02, \"substeps\": 2},"
        " \"fluid\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [0.12, 0.08, 0.12]}}],"
        " \"colliders\": [{\"shape\": {\"box\": {\"size\": [0.3, 0.1, 0.3]}},"
        "                  \"translation\": [0.06, -0.05, 0.06], \"measureForce\": true},"
        "                 {\"shape\": {\"capsule\": {\"radius\": 0.03, \"height\": 0.2}},"
        "                  \"translation\": [0.2, 0.1, 0.06]}],"
        " \"domain\": {\"min\": [0, -0.1, 0], \"max\": [0.3, 0.3, 0.12]}}";
    SluiceSimulation* sim = NULL;
    CHECK(sluice_simulation_create_from_json(kFloorScene, sceneFile, &sim) == SLUICE_OK);
    if (!sim)
        return;
    SluiceColliderForce forces[2];
    uint32_t count = 7;
    uint64_t step = 0;
    for (int i = 0; i < 6 && count != 1; ++i) {
        CHECK(sluice_step(sim) == SLUICE_OK);
        CHECK(sluice_latest_forces(sim, forces, 2, &count, &step) == SLUICE_OK);
    }
    CHECK(count == 1 && step >= 1);
    CHECK(forces[0].collider == 0);
    CHECK(forces[0].force[1] < 0.0f); /* the water presses the floor down */
    CHECK(sluice_measure_force(sim, 1, 1) == SLUICE_OK);
    CHECK(sluice_measure_force(sim, 5, 1) == SLUICE_ERROR_INVALID_ARGUMENT);
    CHECK(sluice_latest_forces(sim, NULL, 2, &count, &step) == SLUICE_ERROR_INVALID_ARGUMENT);
    sluice_simulation_destroy(sim);
}

int main(int argc, char** argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s ASSETS_DIR\n", argv[0]);
        return 2;
    }
    char sceneFile[4096];
    snprintf(sceneFile, sizeof sceneFile, "%s/c-api.json", argv[1]);
    CHECK(strcmp(sluice_last_error(), "") == 0);
    refusesWithoutContext(sceneFile);

    SluiceContext* context = NULL;
    CHECK(sluice_context_create_headless(&context) == SLUICE_OK);
    if (!context) {
        fprintf(stderr, "no headless context: %s\n", sluice_last_error());
        return 1;
    }
    refusesBadScenes(sceneFile);
    SluiceSimulation* sim = NULL;
    CHECK(sluice_simulation_create_from_json(kScene, sceneFile, &sim) == SLUICE_OK);
    if (sim)
        movesAddsAndViews(sim);
    sluice_simulation_destroy(sim);
    readsBodiesWithoutWaiting(sceneFile);
    measuresAShapeFloor(sceneFile);
    sluice_context_destroy(context);
    printf("%d passed, %d failed\n", g_passed, g_failed);
    return g_failed == 0 ? 0 : 1;
}
