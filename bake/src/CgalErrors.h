// What the CGAL bakes throw, as errors naming the mesh (the dense and the sparse bake share it).
#pragma once

#include <exception>
#include <new>
#include <string>

#include "sluice/bake/MeshImport.h"
#include "sluice/format/Result.h"

namespace sluice::bake {

/// Runs `bake` (returning a Result) and turns what CGAL throws into errors: broken
/// preconditions (asserting builds) as Unsupported, allocation failures as SizeOverflow.
template <class Bake>
auto withCgalErrors(const ImportedMesh& mesh, Bake&& bake) -> decltype(bake()) {
    try {
        return bake();
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::SizeOverflow,
                    mesh.sourceFile + ": out of memory while baking; use a coarser grid");
    } catch (const std::exception& e) {
        return fail(ErrorCode::Unsupported, mesh.sourceFile +
                                                ": the CGAL reference failed on this mesh (" +
                                                e.what() + ")");
    }
}

} // namespace sluice::bake
