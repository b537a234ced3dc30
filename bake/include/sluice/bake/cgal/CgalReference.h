// The exact CPU reference: signed distance to a triangle soup with CGAL, in double precision.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/bake/Grid.h"
#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/jobs/Progress.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Result.h"

namespace sluice::bake {

/// What the user asked for: auto picks parity for closed, non-self-intersecting meshes and the
/// generalized winding number otherwise.
enum class SignMode { Auto, Parity, Winding };

/// The sign method a bake uses for `mode` on a mesh with these diagnostics: parity when asked,
/// or under Auto for a closed mesh that does not intersect itself; the winding number otherwise.
/// Error InvalidArgument when parity is forced on a mesh that is not closed.
Result<format::SignMethod> chooseSignMethod(const format::MeshDiagnostics& diagnostics,
                                            SignMode mode);

/// Parses "auto" | "parity" | "winding".
Result<SignMode> parseSignMode(const std::string& text);
const char* signModeName(SignMode mode);

/// Exact unsigned distance (CGAL AABB tree over the soup) with a sign from ray parity
/// (Side_of_triangle_mesh, closed meshes only) or the generalized winding number (any soup).
/// Thread-safe for queries once built.
class CgalReference {
public:
    /// Errors: EmptyMesh (no non-degenerate triangle), InvalidArgument (Parity forced on a mesh
    /// that is not closed).
    static Result<CgalReference> build(const TriangleSoup& soup,
                                       const format::MeshDiagnostics& diagnostics, SignMode mode);
    CgalReference(CgalReference&&) noexcept;
    CgalReference& operator=(CgalReference&&) noexcept;
    ~CgalReference();

    /// The sign method in use.
    format::SignMethod signMethod() const;
    /// Why parity (asked for, or chosen by auto) fell back to the winding number because no
    /// closed polygon mesh could be made of the soup; empty when it did not.
    const std::string& signFallbackReason() const;

    /// Exact |distance| from p to the nearest triangle [world units].
    double unsignedDistance(const glm::dvec3& p) const;
    /// Generalized winding number at p (Jacobson et al. 2013), for any soup.
    double windingNumber(const glm::dvec3& p) const;
    /// Signed distance, negative inside, with the chosen sign method.
    double signedDistance(const glm::dvec3& p) const;

    /// signedDistance at many points, on all cores (TBB), reporting to `progress` if given.
    std::vector<double> signedDistances(std::span<const glm::dvec3> points,
                                        Progress* progress = nullptr) const;

private:
    struct Impl;
    explicit CgalReference(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

struct BakeSettings {
    GridOptions grid;
    SignMode sign = SignMode::Auto;
    format::Storage storage = format::Storage::F32;
    double scale = 1.0; ///< recorded in the asset; the mesh is already scaled
};

/// Metadata of a bake by `backend` ("cgal", "gpu"): grid, storage, sign convention, source file
/// and hash, bake parameters, tool version, diagnostics, and the exact mass properties of a
/// closed mesh (meshMass; empty for an open one). Distances are the caller's.
format::ColliderMeta bakeProvenance(const ImportedMesh& mesh, const GridSpec& grid,
                                    const BakeSettings& settings, const char* backend,
                                    format::SignMethod signUsed);

} // namespace sluice::bake
