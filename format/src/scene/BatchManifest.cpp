// Batch manifests: strict JSON, every field checked and named by its JSON path (Json.h's reads).
#include "sluice/format/scene/BatchManifest.h"

#include <cmath>
#include <fstream>
#include <new>
#include <set>

#include "sluice/format/asset/AssetHeader.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/Suggest.h"
#include "support/Json.h"

namespace sluice::format {
namespace {

namespace fs = std::filesystem;
namespace rj = detail::rj;
using detail::throwAt;

constexpr detail::JsonFileKind kManifestKind{"the manifest", "the manifest", "manifest limit",
                                             kMaxBatchManifestBytes};

/// A number field; a number written as a string is named as such ("got the string \"40\"").
const rj::Value& numberValue(const rj::Value& value, const std::string& path) {
    if (value.IsString())
        throwAt(ErrorCode::BadMetadata, path,
                "expected a number, got the string \"" +
                    detail::displayKey({value.GetString(), value.GetStringLength()}) + "\"");
    return value;
}

/// A finite number > 0, or >= 0 with `allowZero` (as the bake flags require).
double positiveNumber(const rj::Value& value, const std::string& path, bool allowZero) {
    const double number = detail::readNumber(numberValue(value, path), path);
    if (allowZero ? number < 0.0 : number <= 0.0)
        throwAt(ErrorCode::InvalidArgument, path,
                detail::formatNumber(number) + " is out of range: expected a number " +
                    (allowZero ? ">= 0" : "> 0"));
    return number;
}

/// One of `names`; an unknown one suggests the closest and lists them all.
std::string oneOf(const rj::Value& value, const std::string& path, std::string_view what,
                  const std::vector<std::string>& names) {
    const std::string text = detail::readString(value, path);
    for (const std::string& name : names)
        if (text == name)
            return text;
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i)
        list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    throwAt(ErrorCode::InvalidArgument, path,
            "unknown " + std::string(what) + " \"" + detail::displayKey(text) + "\"" +
                didYouMean(text, names, '"') + "; expected " + list);
}

/// A path field: a non-empty string.
std::string pathString(const rj::Value& value, const std::string& path) {
    std::string text = detail::readString(value, path);
    if (text.empty())
        throwAt(ErrorCode::InvalidArgument, path, "expected a file name, got an empty string");
    return text;
}

// "volumeMaps": at most kMaxVolumeMaps supports, each a number > 0, none given twice.
std::vector<double> readVolumeMaps(const rj::Value& value, const std::string& at) {
    const rj::Value& list = detail::requireArray(value, at);
    if (list.Size() > kMaxVolumeMaps)
        throwAt(ErrorCode::InvalidArgument, at,
                std::to_string(list.Size()) + " volume maps; at most " +
                    std::to_string(kMaxVolumeMaps));
    std::vector<double> supports;
    for (rj::SizeType n = 0; n < list.Size(); ++n) {
        const double support = positiveNumber(list[n], detail::joinIndex(at, n), false);
        for (double other : supports)
            if (std::abs(other - support) <= kVolumeMapSupportTolerance * support)
                throwAt(ErrorCode::InvalidArgument, detail::joinIndex(at, n),
                        detail::formatNumber(support) + " is given twice");
        supports.push_back(support);
    }
    return supports;
}

BatchEntry readEntry(const rj::Value& value, const std::string& path, const fs::path& folder) {
    const detail::JsonObject object(value, path,
                                    {"mesh", "output", "resolution", "voxelSize", "padding", "sign",
                                     "storage", "scale", "backend", "sparse", "band", "forSpacing",
                                     "forKernelRadius", "volumeMaps"});
    BatchEntry entry;
    entry.mesh = pathString(object.require("mesh"), object.pathOf("mesh"));
    entry.output = pathString(object.require("output"), object.pathOf("output"));
    entry.meshPath = folder / entry.mesh;
    entry.outputPath = folder / entry.output;
    if (const rj::Value* v = object.find("resolution"))
        entry.resolution = std::uint32_t(detail::readInteger(
            numberValue(*v, object.pathOf("resolution")), object.pathOf("resolution"),
            kMinBakeResolution, kMaxBakeResolution));
    if (const rj::Value* v = object.find("voxelSize")) {
        if (object.has("resolution"))
            throwAt(ErrorCode::InvalidArgument, path,
                    "give \"resolution\" or \"voxelSize\", not both");
        entry.voxelSize = positiveNumber(*v, object.pathOf("voxelSize"), false);
    }
    if (const rj::Value* v = object.find("padding"))
        entry.padding = positiveNumber(*v, object.pathOf("padding"), true);
    if (const rj::Value* v = object.find("scale"))
        entry.scale = positiveNumber(*v, object.pathOf("scale"), false);
    if (const rj::Value* v = object.find("sign"))
        entry.sign = oneOf(*v, object.pathOf("sign"), "sign method", {"auto", "parity", "winding"});
    if (const rj::Value* v = object.find("storage"))
        entry.storage = oneOf(*v, object.pathOf("storage"), "storage", {"f32", "f16"});
    if (const rj::Value* v = object.find("backend"))
        entry.backend = oneOf(*v, object.pathOf("backend"), "backend", {"auto", "gpu", "cgal"});
    if (const rj::Value* v = object.find("sparse")) {
        if (!v->IsBool())
            throwAt(ErrorCode::BadMetadata, object.pathOf("sparse"),
                    "expected true or false, got " + detail::describe(*v));
        entry.sparse = v->GetBool();
    }
    if (const rj::Value* v = object.find("band")) {
        if (!entry.sparse)
            throwAt(ErrorCode::InvalidArgument, object.pathOf("band"),
                    "a band is for sparse assets: add \"sparse\": true");
        entry.band =
            detail::readNumber(numberValue(*v, object.pathOf("band")), object.pathOf("band"));
        if (entry.band < 1.0 || entry.band > 64.0)
            throwAt(ErrorCode::InvalidArgument, object.pathOf("band"),
                    detail::formatNumber(entry.band) + " is out of range: expected 1 to 64 voxels");
    }
    if (const rj::Value* v = object.find("forSpacing")) {
        if (!entry.sparse)
            throwAt(ErrorCode::InvalidArgument, object.pathOf("forSpacing"),
                    "a band is for sparse assets: add \"sparse\": true");
        if (object.has("band"))
            throwAt(ErrorCode::InvalidArgument, path, "give \"band\" or \"forSpacing\", not both");
        entry.forSpacing = positiveNumber(*v, object.pathOf("forSpacing"), false);
    }
    if (const rj::Value* v = object.find("forKernelRadius")) {
        if (!object.has("forSpacing"))
            throwAt(ErrorCode::InvalidArgument, object.pathOf("forKernelRadius"),
                    "a kernel radius goes with \"forSpacing\"");
        entry.forKernelRadius = positiveNumber(*v, object.pathOf("forKernelRadius"), false);
    }
    if (const rj::Value* v = object.find("volumeMaps"))
        entry.volumeMaps = readVolumeMaps(*v, object.pathOf("volumeMaps"));
    // As `bake --sparse` refuses it: a sparse asset stores f32.
    if (entry.sparse && entry.storage == "f16")
        throwAt(ErrorCode::InvalidArgument, object.pathOf("storage"),
                "sparse assets store f32 values; leave out \"storage\": \"f16\"");
    return entry;
}

BatchManifest readManifest(const rj::Value& root, const fs::path& file) {
    const detail::JsonObject object(root, "", {"colliders"});
    const std::string path = object.pathOf("colliders");
    const rj::Value& colliders = detail::requireArray(object.require("colliders"), path);
    BatchManifest manifest;
    manifest.path = file;
    const fs::path folder = file.parent_path();
    std::set<fs::path> outputs;
    for (rj::SizeType n = 0; n < colliders.Size(); ++n) {
        const std::string where = detail::joinIndex(path, n);
        BatchEntry entry = readEntry(colliders[n], where, folder);
        // Two entries writing one file would race under --jobs and overwrite each other anyway.
        if (!outputs.insert(entry.outputPath.lexically_normal()).second)
            throwAt(ErrorCode::InvalidArgument, detail::joinKey(where, "output"),
                    "\"" + entry.output + "\" is written by an earlier entry too");
        manifest.colliders.push_back(std::move(entry));
    }
    return manifest;
}

} // namespace

Result<BatchManifest> parseBatchManifest(std::string_view json, const fs::path& file) {
    return detail::parseJsonText<BatchManifest>(
        json, file, kManifestKind,
        [&](const rj::Document& doc) { return readManifest(doc, file); });
}

Result<BatchManifest> readBatchManifest(const fs::path& file) {
    return detail::readJsonFile<BatchManifest>(
        file, kManifestKind, [&](const rj::Document& doc) { return readManifest(doc, file); });
}

} // namespace sluice::format
