// Mesh import through assimp: every mesh of the file, node transforms applied, welded positions.
#include "sluice/bake/import/MeshImport.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <exception>
#include <mutex>
#include <string>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "sluice/format/support/Hash.h"

#include "import/OffCheck.h"
#include "import/PlyCheck.h"

namespace sluice::bake {

namespace {

/// Largest mesh we import [triangles, counting instances]: the CGAL reference needs roughly
/// 200 bytes per triangle, so this keeps a bake within a few GiB of memory.
constexpr std::uint64_t kMaxTriangles = 20'000'000;
/// Largest source file we hand to assimp [bytes].
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(4) << 30;

/// Exact-position key for welding; -0.0 and +0.0 weld together.
struct PositionKey {
    std::uint64_t bits[3];
    bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (std::uint64_t b : k.bits)
            h = (h ^ b) * 0xff51afd7ed558ccdull, h ^= h >> 32;
        return std::size_t(h);
    }
};
PositionKey keyOf(const glm::dvec3& p) {
    return {{std::bit_cast<std::uint64_t>(p.x + 0.0), std::bit_cast<std::uint64_t>(p.y + 0.0),
             std::bit_cast<std::uint64_t>(p.z + 0.0)}};
}

glm::dmat4 toGlm(const aiMatrix4x4& m) {
    glm::dmat4 out(1.0);
    for (unsigned r = 0; r < 4; ++r) // assimp is row-major, glm column-major
        for (unsigned c = 0; c < 4; ++c)
            out[c][r] = double(m[r][c]);
    return out;
}

void silenceAssimp() {
    // assimp logs through DefaultLogger; the NullLogger drops everything. Errors still come back
    // through Importer::GetErrorString, which is what we report.
    static std::once_flag once;
    std::call_once(once, [] { Assimp::DefaultLogger::set(nullptr); });
}

/// Collects the triangles of the scene in world space, welding identical positions.
class SoupBuilder {
public:
    SoupBuilder(const aiScene& scene, double scale) : m_scene(scene), m_scale(scale) {}

    /// Walks the node tree from the root, accumulating transforms in double precision. A mesh
    /// used by several nodes is instanced once per node.
    Result<void> addScene(const std::string& fileName) {
        if (!m_scene.mRootNode)
            return addAllMeshesUntransformed(fileName);
        std::vector<std::pair<const aiNode*, glm::dmat4>> stack{
            {m_scene.mRootNode, glm::dmat4(1.0)}};
        bool anyMeshUsed = false;
        while (!stack.empty()) {
            const auto [node, parent] = stack.back();
            stack.pop_back();
            const glm::dmat4 world = parent * toGlm(node->mTransformation);
            for (unsigned i = 0; i < node->mNumMeshes; ++i) {
                if (node->mMeshes[i] >= m_scene.mNumMeshes)
                    return fail(ErrorCode::MeshImport,
                                fileName + ": a node refers to a mesh that does not exist");
                anyMeshUsed = true;
                if (Result<void> r = addMesh(*m_scene.mMeshes[node->mMeshes[i]], world, fileName);
                    !r)
                    return r;
            }
            for (unsigned c = node->mNumChildren; c-- > 0;) // reversed so children pop in order
                if (node->mChildren[c])
                    stack.push_back({node->mChildren[c], world});
        }
        // Some loaders leave meshes out of the node tree; take them as they are then.
        return anyMeshUsed ? Result<void>{} : addAllMeshesUntransformed(fileName);
    }

    TriangleSoup take() { return std::move(m_soup); }

private:
    Result<void> addAllMeshesUntransformed(const std::string& fileName) {
        for (unsigned m = 0; m < m_scene.mNumMeshes; ++m)
            if (Result<void> r = addMesh(*m_scene.mMeshes[m], glm::dmat4(1.0), fileName); !r)
                return r;
        return {};
    }

