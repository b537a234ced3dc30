// A game loop around Sluice in about 200 lines: its own GLFW window, GL loader (libepoxy) and
// shader; a pool with a paddle the arrow keys move, a capsule character wading through it, a tap
// (space) whose water a drain catches, and the water's force on the paddle printed every second.
// `--check FRAMES` plays FRAMES frames with scripted keys, then prints what it saw and exits 1 if
// the water is not on screen, the paddle felt no force or the drain did not take the tap's water.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <epoxy/gl.h> // the game's loader; Sluice's is its own (sluice_glad_*)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <sluice/rt/sim/Simulation.h>
#include <sluice/sluice.h>

namespace {

using namespace sluice;

// The game's own shader: each slot of Sluice's position buffer is a point. The view's draw
// command draws only the live particles, which lead the slots.
const char* kVertex = R"(#version 450 core
layout(location = 0) in vec4 position;
uniform mat4 viewProjection;
out float height;
void main() {
    gl_Position = viewProjection * vec4(position.xyz, 1.0);
    gl_PointSize = 4.0;
    height = position.y;
})";
const char* kFragment = R"(#version 450 core
in float height;
out vec4 colour;
void main() { colour = vec4(0.1, 0.35 + height, 0.9, 1.0); })";

GLuint compile(GLenum kind, const char* source) {
    const GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    return shader;
}

// The pool, the paddle (collider 0, its force measured), the character (collider 1) and the
// drain under the tap, built in code from Sluice's defaults.
format::Scene poolScene() {
    format::Scene scene;
    scene.path = "paddle-pool";
    scene.simulation.spacing = 0.03f;
    scene.simulation.capacity = 8000;
    scene.domainMin = glm::vec3(-0.6f, 0.0f, -0.3f);
    scene.domainMax = glm::vec3(0.6f, 0.8f, 0.3f);
    format::FluidBlock pool;
    pool.min = glm::vec3(-0.6f, 0.0f, -0.3f);
    pool.max = glm::vec3(0.6f, 0.18f, 0.3f);
    scene.blocks.push_back(pool);
    format::SceneCollider paddle;
    paddle.shape = format::ColliderShape{.kind = format::ColliderShape::Kind::Box,
                                         .size = {0.04f, 0.3f, 0.4f}};
    paddle.translation = {-0.4f, 0.52f, 0.0f}; // above the water: it dips in (play)
    paddle.measureForce = true;
    scene.colliders.push_back(paddle);
    format::SceneCollider character;
    character.shape = format::ColliderShape{
        .kind = format::ColliderShape::Kind::Capsule, .radius = 0.06f, .height = 0.4f};
    character.translation = {0.0f, 0.53f, 0.15f};
    scene.colliders.push_back(character);
    scene.drains.push_back({{0.35f, 0.3f, -0.15f}, {0.6f, 0.45f, 0.15f}}); // under the tap
    return scene;
}

// The tap: a block of water above the drain, falling.
void openTap(rt::Simulation& sim) {
    std::vector<glm::vec3> positions, velocities;
    for (int x = 0; x < 6; ++x)
        for (int y = 0; y < 4; ++y)
            for (int z = 0; z < 6; ++z) {
                positions.emplace_back(0.4f + 0.03f * x, 0.6f + 0.03f * y, -0.08f + 0.03f * z);
                velocities.emplace_back(0.0f, -1.0f, 0.0f);
            }
    if (auto first = sim.addParticles(positions, velocities); !first)
        std::fprintf(stderr, "tap: %s\n", first.error().message().c_str());
}

struct Report {
    std::uint32_t startCount = 0, afterTap = 0, endCount = 0;
    float strongestPush = 0.0f; // [N], the paddle's largest force
    long waterPixels = 0;
};

