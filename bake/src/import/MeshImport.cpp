// Mesh import through assimp: every mesh of the file, node transforms applied, welded positions.
#include "sluice/bake/import/MeshImport.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <exception>
#include <fstream>
#include <mutex>
#include <sstream>
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

#include "sluice/format/Hash.h"

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

/// Checks an OFF file against its header before assimp reads it.
///
/// First the declared counts: assimp allocates for them before reading (a 12-line OFF file
/// asking for 353 billion vertices takes all memory), so they must fit in the file, each
/// vertex needing at least 6 bytes ("0 0 0\n") and each face 8 ("3 0 1 2\n"). Then the body:
/// the vertex lines (three numbers each, and whatever colour or normal follows) and every face
/// line, whose corner count must be followed on the same line by that many vertex indices, each
/// below the vertex count. Debian's assimp 5.2.5 reads a face's corners past the end of its
/// buffer when the file does not hold them (a SEGV; found by tests/fuzz, and contained by the
/// isolated import, but a user deserves the line number). Files with the header's counts on
/// the first line and '#' comments are read as assimp does; binary OFF is left to assimp.
Result<void> checkOffFile(const std::filesystem::path& path, std::uintmax_t fileBytes,
                          const std::string& shown) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    std::size_t lineNumber = 0;
    // The next line that is not blank and not a comment, without its comment.
    auto nextLine = [&](std::string& out) {
        while (std::getline(in, line)) {
            ++lineNumber;
            const std::size_t hash = line.find('#');
            if (hash != std::string::npos)
                line.resize(hash);
            if (line.find_first_not_of(" \t\r\f\v") != std::string::npos) {
                out = line;
                return true;
            }
        }
        return false;
    };
    std::string text;
    if (!nextLine(text))
        return {};
    std::istringstream first(text);
    std::string magic;
    first >> magic;
    if (magic.size() < 3 || magic.compare(magic.size() - 3, 3, "OFF") != 0 ||
        magic.find("BINARY") != std::string::npos)
        return {}; // not OFF text: assimp says what it is
    // The counts follow the magic on its line, or stand on the next one.
    double vertexCount = 0, faceCount = 0;
    std::istringstream nextCounts;
    std::istream* counts = &first;
    bool vertexCountRead = bool(first >> vertexCount);
    if (!vertexCountRead) {
        if (!nextLine(text))
            return fail(ErrorCode::MeshImport, shown + ": the OFF header has no counts");
        nextCounts.str(text);
        counts = &nextCounts;
        vertexCountRead = bool(nextCounts >> vertexCount);
    }
    const bool faceCountRead = vertexCountRead && bool(*counts >> faceCount);
    // The size test comes first, and judges a vertex count without a face count after it (found
    // by tests/fuzz: "4000000000# big" still makes assimp reserve for the vertices).
    if (vertexCountRead) {
        const double faces = faceCountRead ? faceCount : 0.0;
        if (vertexCount * 6 + faces * 8 > double(fileBytes))
            return fail(ErrorCode::MeshImport,
                        shown + ": " +
                            detail::declaresMoreThanTheFileHolds(vertexCount, faces, fileBytes));
    }
    if (!faceCountRead)
        return fail(ErrorCode::MeshImport, shown + ": line " + std::to_string(lineNumber) +
                                               ": the OFF counts cannot be read");
    if (!(vertexCount >= 0 && faceCount >= 0 && vertexCount < 4.3e9 && faceCount < 4.3e9))
        return fail(ErrorCode::MeshImport, shown + ": the OFF counts are out of range");
    const auto vertices = std::uint64_t(vertexCount), faces = std::uint64_t(faceCount);
    for (std::uint64_t v = 0; v < vertices; ++v) {
        if (!nextLine(text))
            return fail(ErrorCode::MeshImport,
                        shown + ": the file ends after " + std::to_string(v) + " of its " +
                            std::to_string(vertices) + " vertices");
        std::istringstream numbers(text);
        double x, y, z;
        if (!(numbers >> x >> y >> z))
            return fail(ErrorCode::MeshImport, shown + ": line " + std::to_string(lineNumber) +
                                                   ": a vertex needs three numbers");
    }
    for (std::uint64_t f = 0; f < faces; ++f) {
        if (!nextLine(text))
            return fail(ErrorCode::MeshImport,
                        shown + ": the file ends after " + std::to_string(f) + " of its " +
                            std::to_string(faces) + " faces");
        std::istringstream numbers(text);
        long long corners = -1;
        if (!(numbers >> corners) || corners < 1)
            return fail(ErrorCode::MeshImport, shown + ": line " + std::to_string(lineNumber) +
                                                   ": a face must start with its corner count");
        for (long long c = 0; c < corners; ++c) {
            long long index = -1;
            if (!(numbers >> index))
                return fail(ErrorCode::MeshImport,
                            shown + ": line " + std::to_string(lineNumber) + ": the face has " +
                                std::to_string(c) + " of its " + std::to_string(corners) +
                                " vertex indices");
            if (index < 0 || std::uint64_t(index) >= vertices)
                return fail(ErrorCode::MeshImport,
                            shown + ": line " + std::to_string(lineNumber) + ": vertex index " +
                                std::to_string(index) + " is not below the vertex count " +
                                std::to_string(vertices));
        }
    }
    return {};
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

