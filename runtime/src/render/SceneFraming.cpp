// Scene bounds from blocks, emitters, the domain and collider grid boxes; the default camera.
#include "sluice/rt/render/SceneFraming.h"

#include <algorithm>
#include <limits>

#include "sluice/rt/sim/SceneSetup.h"

namespace sluice::rt {
namespace {

struct BoxGrower {
    glm::vec3 lo{std::numeric_limits<float>::max()};
    glm::vec3 hi{std::numeric_limits<float>::lowest()};
    bool any = false;

    void add(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
        any = true;
    }
    void add(glm::vec3 a, glm::vec3 b) {
        add(a);
        add(b);
    }
};

} // namespace

Bounds sceneBounds(const format::Scene& scene,
                   const std::vector<format::ColliderAsset>& colliders) {
    BoxGrower box;
    if (scene.domainMin && scene.domainMax)
        box.add(*scene.domainMin, *scene.domainMax);
    for (const format::FluidBlock& block : scene.blocks) {
        if (block.shape == format::FluidBlock::Shape::Box)
            box.add(block.min, block.max);
        else
            box.add(block.center - glm::vec3(block.radius), block.center + glm::vec3(block.radius));
    }
    for (const format::Emitter& emitter : scene.emitters)
        box.add(emitter.position - glm::vec3(emitter.radius),
                emitter.position + glm::vec3(emitter.radius));
    const std::size_t placed = std::min(colliders.size(), scene.colliders.size());
    for (std::size_t i = 0; i < placed; ++i) {
        const format::ColliderMeta& meta = colliders[i].meta;
        const glm::vec3 lo(meta.origin);
        const glm::vec3 hi = lo + glm::vec3(meta.dims - 1u) * float(meta.voxelSize);
        const ColliderPose pose = colliderPose(scene.colliders[i], 0.0f);
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 local((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                                  (corner & 4) ? hi.z : lo.z);
            box.add(pose.toWorld(local));
        }
    }
    if (!box.any)
        return {glm::vec3(-0.5f), glm::vec3(0.5f)};
    return {box.lo, box.hi};
}

OrbitCamera sceneCamera(const format::Scene& scene, const Bounds& bounds, float aspect) {
    const format::Camera& c = scene.camera;
    if (c.set && c.position != c.target && c.fovDegrees > 0.0f && c.fovDegrees < 180.0f)
        return OrbitCamera::lookAt(c.position, c.target, c.fovDegrees);
    // From the front right and above, like the shipped scenes' cameras.
    const glm::vec3 direction = glm::normalize(glm::vec3(1.1f, 0.75f, 1.3f));
    OrbitCamera camera = OrbitCamera::lookAt(bounds.centre() + direction, bounds.centre(), 45.0f);
    camera.frame(bounds, aspect);
    return camera;
}

float floorHeight(const format::Scene& scene, const Bounds& bounds) {
    return scene.domainMin ? scene.domainMin->y : bounds.min.y;
}

} // namespace sluice::rt