    Result<void> addMesh(const aiMesh& mesh, const glm::dmat4& world, const std::string& fileName) {
        // Map each referenced vertex once: FBX and friends split vertices per face normal, so
        // many assimp vertices weld to one position.
        std::vector<std::uint32_t> welded(mesh.mNumVertices, kUnmapped);
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            if (face.mNumIndices != 3)
                continue; // points and lines; polygons were triangulated by aiProcess_Triangulate
            if (m_soup.triangles.size() >= kMaxTriangles)
                return fail(ErrorCode::SizeOverflow,
                            fileName + ": more than " + std::to_string(kMaxTriangles) +
                                " triangles; decimate the mesh before baking");
            glm::uvec3 tri;
            for (int c = 0; c < 3; ++c) {
                const unsigned v = face.mIndices[c];
                if (v >= mesh.mNumVertices)
                    return fail(ErrorCode::MeshImport,
                                fileName + ": a face refers to a vertex that does not exist");
                if (welded[v] == kUnmapped) {
                    const aiVector3D& p = mesh.mVertices[v];
                    const glm::dvec3 w =
                        glm::dvec3(world * glm::dvec4(double(p.x), double(p.y), double(p.z), 1.0)) *
                        m_scale;
                    if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z))
                        return fail(ErrorCode::NonFinite,
                                    fileName + ": vertex " + std::to_string(v) + " of mesh '" +
                                        mesh.mName.C_Str() +
                                        "' has a NaN or infinite coordinate; fix the mesh");
                    welded[v] = weld(w);
                }
                tri[c] = welded[v];
            }
            m_soup.triangles.push_back(tri);
        }
        return {};
    }

    std::uint32_t weld(const glm::dvec3& p) {
        const auto [it, inserted] =
            m_index.try_emplace(keyOf(p), std::uint32_t(m_soup.positions.size()));
        if (inserted)
            m_soup.positions.push_back(p);
        return it->second;
    }

    static constexpr std::uint32_t kUnmapped = ~std::uint32_t(0);
    const aiScene& m_scene;
    double m_scale;
    TriangleSoup m_soup;
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> m_index;
};

/// Whether assimp may read a file of extension `ext` (lower case, with its dot) as PLY: it
/// picks its loader by extension, and by content ("ply" first) only for extensions it does not
/// know, so those files may be PLY too (detail::checkPlyFile looks at the content).
bool mayBeReadAsPly(const std::string& ext) {
    return ext == ".ply" || !Assimp::Importer().IsExtensionSupported(ext);
}

/// Whether any mesh has a face of three or more corners, looking only through pointers that
/// are set (the scene is not validated yet).
bool hasSurfaceFaces(const aiScene& scene) {
    for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
        const aiMesh* mesh = scene.mMeshes ? scene.mMeshes[m] : nullptr;
        if (!mesh || !mesh->mFaces)
            continue;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f)
            if (mesh->mFaces[f].mNumIndices >= 3)
                return true;
    }
    return false;
}

/// Refuses a scale that is not finite and positive, and a path that is not a regular file of
/// 1 byte to 4 GiB; the file's size [bytes].
Result<std::uintmax_t> checkMeshFile(const std::filesystem::path& path, double scale,
                                     const std::string& shown) {
    if (!std::isfinite(scale) || !(scale > 0.0))
        return fail(ErrorCode::InvalidArgument,
                    "import scale must be finite and > 0, got " + std::to_string(scale));
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
        return fail(ErrorCode::Io, shown + ": no such file");
    if (!std::filesystem::is_regular_file(status))
        return fail(ErrorCode::Io, shown + ": not a regular file");
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (ec)
        return fail(ErrorCode::Io, shown + ": cannot read the file size (" + ec.message() + ")");
    if (bytes == 0)
        return fail(ErrorCode::EmptyMesh, shown + ": the file is empty");
    if (bytes > kMaxFileBytes)
        return fail(ErrorCode::SizeOverflow, shown + ": the file is larger than 4 GiB");
    return bytes;
}

/// The pre-flight checks of what assimp trusts in OFF and PLY files. checkPlyFile reads the
/// magic itself, and passes a file without it.
Result<void> preflightChecks(const std::filesystem::path& path, std::uintmax_t bytes,
                             const std::string& shown) {
    const std::string extension = detail::lowered(path.extension().string());
    if (extension == ".off")
        if (Result<void> r = detail::checkOffFile(path, bytes, shown); !r)
            return r;
    if (mayBeReadAsPly(extension))
        if (Result<void> r = detail::checkPlyFile(path, shown); !r)
            return r;
    return {};
}

