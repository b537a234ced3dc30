// A game's own glad2 loader linked beside Sluice's, in one program and one translation unit
// with Sluice's public headers: it links (no symbol is shared), each loader drives its own
// calls, and the game copies Sluice's particle buffer with its loader's functions.
#include <glad/gl.h> // the game's loader, generated for this test only

#include <EGL/egl.h>

#include <cstdio>
#include <vector>

#include "sluice/rt/sim/Simulation.h" // must compile beside the game's GL header
#include "sluice/sluice.h"

namespace {

int g_failed = 0;
int g_passed = 0;

void check(bool ok, const char* what) {
    if (ok) {
        ++g_passed;
        return;
    }
    ++g_failed;
    std::fprintf(stderr, "OwnLoaderTest: %s failed (sluice: %s)\n", what, sluice_last_error());
}

GLADapiproc gameProcAddress(const char* name) {
    return reinterpret_cast<GLADapiproc>(eglGetProcAddress(name));
}

} // namespace

int main() {
    SluiceContext* context = nullptr;
    if (sluice_context_create_headless(&context) != SLUICE_OK) {
        std::fprintf(stderr, "OwnLoaderTest: no headless context: %s\n", sluice_last_error());
        return 1;
    }
    // The game loads its loader from the same current context.
    check(gladLoadGL(gameProcAddress) != 0 && GLAD_GL_VERSION_4_5, "the game's gladLoadGL");

    SluiceSimulation* sim = nullptr;
    check(sluice_simulation_create_from_json(
              R"({"simulation": {"spacing": 0.02}, "fluid": [{"box": {"min": [0, 0, 0],)"
              R"( "max": [0.08, 0.08, 0.08]}}], "domain": {"min": [0, 0, 0],)"
              R"( "max": [0.08, 0.16, 0.08]}})",
              "own-loader.json", &sim) == SLUICE_OK,
          "create");
    if (!sim)
        return 1;
    check(sluice_step(sim) == SLUICE_OK, "step");
    SluiceParticleView view{};
    check(sluice_particle_view(sim, &view) == SLUICE_OK && view.count == 64, "view");

    // The game's own buffer, filled from Sluice's with the game's functions.
    GLuint copy = 0;
    glCreateBuffers(1, &copy);
    const GLsizeiptr bytes = GLsizeiptr(view.count) * view.positionStride;
    glNamedBufferData(copy, bytes, nullptr, GL_STREAM_COPY);
    glCopyNamedBufferSubData(view.positions, copy, 0, 0, bytes);
    std::vector<float> mine(std::size_t(view.count) * 4);
    glGetNamedBufferSubData(copy, 0, bytes, mine.data());
    check(glGetError() == GL_NO_ERROR, "the game's GL calls");

    std::vector<float> positions(std::size_t(view.count) * 3);
    std::uint32_t count = 0;
    check(sluice_read_particles(sim, positions.data(), nullptr, view.count, &count) == SLUICE_OK &&
              count == view.count,
          "read particles");
    bool same = true;
    for (std::uint32_t i = 0; i < count; ++i)
        for (int a = 0; a < 3; ++a)
            same = same && mine[4 * i + a] == positions[3 * i + a];
    check(same, "the game's copy equals Sluice's particles");

    // Sluice's copy in id order into the game's buffer, and its draw command.
    std::vector<std::uint32_t> ids(view.count);
    check(sluice_read_particles(sim, positions.data(), ids.data(), view.count, &count) == SLUICE_OK,
          "read particles and ids");
    check(sluice_copy_particles_by_id(sim, copy, 0, 0, view.count) == SLUICE_OK, "copy by id");
    glGetNamedBufferSubData(copy, 0, bytes, mine.data());
    bool inIdOrder = true;
    for (std::uint32_t i = 0; i < count; ++i)
        for (int a = 0; a < 3; ++a)
            inIdOrder = inIdOrder && ids[i] < count &&
                        mine[4 * ids[i] + a] == positions[3 * i + a] &&
                        mine[4 * ids[i] + 3] == 1.0f;
    check(inIdOrder, "the copy by id puts each particle at its id");
    check(sluice_copy_particles_by_id(sim, copy, 0, 0, view.count + 1) ==
              SLUICE_ERROR_INVALID_ARGUMENT,
          "a copy larger than the game's buffer is refused");
    GLuint command[4] = {0, 0, 0, 0};
    glGetNamedBufferSubData(view.drawArgs, 0, sizeof command, command);
    check(command[0] == view.count && command[1] == 1, "the draw command counts the particles");
    glDeleteBuffers(1, &copy);

    sluice_simulation_destroy(sim);
    sluice_context_destroy(context);
    std::printf("%d passed, %d failed\n", g_passed, g_failed);
    return g_failed == 0 ? 0 : 1;
}
