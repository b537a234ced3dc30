// Collider textures, poses per frame and the two ray-marching draws.
#include "ColliderPass.h"

#include <array>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "sluice/gpu/colliders/SparseGrids.h"
#include "shared/Render.h"
#include "sluice/rt/RuntimeShaders.h"
#include "sluice/rt/sim/SceneSetup.h"
#include "sluice/rt/render/Renderer.h"

namespace sluice::rt {
namespace {

// Local [asset units] -> world [m]: translate * rotate * uniform scale (docs/pbf.md).
glm::mat4 localToWorld(const ColliderPose& pose) {
    return glm::translate(glm::mat4(1.0f), pose.translation) * glm::mat4_cast(pose.rotation) *
           glm::scale(glm::mat4(1.0f), glm::vec3(pose.scale));
}

Result<gpu::Program> program(bool glass, bool sparse) {
    std::vector<gpu::ShaderDefine> defines;
    if (glass)
        defines.push_back({"SLUICE_GLASS", "1"});
    if (sparse)
        defines.push_back({"SLUICE_SPARSE_COLLIDERS", "1"});
    const std::string name = std::string("render_collider") + (glass ? " (glass)" : "") +
                             (sparse ? " (sparse)" : "");
    return gpu::Program::graphics(name, shaders::shaderSource("render_collider.vert"),
                                  shaders::shaderSource("render_collider.frag"), defines);
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
    std::uint64_t sparseBytes = 0; // NanoVDB grids back to back (SparseGrids.h)
    for (std::size_t i = 0; i < colliders.size(); ++i) {
        const format::ColliderAsset& asset = colliders[i];
        Collider collider;
        collider.origin = glm::vec3(asset.meta.origin);
        collider.dims = glm::vec3(asset.meta.dims);
        collider.voxel = float(asset.meta.voxelSize);
        collider.colour = colliderColour(i);
        if (asset.sparse()) {
            collider.sparse = true;
            collider.gridOffset = std::uint32_t(sparseBytes);
            sparseBytes += gpu::sparseSlotBytes(asset);
            pass.m_colliders.push_back(std::move(collider));
            continue;
        }
        auto texture =
            gpu::Texture3D::createR32F(asset.meta.dims, "collider " + std::to_string(i) + " SDF");
        if (!texture)
            return fail(texture.error().code, scene.path + ": colliders[" + std::to_string(i) +
                                                  "]: " + texture.error().detail);
        texture->upload(asset.distances);
        collider.sdf = std::move(*texture);
        pass.m_colliders.push_back(std::move(collider));
    }
    if (sparseBytes > 0) {
        if (sparseBytes > 0xffffffffu) // PNanoVDB's GLSL addresses are 32 bits
            return fail(ErrorCode::GpuOutOfMemory,
                        scene.path + ": the sparse colliders' grids take " +
                            std::to_string(sparseBytes) +
                            " bytes, more than the 4 GiB the renderer can address");
        auto buffer = gpu::Buffer::create(sparseBytes, "sparse collider grids");
        if (!buffer)
            return fail(buffer.error().code, scene.path + ": " + buffer.error().detail);
        // Each grid straight from its asset to its slot: no packed copy on the CPU.
        for (std::size_t i = 0; i < colliders.size(); ++i)
            if (pass.m_colliders[i].sparse)
                buffer->upload(colliders[i].grid.data(), colliders[i].grid.size(),
                               pass.m_colliders[i].gridOffset);
        pass.m_sparseGrids = std::move(*buffer);
    }
    struct Build {
        gpu::Program* program;
        bool glass, sparse;
    };
    const Build builds[] = {{&pass.m_opaque, false, false},
                            {&pass.m_glass, true, false},
                            {&pass.m_opaqueSparse, false, true},
                            {&pass.m_glassSparse, true, true}};
    for (const Build& b : builds) {
        if (b.sparse && sparseBytes == 0)
            continue;
        auto built = program(b.glass, b.sparse);
        if (!built)
            return built.error();
        *b.program = std::move(*built);
    }
    return pass;
}

void ColliderPass::drawOpaque(const std::vector<ColliderPose>& poses, bool glassWalls) const {
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    draw(m_opaque, m_opaqueSparse, poses, glassWalls);
}

void ColliderPass::drawGlass(const std::vector<ColliderPose>& poses) const {
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
    draw(m_glass, m_glassSparse, poses, true);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
}

void ColliderPass::draw(const gpu::Program& dense, const gpu::Program& sparse,
                        const std::vector<ColliderPose>& poses, bool glassWalls) const {
    // Each pixel keeps only its exit face (see render_collider.frag), so no face culling.
    glDisable(GL_CULL_FACE);
    if (m_sparseGrids.id() != 0)
        m_sparseGrids.bindStorage(shared::kRenderBindSparse);
    for (std::size_t i = 0; i < m_colliders.size() && i < poses.size(); ++i) {
        const Collider& collider = m_colliders[i];
        const gpu::Program& program = collider.sparse ? sparse : dense;
        program.use();
        program.set("uGlassWalls", std::int32_t(glassWalls ? 1 : 0));
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
        if (collider.sparse)
            program.set("uGridOffset", collider.gridOffset);
        else
            collider.sdf.bindTexture(shared::kRenderUnitSdf);
        glDrawArrays(GL_TRIANGLES, 0, 36);
    }
}

} // namespace sluice::rt
