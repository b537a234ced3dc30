// Volume maps of static colliders (docs/pbf.md, "Volume maps"): which colliders get one, their
// build on the GPU (pbf_volume_map.comp) when a scene loads and when h changes, and the boundary
// probe (pbf_boundary_probe.comp) that reads the walls' and colliders' share at points.
#include "sim/SimulationImpl.h"

#include "colliders/VolumeMapSize.h"
#include "sluice/gpu/colliders/VolumeMapPass.h"

namespace sluice::rt {

std::uint64_t Simulation::Impl::volumeMapPoints(std::size_t c) const {
    return rt::volumeMapPoints(colliderAssets[c]);
}

bool Simulation::Impl::mapsCollider(std::size_t c) const {
    return bodySetup.bodyOfCollider[c] == shared::kNoBody &&
           volumeMapPoints(c) <= shared::kVolumeMapMaxPoints;
}

bool Simulation::Impl::wantsVolumeMap(std::size_t c) const {
    return volumeMapsFit && mapsCollider(c);
}

std::uint64_t Simulation::Impl::volumeMapWords() const {
    std::uint64_t words = 0;
    for (std::size_t c = 0; c < colliderAssets.size(); ++c)
        words += mapsCollider(c) ? volumeMapPoints(c) : 0;
    return words;
}

std::uint64_t Simulation::Impl::sdfBufferBytes(std::int64_t maxBlockBytes) {
    // Volume maps go after the grids in the same block; where they would not fit, the colliders
    // keep the flat closed form (docs/pbf.md, "Volume maps").
    const std::uint64_t grids = colliderDataBytes(colliderAssets);
    const std::uint64_t block = std::min<std::uint64_t>(
        0xffffffffull, maxBlockBytes > 0 ? std::uint64_t(maxBlockBytes) : ~0ull);
    const std::uint64_t maps = volumeMapWords() * sizeof(float);
    volumeMapsFit = grids + maps <= block;
    return grids + (volumeMapsFit ? maps : 0);
}

std::vector<gpu::ShaderDefine> Simulation::Impl::colliderDefines() const {
    std::vector<gpu::ShaderDefine> defines;
    if (anySparse(colliderAssets))
        defines.push_back({"SLUICE_SPARSE_COLLIDERS", "1"});
    if (!sdfAsTexels)
        defines.push_back({"SLUICE_SDF_STORAGE", "1"});
    return defines;
}

void Simulation::Impl::bindColliders() const {
    bindColliderRecords(colliderBuf);
    sdfBuf.bindStorage(shared::kBindSdf);
    if (sdfAsTexels)
        sdfTexels.bindTexture(shared::kUnitSdfTexels);
}

Result<void> Simulation::Impl::buildVolumeMaps() {
    volumeMapsH = k.h;
    volumeMapLoad = {};
    // A map baked with the collider for this support is uploaded; the others are built here.
    std::vector<std::size_t> toBuild;
    for (std::size_t c = 0; c < colliderRecords.size(); ++c) {
        if (colliderRecords[c].volumeMap == shared::kNoVolumeMap)
            continue;
        // A map built in code with the wrong number of values is built again, not uploaded.
        const format::VolumeMap* baked = colliderAssets[c].volumeMapFor(supportOf(c));
        if (baked && baked->values.size() == volumeMapPoints(c)) {
            sdfBuf.upload(baked->values, std::size_t(colliderRecords[c].volumeMap) * sizeof(float));
            ++volumeMapLoad.baked;
        } else {
            toBuild.push_back(c);
        }
    }
    if (toBuild.empty())
        return {};
    if (!volumeMapPass.id()) {
        auto program = gpu::volumeMapProgram(colliderDefines());
        if (!program)
            return program.error();
        volumeMapPass = std::move(*program);
    }
    bindColliders();
    sdfBuf.bindStorage(shared::kBindVolumeMapOut);
    // Each map in the collider's local units, at its scene scale. Not a step's command:
    // commandCount() leaves them out.
    for (std::size_t c : toBuild)
        gpu::dispatchVolumeMap(volumeMapPass, std::uint32_t(c), colliderAssets[c], supportOf(c));
    volumeMapLoad.built = std::uint32_t(toBuild.size());
    volumeMapLoad.builtFor.assign(toBuild.begin(), toBuild.end());
    // The passes fetch the maps through the SDF buffer's texel view.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    return {};
}

double Simulation::Impl::supportOf(std::size_t c) const {
    return double(k.h) / double(scene.colliders[c].scale);
}

VolumeMapLoad Simulation::volumeMapLoad() const {
    return m_impl->volumeMapLoad;
}

std::uint32_t Simulation::volumeMapCount() const {
    const Impl& s = *m_impl;
    return std::uint32_t(std::count_if(
        s.colliderRecords.begin(), s.colliderRecords.end(),
        [](const shared::GpuCollider& r) { return r.volumeMap != shared::kNoVolumeMap; }));
}

Result<std::vector<glm::vec4>> Simulation::solidBoundaryAt(const std::vector<glm::vec3>& points) {
    Impl& s = *m_impl;
    if (points.empty())
        return std::vector<glm::vec4>{};
    if (!s.boundaryProbe.id()) {
        const std::vector<gpu::ShaderDefine> defines = s.colliderDefines();
        auto program = gpu::Program::compute(
            "pbf_boundary_probe.comp", shaders::shaderSource("pbf_boundary_probe.comp"), defines);
        if (!program)
            return program.error();
        s.boundaryProbe = std::move(*program);
    }
    std::vector<glm::vec4> in;
    for (const glm::vec3& p : points)
        in.emplace_back(p, 0.0f);
    auto input = gpu::Buffer::createFrom(in, "boundary probe points");
    if (!input)
        return input.error();
    auto output = gpu::Buffer::create(in.size() * sizeof(glm::vec4), "boundary probe shares");
    if (!output)
        return output.error();
    s.uploadParams();
    s.uploadColliders(s.time, s.time); // static colliders' records get their pose
    s.params.bindBase(GL_UNIFORM_BUFFER, shared::kBindParams);
    s.bindColliders();
    input->bindStorage(shared::kBindPosIn);
    output->bindStorage(shared::kBindPosOut);
    s.boundaryProbe.set("uCount", std::uint32_t(in.size()));
    s.boundaryProbe.dispatchChunked(glm::uvec3(groupsFor(std::uint32_t(in.size())), 1, 1),
                                    kMaxGroupsPerDispatch);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    return output->download<glm::vec4>();
}

} // namespace sluice::rt
