// libFuzzer target: mesh import (bake::importMesh) on untrusted file contents.
//
// The first byte picks the file extension (obj, off, ply, stl, fbx: assimp chooses its loader by
// extension first, then by content), the rest is the file. Import runs in this process
// (ImportOptions::isolate = false): the fork of the real tool would hide every crash from the
// fuzzer, and coverage with it. sluice-bake imports in a child process, so a crash, abort, hang
// or leak inside assimp is an error there, not a crash; here it is a finding to triage (fix our
// side, as for a header that makes assimp reserve absurd memory, or suppress a leak that only
// assimp makes: lsan-suppressions.txt). docs/reliability.md lists what was found.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "FuzzSupport.h"
#include "sluice/bake/import/MeshImport.h"

namespace {

using namespace sluice;
namespace fs = std::filesystem;

constexpr const char* kExtensions[] = {"obj", "off", "ply", "stl", "fbx"};
constexpr std::size_t kExtensionCount = sizeof(kExtensions) / sizeof(kExtensions[0]);

/// A private folder for this process's input files, on tmpfs where there is one.
const fs::path& workDir() {
    static const fs::path dir = [] {
        std::error_code ec;
        const fs::path base =
            fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
        fs::path d = base / ("sluice-fuzz-mesh-" + std::to_string(::getpid()));
        fs::create_directories(d, ec);
        if (ec)
            fuzz::violated("cannot create the fuzz work folder", d.c_str());
        return d;
    }();
    static const bool removedAtExit = [] {
        return std::atexit([] {
                   std::error_code ec;
                   fs::remove_all(workDir(), ec);
               }) == 0;
    }();
    (void)removedAtExit;
    return dir;
}

void checkAccepted(const bake::ImportedMesh& mesh) {
    const bake::TriangleSoup& soup = mesh.soup;
    SLUICE_FUZZ_CHECK(!soup.triangles.empty(), "an accepted mesh has triangles");
    for (const glm::dvec3& p : soup.positions)
        SLUICE_FUZZ_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
                          "positions finite");
    for (const glm::uvec3& t : soup.triangles)
        for (int c = 0; c < 3; ++c)
            SLUICE_FUZZ_CHECK(t[c] < soup.positions.size(), "indices inside the positions");
    SLUICE_FUZZ_CHECK(mesh.diagnostics.triangles == soup.triangles.size(), "diagnosed count");
    SLUICE_FUZZ_CHECK(mesh.diagnostics.degenerateTriangles <= soup.triangles.size(),
                      "degenerate count");
    SLUICE_FUZZ_CHECK(mesh.sourceHash.size() == 16, "source hash");
    const bake::Box box = soup.bounds();
    SLUICE_FUZZ_CHECK(!box.empty(), "bounds of a mesh with triangles");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1)
        return 0;
    const fs::path file =
        workDir() / (std::string("input.") + kExtensions[data[0] % kExtensionCount]);
    {
        std::FILE* out = std::fopen(file.c_str(), "wb");
        if (!out)
            fuzz::violated("cannot write the fuzz input file", file.c_str());
        if (size > 1 && std::fwrite(data + 1, 1, size - 1, out) != size - 1)
            fuzz::violated("cannot write the fuzz input file", file.c_str());
        std::fclose(out);
    }
    bake::ImportOptions options;
    options.isolate = false;
    Result<bake::ImportedMesh> mesh = bake::importMesh(file, options);
    if (mesh) {
        checkAccepted(*mesh);
    } else {
        SLUICE_FUZZ_CHECK(mesh.error().detail.find(file.filename().string()) != std::string::npos,
                          "messages name the file");
    }
    std::error_code ec;
    fs::remove(file, ec);
    return 0;
}
