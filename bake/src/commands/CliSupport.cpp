// Helpers shared by the sluice-bake subcommands: errors, loading by file type, names and JSON.
#include "commands/CliSupport.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <sys/resource.h>

#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/interop/NanoVdbIO.h"
#include "sluice/bake/interop/VdbIO.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::bake::cli {

std::string toolVersion() {
    return std::string("sluice-bake ") + SLUICE_VERSION;
}

int reportError(std::string_view command, const std::string& what, const Error& error) {
    std::cerr << "sluice-bake " << command << ": " << what << ": " << error.message() << '\n';
    return exitCodeFor(error);
}

int reportFileError(std::string_view command, const std::string& what,
                    const std::filesystem::path& path, const Error& error) {
    const bool named = error.detail.find(path.string()) != std::string::npos;
    return reportError(command, named ? what : what + " '" + path.string() + "'", error);
}

int reportBadInput(std::string_view command, const std::string& message) {
    std::cerr << "sluice-bake " << command << ": " << message << '\n';
    return kExitBadInput;
}

bool hasExtension(const std::filesystem::path& path, std::string_view ext) {
    std::string actual = path.extension().string();
    std::transform(actual.begin(), actual.end(), actual.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return actual == ext;
}

bool isLevelSetFile(const std::filesystem::path& path) {
    return hasExtension(path, ".vdb") || hasExtension(path, ".nvdb");
}

Result<ImportedMesh> loadMesh(const std::filesystem::path& path, double scale) {
    ImportOptions options;
    options.scale = scale;
    return loadMesh(path, options);
}

Result<ImportedMesh> loadMesh(const std::filesystem::path& path, const ImportOptions& options) {
    if (!isLevelSetFile(path))
        return importMesh(path, options);
    Result<ImportedMesh> mesh = hasExtension(path, ".vdb")
                                    ? importVdbLevelSet(path, options.scale)
                                    : importNvdbLevelSet(path, options.scale);
    if (options.whileImporting)
        options.whileImporting();
    return mesh;
}

Result<format::ColliderAsset> loadAsset(const std::filesystem::path& path) {
    if (hasExtension(path, ".vdb"))
        return readVdbDense(path);
    return format::readAsset(path);
}

Result<void> prepareOutputPath(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (path.filename().empty() || fs::is_directory(path, ec))
        return fail(ErrorCode::InvalidArgument, "'" + path.string() + "' is a folder, not a file");
    const fs::path folder = path.parent_path();
    if (folder.empty() || fs::is_directory(folder, ec))
        return {};
    fs::create_directories(folder, ec);
    if (ec || !fs::is_directory(folder))
        return fail(ErrorCode::Io, "cannot create the folder '" + folder.string() + "' for '" +
                                       path.string() +
                                       "': " + (ec ? ec.message() : std::string("not a folder")));
    return {};
}

std::string describeMesh(const format::MeshDiagnostics& mesh) {
    std::string text = plural(mesh.triangles, "triangle") + ", " +
                       plural(mesh.vertices, "vertex", "vertices") + ", ";
    text += mesh.closed ? "closed" : "open";
    text += mesh.selfIntersecting ? ", self-intersecting" : ", not self-intersecting";
    text += ", " + std::to_string(mesh.degenerateTriangles) + " degenerate, " +
            plural(mesh.boundaryEdges, "boundary edge") + ", " +
            plural(mesh.nonManifoldEdges, "non-manifold edge");
    return text;
}

std::string describeDims(const glm::uvec3& dims) {
    return std::to_string(dims.x) + " x " + std::to_string(dims.y) + " x " +
           std::to_string(dims.z) + " = " +
           std::to_string(std::uint64_t(dims.x) * dims.y * dims.z) + " points";
}

std::string num(double value, int digits) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    return text;
}

nlohmann::ordered_json toJson(const format::MeshDiagnostics& mesh) {
    return {{"triangles", mesh.triangles},
            {"vertices", mesh.vertices},
            {"degenerateTriangles", mesh.degenerateTriangles},
            {"boundaryEdges", mesh.boundaryEdges},
            {"nonManifoldEdges", mesh.nonManifoldEdges},
            {"closed", mesh.closed},
            {"selfIntersecting", mesh.selfIntersecting}};
}

nlohmann::ordered_json toJson(const format::ValidationFigures& figures) {
    if (!figures.known)
        return {{"known", false},
                {"pointsChecked", nullptr},
                {"maxError", nullptr},
                {"meanError", nullptr},
                {"rmsError", nullptr},
                {"signMismatches", nullptr},
                {"eikonalMedian", nullptr},
                {"eikonalP99", nullptr},
                {"eikonalOutsideShare", nullptr}};
    return {{"known", figures.known},
            {"pointsChecked", figures.pointsChecked},
            {"maxError", figures.maxError},
            {"meanError", figures.meanError},
            {"rmsError", figures.rmsError},
            {"signMismatches", figures.signMismatches},
            {"eikonalMedian", figures.eikonalMedian},
            {"eikonalP99", figures.eikonalP99},
            {"eikonalOutsideShare", figures.eikonalOutsideShare}};
}

nlohmann::ordered_json toJson(const std::optional<format::MassProperties>& mass) {
    if (!mass)
        return nullptr;
    nlohmann::ordered_json inertia = nlohmann::ordered_json::array();
    for (int row = 0; row < 3; ++row)
        inertia.push_back({mass->inertia[0][row], mass->inertia[1][row], mass->inertia[2][row]});
    const glm::dvec3& c = mass->centerOfMass;
    return {{"volume", mass->volume}, {"centerOfMass", {c.x, c.y, c.z}}, {"inertia", inertia}};
}

nlohmann::ordered_json toJson(const format::ColliderMeta& meta) {
    const format::BakeParams& bake = meta.bake;
    return {{"dims", {meta.dims.x, meta.dims.y, meta.dims.z}},
            {"pointCount", std::uint64_t(meta.dims.x) * meta.dims.y * meta.dims.z},
            {"origin", {meta.origin.x, meta.origin.y, meta.origin.z}},
            {"voxelSize", meta.voxelSize},
            {"storage", storageName(meta.storage)},
            {"signConvention", meta.signConvention},
            {"sourceFile", meta.sourceFile},
            {"sourceHash", meta.sourceHash},
            {"toolVersion", meta.toolVersion},
            {"bake",
             {{"backend", bake.backend},
              {"resolution", bake.resolution},
              {"padding", bake.padding},
              {"signMode", bake.signMode},
              {"signUsed", signMethodName(bake.signUsed)},
              {"scale", bake.scale}}},
            {"mesh", toJson(meta.mesh)},
            {"validation", toJson(meta.validation)},
            {"quantizationError", meta.quantizationError},
            {"massProperties", toJson(meta.meshMass)},
            {"layout", layoutName(meta.layout)},
            {"bandWidth", meta.bandWidth}};
}

std::uint64_t peakRssBytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0)
        return 0;
    return std::uint64_t(usage.ru_maxrss) * 1024; // Linux reports kilobytes
}

} // namespace sluice::bake::cli
