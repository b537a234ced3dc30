// Reads a collider asset through the installed format library: read_collider ASSET.slc.
#include <cstdio>

#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/SdfSampler.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: read_collider ASSET.slc\n");
        return 2;
    }
    sluice::Result<sluice::format::ColliderAsset> asset = sluice::format::readAsset(argv[1]);
    if (!asset) {
        std::fprintf(stderr, "read_collider: %s\n", asset.error().message().c_str());
        return 1;
    }
    const sluice::format::ColliderMeta& meta = asset->meta;
    // The sampler pulls in more of the library (and glm through its interface).
    const sluice::format::SdfSampler sampler(*asset);
    std::printf("dims %u %u %u source %s tool %s phi(0) %.4f\n", meta.dims.x, meta.dims.y,
                meta.dims.z, meta.sourceFile.c_str(), meta.toolVersion.c_str(),
                double(sampler.value(glm::dvec3(0.0))));
    return 0;
}
