// Draws the scene's colliders by sphere tracing their signed distance grids, uploaded once (a
// dense grid as a 3D texture, a sparse one's NanoVDB grid into a storage buffer): an opaque
// pass before the particles and a translucent "glass" pass after them.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"
#include "sluice/format/scene/Scene.h"
#include "sluice/gpu/Buffer.h"
#include "sluice/gpu/Program.h"
#include "sluice/gpu/Texture3D.h"

#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::rt {

/// Ray-marched colliders. Needs the frame block bound (shared/Render.h) and an empty vertex
/// array bound when drawing.
class ColliderPass {
public:
    /// Uploads every collider of `scene` (`colliders[i]` belongs to scene.colliders[i]) and
    /// compiles the two programs (and their sparse variants when a collider is sparse). InvalidArgument when the counts differ; the texture and
    /// program errors of the gpu library otherwise.
    static Result<ColliderPass> create(const format::Scene& scene,
                                       const std::vector<format::ColliderAsset>& colliders);

    /// The opaque surfaces with collider i at poses[i] (Simulation::colliderPoses: dynamic
    /// bodies where the solver moved them): depth test and write on. With `glassWalls`,
    /// surfaces with more of the same collider behind them are left to drawGlass.
    void drawOpaque(const std::vector<ColliderPose>& poses, bool glassWalls) const;
    /// The glass surfaces, blended over what is drawn, depth test on and depth write off.
    void drawGlass(const std::vector<ColliderPose>& poses) const;

    std::size_t count() const { return m_colliders.size(); }

private:
    struct Collider {
        gpu::Texture3D sdf;         // dense
        bool sparse = false;
        std::uint32_t gridOffset = 0; // sparse: its grid in m_sparseGrids [bytes]
        glm::vec3 origin{0.0f}; // grid point (0, 0, 0), local [asset units]
        glm::vec3 dims{0.0f};   // grid points per axis
        float voxel = 0.0f;     // [asset units]
        glm::vec3 colour{0.0f};
    };

    // Each collider with `dense` or, when it is sparse, `sparse`.
    void draw(const gpu::Program& dense, const gpu::Program& sparse,
              const std::vector<ColliderPose>& poses, bool glassWalls) const;

    std::vector<Collider> m_colliders;
    gpu::Buffer m_sparseGrids; // every sparse collider's NanoVDB grid, 32-byte aligned
    gpu::Program m_opaque;
    gpu::Program m_glass;
    gpu::Program m_opaqueSparse; // compiled when a collider is sparse
    gpu::Program m_glassSparse;
};

} // namespace sluice::rt
