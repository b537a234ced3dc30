// Collider textures, poses per frame and the two ray-marching draws.
#include "ColliderPass.h"

#include <array>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "shared/Render.h"
#include "sluice/rt/RuntimeShaders.h"
#include "sluice/rt/SceneSetup.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {
namespace {

// Local [asset units] -> world [m]: translate * rotate * uniform scale (docs/pbf.md).
glm::mat4 localToWorld(const ColliderPose& pose) {
    return glm::translate(glm::mat4(1.0f), pose.translation) * glm::mat4_cast(pose.rotation) *
           glm::scale(glm::mat4(1.0f), glm::vec3(pose.scale));
}

Result<gpu::Program> program(bool glass) {
    const std::array<gpu::ShaderDefine, 1> defines{{{"SLUICE_GLASS", "1"}}};
    return gpu::Program::graphics(glass ? "render_collider (glass)" : "render_collider",
                                  shaders::shaderSource("render_collider.vert"),
                                  shaders::shaderSource("render_collider.frag"),
                                  glass ? std::span<const gpu::ShaderDefine>(defines)
                                        : std::span<const gpu::ShaderDefine>());
}

} // namespace

glm::vec3 colliderColour(std::size_t index) {
    static constexpr std::array<glm::vec3, 4> kPalette{{
        {0.78f, 0.75f, 0.70f}, // stone
        {0.86f, 0.46f, 0.26f}, // terracotta
        {0.52f, 0.70f, 0.42f}, // sage
        {0.74f, 0.58f, 0.82f}, // lilac
    }};
    return kPalette[index % kPalette.size()];
}

Result<ColliderPass> ColliderPass::create(const format::Scene& scene,
                                          const std::vector<format::ColliderAsset>& colliders) {
    if (colliders.size() != scene.colliders.size())
        return fail(ErrorCode::InvalidArgument,
                    scene.path + ": " + std::to_string(scene.colliders.size()) +
                        " colliders in the scene but " + std::to_string(colliders.size()) +
                        " collider assets given to the renderer");
    ColliderPass pass;
    for (std::size_t i = 0; i < colliders.size(); ++i) {
        const format::ColliderAsset& asset = colliders[i];
        auto texture =
            gpu::Texture3D::createR32F(asset.meta.dims, "collider " + std::to_string(i) + " SDF");
        if (!texture)
            return fail(texture.error().code,
                         scene.colliders[i].resolvedPath + ": " + texture.error().detail);
        texture->upload(asset.distances);
        Collider collider;
        collider.sdf = std::move(*texture);
        collider.origin = glm::vec3(asset.meta.origin);
        collider.dims = glm::vec3(asset.meta.dims);
        collider.voxel = float(asset.meta.voxelSize);
        collider.colour = colliderColour(i);
        pass.m_colliders.push_back(std::move(collider));
    }
    auto opaque = program(false);
    if (!opaque)
        return opaque.error();
    auto glass = program(true);
    if (!glass)
        return glass.error();
    pass.m_opaque = std::move(*opaque);
    pass.m_glass = std::move(*glass);
    return pass;
}

void ColliderPass::drawOpaque(const std::vector<ColliderPose>& poses, bool glassWalls) const {
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    draw(m_opaque, poses, glassWalls);
}

void ColliderPass::drawGlass(const std::vector<ColliderPose>& poses) const {
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
    draw(m_glass, poses, true);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
}

void ColliderPass::draw(const gpu::Program& program, const std::vector<ColliderPose>& poses,
                        bool glassWalls) const {
    // Each pixel keeps only its exit face (see render_collider.frag), so no face culling.
    glDisable(GL_CULL_FACE);
    program.use();
    program.set("uGlassWalls", std::int32_t(glassWalls ? 1 : 0));
    for (std::size_t i = 0; i < m_colliders.size() && i < poses.size(); ++i) {
        const Collider& collider = m_colliders[i];
        const glm::mat4 toWorld = localToWorld(poses[i]);
        const glm::vec3 boxMax = collider.origin + (collider.dims - 1.0f) * collider.voxel;
        program.set("uLocalToWorld", toWorld);
        program.set("uWorldToLocal", glm::inverse(toWorld));
        program.set("uBoxMin", collider.origin);
        program.set("uBoxMax", boxMax);
        program.set("uGridOrigin", collider.origin);
        program.set("uDims", collider.dims);
        program.set("uVoxel", collider.voxel);
        program.set("uColour", collider.colour);
        collider.sdf.bindTexture(shared::kRenderUnitSdf);
        glDrawArrays(GL_TRIANGLES, 0, 36);
    }
}

} // namespace sluice::rt
