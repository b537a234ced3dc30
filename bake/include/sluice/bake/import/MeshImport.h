// Mesh import through assimp (every format it reads) into one welded triangle soup.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "sluice/bake/import/Isolated.h"
#include "sluice/bake/jobs/PhaseLog.h"
#include "sluice/bake/import/TriangleSoup.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

struct ImportOptions {
    double scale = 1.0; ///< uniform scale applied after node transforms; finite, > 0
    /// Run assimp in a child process (runIsolated) so that a crash, an abort from one of its
    /// compiled-in asserts, or a hang on a hostile file becomes a MeshImport error.
    bool isolate = true;
    IsolationLimits limits; ///< time and memory for the isolated importer
    /// Where the import laps its phases (file checks, hash, assimp, diagnostics), if anywhere.
    PhaseLog* phases = nullptr;
    /// false: leave the self-intersection test out of the diagnostics (selfIntersecting is
    /// false until the caller runs selfIntersects, e.g. on another thread).
    bool selfIntersectionTest = true;
    /// Runs while the isolated child reads the file (right after the fork), so the caller's own
    /// work overlaps the import: opening a GL context, say. Without isolation it runs first.
    std::function<void()> whileImporting;
};

/// A mesh ready to bake, with what we learned about it.
struct ImportedMesh {
    TriangleSoup soup;
    format::MeshDiagnostics diagnostics;
    std::string sourceFile; ///< file name without folders
    std::string sourceHash; ///< XXH3-64 of the file bytes, 16 hex digits
};

/// Reads every mesh of the file with node transforms applied, welds identical positions, drops
/// nothing but reports degenerate triangles. Errors: Io, MeshImport (assimp's message),
/// EmptyMesh (no triangles: empty file, point cloud, lines), NonFinite (NaN/inf coordinates),
/// InvalidArgument (bad scale), SizeOverflow (over 20 M triangles or a 4 GiB file). `.vdb`
/// level sets go through importVdbLevelSet instead.
Result<ImportedMesh> importMesh(const std::filesystem::path& path, const ImportOptions& options);

/// Edge and degeneracy counts, closedness, and CGAL's self-intersection test.
format::MeshDiagnostics diagnose(const TriangleSoup& soup);

/// diagnose without the self-intersection test (selfIntersecting false): the cheap part.
format::MeshDiagnostics diagnoseTopology(const TriangleSoup& soup);

/// Whether two non-degenerate triangles intersect in more than the corners or the edge they
/// share (CGAL box intersection, then exact predicates): diagnose's selfIntersecting, which
/// costs far more than the rest of it.
bool selfIntersects(const TriangleSoup& soup);

} // namespace sluice::bake
