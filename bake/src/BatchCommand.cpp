// `sluice-bake batch`: bakes every collider a JSON manifest lists, skipping those up to date.
//
// Manifest (paths relative to the manifest's folder; every field but mesh and output optional,
// with the defaults of `bake`):
//   { "colliders": [ { "mesh": "meshes/rock.obj", "output": "rock.slc", "resolution": 64,
//                      "voxelSize": 0, "padding": 3, "sign": "auto", "storage": "f32",
//                      "scale": 1, "backend": "cgal" } ] }
// An output is up to date when it exists, is no older than its mesh, and records the same tool
// version and bake settings as its entry asks for; --force bakes everything. --depfile writes a
// Makefile-syntax rule per output (output: mesh manifest) for build systems (Ninja's depfile).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "CliSupport.h"
#include "sluice/bake/Cli.h"
#include "sluice/format/AssetIO.h"
#include "sluice/format/AtomicFile.h"

namespace sluice::bake::cli {
namespace {

namespace fs = std::filesystem;

struct BatchArgs {
    std::string manifest;
    std::string depfile;
    bool force = false;
    bool quiet = false;
};

/// One manifest entry, paths resolved against the manifest's folder.
Result<BakeArgs> parseEntry(const nlohmann::json& entry, const fs::path& folder, std::size_t n) {
    const std::string where = "colliders[" + std::to_string(n) + "]";
    if (!entry.is_object() || !entry.contains("mesh") || !entry["mesh"].is_string() ||
        !entry.contains("output") || !entry["output"].is_string())
        return fail(ErrorCode::InvalidArgument,
                    where + " needs string fields \"mesh\" and \"output\"");
    BakeArgs args;
    args.mesh = (folder / entry["mesh"].get<std::string>()).string();
    args.output = (folder / entry["output"].get<std::string>()).string();
    try {
        args.resolution = entry.value("resolution", args.resolution);
        args.voxelSize = entry.value("voxelSize", args.voxelSize);
        args.padding = entry.value("padding", args.padding);
        args.sign = entry.value("sign", args.sign);
        args.storage = entry.value("storage", args.storage);
        args.scale = entry.value("scale", args.scale);
        args.backend = entry.value("backend", args.backend);
    } catch (const nlohmann::json::exception& e) {
        return fail(ErrorCode::InvalidArgument, where + ": " + e.what());
    }
    if (args.resolution < 1 || args.resolution > 4096)
        return fail(ErrorCode::InvalidArgument, where + ": resolution must be 1..4096");
    return args;
}

/// Whether `args.output` already holds what baking `args` would write.
bool upToDate(const BakeArgs& args) {
    std::error_code ec;
    const auto outputTime = fs::last_write_time(args.output, ec);
    if (ec)
        return false;
    const auto meshTime = fs::last_write_time(args.mesh, ec);
    if (ec || outputTime < meshTime)
        return false;
    Result<format::ColliderAsset> asset = format::readAsset(args.output);
    if (!asset)
        return false;
    const format::ColliderMeta& meta = asset->meta;
    const bool byVoxelSize = args.voxelSize > 0.0;
    return meta.toolVersion == toolVersion() && meta.bake.backend == args.backend &&
           meta.bake.resolution == (byVoxelSize ? 0u : args.resolution) &&
           (!byVoxelSize || meta.voxelSize == args.voxelSize) &&
           meta.bake.padding == args.padding && meta.bake.signMode == args.sign &&
           meta.bake.scale == args.scale && storageName(meta.storage) == args.storage &&
           meta.sourceFile == fs::path(args.mesh).filename().string();
}

/// A path in a Makefile rule: spaces, '#' and '$' escaped.
std::string makePath(const std::string& path) {
    std::string out;
    for (char c : path) {
        if (c == ' ' || c == '#')
            out += '\\';
        if (c == '$')
            out += '$';
        out += c;
    }
    return out;
}

int runBatch(const BatchArgs& args) {
    constexpr std::string_view cmd = "batch";
    std::ifstream in(args.manifest);
    if (!in)
        return reportBadInput(cmd, "cannot read manifest '" + args.manifest + "'");
    nlohmann::json manifest;
    try {
        manifest = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        return reportBadInput(cmd, "manifest '" + args.manifest + "' is not JSON: " + e.what());
    }
    if (!manifest.is_object() || !manifest.contains("colliders") ||
        !manifest["colliders"].is_array())
        return reportBadInput(cmd, "manifest '" + args.manifest +
                                       "' needs an array \"colliders\" of {mesh, output, ...}");
    const fs::path folder = fs::path(args.manifest).parent_path();
    std::vector<BakeArgs> entries;
    for (std::size_t n = 0; n < manifest["colliders"].size(); ++n) {
        Result<BakeArgs> entry = parseEntry(manifest["colliders"][n], folder, n);
        if (!entry)
            return reportBadInput(cmd, "manifest '" + args.manifest + "': " + entry.error().detail);
        entry->quiet = true;
        entries.push_back(*entry);
    }

    int result = kExitOk;
    std::size_t baked = 0, skipped = 0, failed = 0;
    for (const BakeArgs& entry : entries) {
        if (!args.force && upToDate(entry)) {
            ++skipped;
            if (!args.quiet)
                std::cout << "up to date " << entry.output << '\n';
            continue;
        }
        const int code = runBake(entry);
        if (code != kExitOk) {
            ++failed;
            if (result == kExitOk)
                result = code;
            continue;
        }
        ++baked;
        if (!args.quiet)
            std::cout << "baked      " << entry.output << '\n';
    }
    if (!args.depfile.empty()) {
        std::string rules;
        for (const BakeArgs& entry : entries)
            rules += makePath(entry.output) + ": " + makePath(entry.mesh) + " " +
                     makePath(args.manifest) + "\n";
        const auto* bytes = reinterpret_cast<const std::byte*>(rules.data());
        if (Result<void> written = format::writeFileAtomic(args.depfile, {bytes, rules.size()});
            !written)
            return reportFileError(cmd, "cannot write", args.depfile, written.error());
    }
    if (!args.quiet)
        std::cout << baked << " baked, " << skipped << " up to date, " << failed << " failed\n";
    return result;
}

} // namespace

Command addBatchCommand(CLI::App& parent) {
    auto args = std::make_shared<BatchArgs>();
    CLI::App* app = parent.add_subcommand(
        "batch", "Bake every collider a JSON manifest lists ({\"colliders\": [{\"mesh\", "
                 "\"output\", and optionally \"resolution\", \"voxelSize\", \"padding\", "
                 "\"sign\", \"storage\", \"scale\", \"backend\"}]}, paths relative to the "
                 "manifest), skipping outputs that are up to date.");
    app->add_option("MANIFEST", args->manifest, "manifest file (.json)")->required();
    app->add_option("--depfile", args->depfile,
                    "write a Makefile-syntax depfile (output: mesh manifest) for build systems");
    app->add_flag("--force", args->force, "bake every entry, up to date or not");
    app->add_flag("-q,--quiet", args->quiet, "print nothing but errors");
    return {app, [args] { return runBatch(*args); }};
}

} // namespace sluice::bake::cli
