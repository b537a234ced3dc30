// What the libraries under a bake throw, as errors naming the mesh (the CGAL and GPU bakes,
// dense and sparse, share it).
#pragma once

#include <exception>
#include <new>
#include <string>
#include <utility>

#include "sluice/bake/import/MeshImport.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// Runs `bake` (returning a Result) and turns what it throws into errors naming the mesh:
/// allocation failures as SizeOverflow, anything else (CGAL's broken preconditions in
/// asserting builds, OpenVDB's exceptions) as Unsupported, "<mesh>: <failure> (<what>)".
template <class Bake>
auto withBakeErrors(const ImportedMesh& mesh, const char* failure, Bake&& bake)
    -> decltype(bake()) {
    try {
        return bake();
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": out of memory while baking; use a coarser grid");
    } catch (const std::exception& e) {
        return fail(ErrorCode::Unsupported,
                    mesh.sourceFile + ": " + failure + " (" + e.what() + ")");
    }
}

/// withBakeErrors for the CGAL bakes.
template <class Bake> auto withCgalErrors(const ImportedMesh& mesh, Bake&& bake) {
    return withBakeErrors(mesh, "the CGAL reference failed on this mesh", std::forward<Bake>(bake));
}

/// withBakeErrors for the GPU bakes (their CPU side: the soup's orientation, the BVH, OpenVDB).
template <class Bake> auto withGpuBakeErrors(const ImportedMesh& mesh, Bake&& bake) {
    return withBakeErrors(mesh, "preparing this mesh for the GPU bake failed",
                          std::forward<Bake>(bake));
}

} // namespace sluice::bake