Result<ImportedMesh> importChecked(const std::filesystem::path& path,
                                   const ImportOptions& options) {
    const std::string fileName = path.filename().string();
    const std::string shown = path.string();
    const auto lap = [&](std::string_view name) { bake::lap(options.phases, name); };
    if (!std::isfinite(options.scale) || !(options.scale > 0.0))
        return fail(ErrorCode::InvalidArgument,
                    "import scale must be finite and > 0, got " + std::to_string(options.scale));

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

    lap("import: file checks");
    Result<std::string> hash = format::hashFileHex(path);
    if (!hash)
        return hash.error();
    lap("import: file hash");

    const auto readSoup = [&]() -> Result<TriangleSoup> {
        // Pre-flight checks of what assimp trusts in OFF and PLY files, in the child too: they
        // read the whole file, and the parent has other work meanwhile. checkPlyFile reads the
        // magic itself, and passes a file without it.
        const std::string extension = detail::lowered(path.extension().string());
        if (extension == ".off")
            if (Result<void> r = checkOffFile(path, bytes, shown); !r)
                return r.error();
        if (mayBeReadAsPly(extension))
            if (Result<void> r = detail::checkPlyFile(path, shown); !r)
                return r.error();
        silenceAssimp();
        Assimp::Importer importer;
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

        SoupBuilder builder(*scene, options.scale);
        if (Result<void> r = builder.addScene(shown); !r)
            return r.error();
        return builder.take();
    };
    // Everything assimp touches runs in the child when isolated; the rest runs here.
    IsolationReport child;
    Result<TriangleSoup> soup = Error{ErrorCode::MeshImport, {}};
    if (options.isolate) {
        soup = runIsolated(shown, options.limits, readSoup, options.whileImporting, &child);
    } else {
        if (options.whileImporting)
            options.whileImporting();
        soup = readSoup();
    }
    if (options.isolate && options.phases)
        options.phases->addOverlapped("import: isolated child process (OFF/PLY checks, assimp)",
                                      child.wallSeconds, child.cpuSeconds);
    if (!soup)
        return soup.error();
    lap(options.isolate ? "import: wait for the isolated child" : "import: checks and assimp");
    ImportedMesh mesh;
    mesh.soup = std::move(*soup);
    if (mesh.soup.triangles.empty())
        return fail(ErrorCode::EmptyMesh,
                    shown + ": no triangles (only points or lines, or no geometry at all)");
    mesh.diagnostics =
        options.selfIntersectionTest ? diagnose(mesh.soup) : diagnoseTopology(mesh.soup);
    mesh.sourceFile = fileName;
    mesh.sourceHash = std::move(*hash);
    lap(options.selfIntersectionTest ? "mesh diagnostics"
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