// The game loop: keys (or the script) move the paddle and open the tap, the character walks,
// Sluice steps by the frame's time, and the water is drawn with the game's shader.
Report play(GLFWwindow* window, rt::Simulation& sim, int checkFrames) {
    const GLuint program = glCreateProgram();
    glAttachShader(program, compile(GL_VERTEX_SHADER, kVertex));
    glAttachShader(program, compile(GL_FRAGMENT_SHADER, kFragment));
    glLinkProgram(program);
    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribFormat(vao, 0, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
    glEnable(GL_PROGRAM_POINT_SIZE);
    const glm::mat4 viewProjection =
        glm::perspective(glm::radians(45.0f), 640.0f / 400.0f, 0.05f, 10.0f) *
        glm::lookAt(glm::vec3(0.0f, 0.9f, 1.5f), glm::vec3(0.0f, 0.15f, 0.0f), glm::vec3(0, 1, 0));
    Report report;
    report.startCount = sim.liveParticleCount();
    float paddleX = -0.4f, walk = 0.0f;
    int tappedAt = -1;
    double last = glfwGetTime();
    for (int frame = 0; !glfwWindowShouldClose(window) && (!checkFrames || frame < checkFrames);
         ++frame) {
        glfwPollEvents();
        const double now = glfwGetTime();
        const double dt = checkFrames ? 1.0 / 60.0 : now - last;
        last = now;
        float push = float(glfwGetKey(window, GLFW_KEY_RIGHT) == GLFW_PRESS) -
                     float(glfwGetKey(window, GLFW_KEY_LEFT) == GLFW_PRESS);
        bool tap = glfwGetKey(window, GLFW_KEY_SPACE) == GLFW_PRESS;
        if (checkFrames) { // the script: the paddle sweeps back and forth, the tap opens once
            push = (frame / 30) % 2 == 0 ? 1.0f : -1.0f;
            tap = frame == 10;
        }
        paddleX = glm::clamp(paddleX + push * 0.6f * float(dt), -0.55f, -0.2f);
        walk += float(dt);
        // Both start above the water and step into it over the first 0.8 s.
        const float enter = 0.4f * std::max(0.0f, 0.8f - walk);
        sim.setColliderPose(0, {paddleX, 0.2f + enter, 0.0f}, glm::quat(1, 0, 0, 0));
        sim.setColliderPose(1, {0.15f * std::sin(walk), 0.21f + enter, 0.15f * std::cos(walk)},
                            glm::quat(1, 0, 0, 0));
        if (tap) {
            openTap(sim);
            tappedAt = frame;
        }
        sim.advance(dt);
        if (frame == tappedAt + 2) // joined, not yet in the drain
            report.afterTap = sim.liveParticleCount();
        if (auto forces = sim.latestForces(); forces && !forces->colliders.empty()) {
            const glm::vec3 f = forces->colliders[0].force;
            report.strongestPush = std::max(report.strongestPush, glm::length(f));
            if (frame % 60 == 0)
                std::printf("frame %d: the water pushes the paddle with (%.3f, %.3f, %.3f) N\n",
                            frame, f.x, f.y, f.z);
        }
        // Sluice's buffer drawn with the game's shader; its name may change every step.
        int width = 0, height = 0;
        glfwGetFramebufferSize(window, &width, &height);
        glViewport(0, 0, width, height);
        glClearColor(0.9f, 0.9f, 0.85f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        const rt::ParticleView view = sim.particleView();
        glUseProgram(program);
        glUniformMatrix4fv(glGetUniformLocation(program, "viewProjection"), 1, GL_FALSE,
                           glm::value_ptr(viewProjection));
        glVertexArrayVertexBuffer(vao, 0, view.positions, 0, GLsizei(view.positionStride));
        glBindVertexArray(vao);
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, view.drawArgs);
        glDrawArraysIndirect(GL_POINTS, nullptr);
        if (checkFrames && frame + 1 == checkFrames) {
            std::vector<unsigned char> pixels(std::size_t(width) * height * 4);
            glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
            for (std::size_t p = 0; p < pixels.size(); p += 4)
                report.waterPixels += pixels[p + 2] > 200 && pixels[p] < 60; // blue, not the wall
        }
        glfwSwapBuffers(window);
    }
    report.endCount = sim.liveParticleCount();
    return report;
}

} // namespace

int main(int argc, char** argv) {
    const bool check = argc == 3 && std::strcmp(argv[1], "--check") == 0;
    const int checkFrames = check ? std::atoi(argv[2]) : 0;
    if (!glfwInit())
        return 2;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow* window = glfwCreateWindow(640, 400, "Sluice paddle", nullptr, nullptr);
    if (!window)
        return 2;
    glfwMakeContextCurrent(window);
    glfwSwapInterval(check ? 0 : 1);
    if (sluice_load_gl(glfwGetProcAddress) != SLUICE_OK) { // Sluice's loader, from our context
        std::fprintf(stderr, "%s\n", sluice_last_error());
        return 2;
    }
    Report report;
    {
        const format::Scene scene = poolScene();
        auto colliders = rt::loadSceneColliders(scene); // the shapes, sampled
        auto sim = colliders ? rt::Simulation::create(scene, std::move(*colliders))
                             : Result<rt::Simulation>(colliders.error());
        if (!sim) {
            std::fprintf(stderr, "%s\n", sim.error().message().c_str());
            return 2;
        }
        report = play(window, *sim, checkFrames);
    } // the simulation goes before its context
    glfwDestroyWindow(window);
    glfwTerminate();
    std::printf("particles: %u at the start, %u after the tap, %u at the end\n", report.startCount,
                report.afterTap, report.endCount);
    std::printf("water pixels: %ld; strongest push on the paddle: %.3f N\n", report.waterPixels,
                report.strongestPush);
    if (!check)
        return 0;
    const bool ok = report.waterPixels > 1000 && report.strongestPush > 0.01f &&
                    report.afterTap > report.startCount && report.endCount == report.startCount;
    std::printf("%s\n", ok ? "check passed" : "check FAILED");
    return ok ? 0 : 1;
}