/// The file's scene as `importer` reads it: refused when it has no surface, validated, then
/// triangulated.
Result<const aiScene*> readScene(Assimp::Importer& importer, const std::filesystem::path& path,
                                 const std::string& shown) {
    // Read without post-processing first: a point cloud or a file of lines is not corrupt,
    // it just has nothing to bake, and we say so before assimp's validation calls a mesh
    // without faces invalid.
    const aiScene* scene = importer.ReadFile(path.string(), 0);
    if (!scene) {
        const std::string why = importer.GetErrorString();
        return fail(ErrorCode::MeshImport,
                    shown + ": assimp cannot read it" + (why.empty() ? "" : " (" + why + ")"));
    }
    if (!hasSurfaceFaces(*scene))
        return fail(ErrorCode::EmptyMesh,
                    shown + ": no triangles (only points or lines, or no geometry at all)");
    // Validation must come before anything else touches the scene: Debian's assimp is
    // built with its internal asserts on, and its steps abort() on out-of-range indices.
    scene = importer.ApplyPostProcessing(aiProcess_ValidateDataStructure);
    if (!scene) {
        const std::string why = importer.GetErrorString();
        return fail(ErrorCode::MeshImport, shown + ": assimp read an invalid scene" +
                                               (why.empty() ? "" : " (" + why + ")"));
    }
    // Polygons become triangles; points and lines stay 1- and 2-index faces and are
    // skipped. No PreTransformVertices: we walk the node tree ourselves (instancing too).
    scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
    if (!scene)
        return fail(ErrorCode::MeshImport, shown + ": assimp cannot triangulate its polygons");
    return scene;
}

/// Everything assimp touches: the pre-flight checks (in the child too when isolated: they read
/// the whole file, and the parent has other work meanwhile), the scene, and its welded soup.
Result<TriangleSoup> readSoup(const std::filesystem::path& path, std::uintmax_t bytes,
                              const std::string& shown, double scale) {
    if (Result<void> r = preflightChecks(path, bytes, shown); !r)
        return r.error();
    silenceAssimp();
    Assimp::Importer importer;
    Result<const aiScene*> scene = readScene(importer, path, shown);
    if (!scene)
        return scene.error();
    SoupBuilder builder(**scene, scale);
    if (Result<void> r = builder.addScene(shown); !r)
        return r.error();
    return builder.take();
}

/// readSoup in an isolated child process when options.isolate (its time an overlapped phase),
/// else here; options.whileImporting runs meanwhile either way.
Result<TriangleSoup> readSoupAsAsked(const std::filesystem::path& path, std::uintmax_t bytes,
                                     const std::string& shown, const ImportOptions& options) {
    const auto read = [&] { return readSoup(path, bytes, shown, options.scale); };
    if (!options.isolate) {
        if (options.whileImporting)
            options.whileImporting();
        return read();
    }
    IsolationReport child;
    Result<TriangleSoup> soup =
        runIsolated(shown, options.limits, read, options.whileImporting, &child);
    if (options.phases)
        options.phases->addOverlapped("import: isolated child process (OFF/PLY checks, assimp)",
                                      child.wallSeconds, child.cpuSeconds);
    return soup;
}

Result<ImportedMesh> importChecked(const std::filesystem::path& path,
                                   const ImportOptions& options) {
    const std::string shown = path.string();
    Result<std::uintmax_t> bytes = checkMeshFile(path, options.scale, shown);
    if (!bytes)
        return bytes.error();
    lap(options.phases, "import: file checks");
    Result<std::string> hash = format::hashFileHex(path);
    if (!hash)
        return hash.error();
    lap(options.phases, "import: file hash");

    Result<TriangleSoup> soup = readSoupAsAsked(path, *bytes, shown, options);
    if (!soup)
        return soup.error();
    lap(options.phases,
        options.isolate ? "import: wait for the isolated child" : "import: checks and assimp");
    ImportedMesh mesh;
    mesh.soup = std::move(*soup);
    if (mesh.soup.triangles.empty())
        return fail(ErrorCode::EmptyMesh,
                    shown + ": no triangles (only points or lines, or no geometry at all)");
    mesh.diagnostics =
        options.selfIntersectionTest ? diagnose(mesh.soup) : diagnoseTopology(mesh.soup);
    mesh.sourceFile = path.filename().string();
    mesh.sourceHash = std::move(*hash);
    lap(options.phases, options.selfIntersectionTest
                            ? "mesh diagnostics"
                            : "mesh diagnostics: topology (self-intersection test later)");
    return mesh;
}

} // namespace

Result<ImportedMesh> importMesh(const std::filesystem::path& path, const ImportOptions& options) {
    // The module boundary: assimp (and allocation on hostile inputs) may throw.
    try {
        return importChecked(path, options);
    } catch (const std::bad_alloc&) {
        return fail(ErrorCode::SizeOverflow, path.string() + ": out of memory while importing");
    } catch (const std::exception& e) {
        return fail(ErrorCode::MeshImport, path.string() + ": import failed (" + e.what() + ")");
    } catch (...) {
        return fail(ErrorCode::MeshImport, path.string() + ": import failed (unknown exception)");
    }
}

} // namespace sluice::bake
