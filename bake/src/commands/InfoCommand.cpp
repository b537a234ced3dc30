// `sluice-bake info`: an asset's header, provenance and figures, and optionally a slice picture.
#include <algorithm>
#include <array>
#include <fstream>
#include <iostream>
#include <optional>

#include "commands/CliSupport.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/interop/NanoVdbIO.h"
#include "sluice/bake/validate/SliceImage.h"
#include "sluice/format/asset/AssetHeader.h"
#include "sluice/format/asset/NanoVdbCheck.h"
#include "sluice/format/scene/SolverReach.h"
#include "sluice/format/support/Hash.h"

namespace sluice::bake::cli {
namespace {

struct InfoArgs {
    std::string asset;
    bool json = false;
    std::string slice;
    std::string png;
};

/// The header of a file that has already been read and verified whole.
format::AssetHeader readHeader(const std::filesystem::path& path) {
    std::array<std::byte, format::kAssetHeaderSize> bytes{};
    std::ifstream in(path, std::ios::binary);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
    return format::unpackAssetHeader(bytes);
}

/// The "mass" line: the closed mesh's exact mass properties, or why there are none.
void printMass(const std::optional<format::MassProperties>& mass,
               const format::AssetHeader& header) {
    if (!mass) {
        std::cout << "  mass          not recorded ("
                  << (header.minor < format::kAssetMinorMeshMass
                          ? "the asset predates format 1.1; re-bake to record it"
                          : "the source mesh is not a closed, consistently wound surface")
                  << ")\n";
        return;
    }
    const glm::dvec3& c = mass->centerOfMass;
    const glm::dmat3& i = mass->inertia; // column-major: i[col][row]
    std::cout << "  mass          volume " << num(mass->volume)
              << " world units^3, centre of mass (" << num(c.x) << ", " << num(c.y) << ", "
              << num(c.z) << ") (exact, closed mesh)\n"
              << "  inertia       about the centre of mass, unit density [world units^5]:\n";
    for (int row = 0; row < 3; ++row)
        std::cout << "                [" << num(i[0][row]) << ", " << num(i[1][row]) << ", "
                  << num(i[2][row]) << "]\n";
}

/// The NanoVDB tree of a sparse asset or .nvdb file: nodes per level, band voxels, bytes.
void printTree(const format::NanoVdbTreeStats& t, double bandWidth) {
    std::cout << "  tree          NanoVDB: " << plural(t.upperNodes, "upper node") << ", "
              << plural(t.lowerNodes, "lower node") << ", " << plural(t.leafNodes, "leaf node")
              << ", " << plural(t.rootTiles, "root tile") << "; " << t.activeVoxels
              << " active voxels (band " << num(bandWidth) << " voxels), " << t.bytes << " bytes\n";
}

/// What a band of `band` voxels of `voxel` [world units] holds exact, and the particle spacings
/// it serves in sluice-play (format/scene/SolverReach.h), at scale 1 and the default kernel.
void printBandServes(double band, double voxel) {
    std::cout << "  band serves   exact to " << num(format::exactReach(band, voxel))
              << " world units from the surface with trilinear reads: particle spacing up to "
              << num(format::largestSpacingForBand(band, voxel, false)) << " as a static collider, "
              << num(format::largestSpacingForBand(band, voxel, true))
              << " as a dynamic body (kernel radius 2 x spacing, scale 1; `bake --sparse "
                 "--for-spacing S` picks the band for S)\n";
}

nlohmann::ordered_json bandServesJson(double band, double voxel) {
    return {{"staticSpacing", format::largestSpacingForBand(band, voxel, false)},
            {"dynamicSpacing", format::largestSpacingForBand(band, voxel, true)}};
}

nlohmann::ordered_json treeJson(const format::NanoVdbTreeStats& t) {
    return {{"upperNodes", t.upperNodes},   {"lowerNodes", t.lowerNodes},
            {"leafNodes", t.leafNodes},     {"rootTiles", t.rootTiles},
            {"valueEntries", t.valueTiles}, {"activeVoxels", t.activeVoxels},
            {"background", t.background},   {"bytes", t.bytes}};
}

// What a volume map holds: its support, points, the share of them not 0, and its range.
struct VolumeMapSummary {
    double support = 0.0;
    std::uint64_t points = 0;
    std::uint64_t nonZero = 0;
    float lo = 0.0f, hi = 0.0f;
};

std::vector<VolumeMapSummary> summarizeVolumeMaps(const format::ColliderAsset& asset) {
    std::vector<VolumeMapSummary> out;
    for (const format::VolumeMap& map : asset.volumeMaps) {
        VolumeMapSummary s;
        s.support = map.support;
        s.points = map.values.size();
        if (!map.values.empty())
            s.lo = s.hi = map.values[0];
        for (float v : map.values) {
            s.nonZero += v != 0.0f;
            s.lo = std::min(s.lo, v);
            s.hi = std::max(s.hi, v);
        }
        out.push_back(s);
    }
    return out;
}

void printVolumeMaps(const format::ColliderAsset& asset) {
    const std::vector<VolumeMapSummary> maps = summarizeVolumeMaps(asset);
    if (maps.empty()) {
        std::cout << "  volume maps   none (sluice-bake bake --volume-map H bakes one)\n";
        return;
    }
    for (const VolumeMapSummary& s : maps)
        std::cout << "  volume map    support " << num(s.support) << " asset units: " << s.points
                  << " points, " << s.nonZero << " not 0, " << num(s.lo, 4) << " .. "
                  << num(s.hi, 4) << '\n';
}

nlohmann::ordered_json volumeMapsJson(const format::ColliderAsset& asset) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const VolumeMapSummary& s : summarizeVolumeMaps(asset))
        out.push_back({{"support", s.support},
                       {"points", s.points},
                       {"nonZero", s.nonZero},
                       {"range", {s.lo, s.hi}}});
    return out;
}

void printText(const InfoArgs& args, const format::ColliderAsset& asset, bool vdb,
               const format::AssetHeader& header, float lo, float hi) {
    const format::ColliderMeta& m = asset.meta;
    std::cout << args.asset;
    if (vdb)
        std::cout << "  (OpenVDB grid, read densely over its active box)\n";
    else
        std::cout << "  (collider asset v" << header.major << '.' << header.minor << ", "
                  << header.fileSize << " bytes, checksum " << format::hex64(header.checksum)
                  << ")\n";
    const glm::dvec3 extent = glm::dvec3(m.dims - 1u) * m.voxelSize;
    std::cout << "  grid          " << describeDims(m.dims) << '\n'
              << "  voxel size    " << num(m.voxelSize) << " world units\n"
              << "  origin        (" << num(m.origin.x) << ", " << num(m.origin.y) << ", "
              << num(m.origin.z) << ") world units\n"
              << "  extent        " << num(extent.x) << " x " << num(extent.y) << " x "
              << num(extent.z) << " world units\n"
              << "  distances     " << num(lo) << " .. " << num(hi)
              << " world units (negative inside)\n"
              << "  storage       " << storageName(m.storage) << ", quantization error "
              << num(m.quantizationError, 3) << " world units\n"
              << "  layout        " << layoutName(m.layout) << '\n';
    if (asset.sparse()) {
        printTree(*format::checkNanoVdbGrid(asset.grid, args.asset), m.bandWidth);
        printBandServes(m.bandWidth, m.voxelSize);
    }
    const format::BakeParams& b = m.bake;
    std::cout << "  source        " << m.sourceFile << "  (xxh3 " << m.sourceHash << ")\n"
              << "  tool          " << (m.toolVersion.empty() ? "not recorded" : m.toolVersion)
              << '\n';
    if (vdb) {
        // A grid's metadata records where it came from, not how it was baked.
        std::cout << "  bake          backend " << b.backend << ", sign "
                  << signMethodName(b.signUsed) << " (the rest is not recorded in a .vdb)\n";
        return;
    }
    std::cout << "  bake          backend " << b.backend << ", resolution "
              << (b.resolution ? std::to_string(b.resolution) : std::string("- (voxel size)"))
              << ", padding " << num(b.padding) << " voxels, sign " << b.signMode << " -> "
              << signMethodName(b.signUsed) << ", scale " << num(b.scale) << '\n'
              << "  mesh          " << describeMesh(m.mesh) << '\n';
    printMass(m.meshMass, header);
    printVolumeMaps(asset);
    const format::ValidationFigures& v = m.validation;
    if (!v.known) {
        std::cout << "  validation    not recorded (sluice-bake validate --write)\n";
        return;
    }
    std::cout << "  validation    " << v.pointsChecked << " points: error max "
              << num(v.maxError, 3) << ", mean " << num(v.meanError, 3) << ", rms "
              << num(v.rmsError, 3) << " voxels; "
              << plural(v.signMismatches, "sign mismatch", "sign mismatches")
              << "; |grad phi| median " << num(v.eikonalMedian, 4) << ", p99 "
              << num(v.eikonalP99, 4) << ", " << num(100.0 * v.eikonalOutsideShare, 3)
              << " % outside [0.5, 1.5]\n";
}

/// toJson(meta), with null for what a .vdb grid does not record (the bake settings other than
/// backend and sign, and the mesh diagnostics) rather than zeros and falses.
nlohmann::ordered_json metaJson(const format::ColliderMeta& meta, bool vdb) {
    nlohmann::ordered_json json = toJson(meta);
    if (!vdb)
        return json;
    if (meta.toolVersion.empty())
        json["toolVersion"] = nullptr;
    for (const char* key : {"resolution", "padding", "signMode", "scale"})
        json["bake"][key] = nullptr;
    for (auto& [key, value] : json["mesh"].items())
        value = nullptr;
    return json;
}

/// `info GRID.nvdb`: the first grid's tree, as read and checked.
int runInfoNvdb(const InfoArgs& args) {
    constexpr std::string_view cmd = "info";
    if (!args.slice.empty())
        return reportBadInput(cmd, "--slice needs a collider asset (.slc) or a .vdb file");
    Result<format::GridBytes> grid = readNvdbGrid(args.asset);
    if (!grid)
        return reportFileError(cmd, "cannot read grid", args.asset, grid.error());
    const format::NanoVdbTreeStats t = *format::checkNanoVdbGrid(*grid, args.asset);
    if (args.json) {
        nlohmann::ordered_json out = {{"file", args.asset}, {"format", "nanovdb"}};
        out["name"] = t.name.data();
        out["voxelSize"] = {t.voxelSize.x, t.voxelSize.y, t.voxelSize.z};
        out["translation"] = {t.translation.x, t.translation.y, t.translation.z};
        out["tree"] = treeJson(t);
        out["bandServes"] = bandServesJson(t.background / t.voxelSize.x, t.voxelSize.x);
        std::cout << out.dump(2) << '\n';
        return kExitOk;
    }
    std::cout << args.asset << "  (NanoVDB float level set '" << t.name.data() << "')\n"
              << "  voxel size    " << num(t.voxelSize.x) << " world units\n"
              << "  translation   (" << num(t.translation.x) << ", " << num(t.translation.y) << ", "
              << num(t.translation.z) << ") world units\n"
              << "  background    " << num(t.background) << " world units\n";
    printTree(t, t.background / t.voxelSize.x);
    printBandServes(t.background / t.voxelSize.x, t.voxelSize.x);
    return kExitOk;
}

int runInfo(const InfoArgs& args) {
    constexpr std::string_view cmd = "info";
    if (hasExtension(args.asset, ".nvdb"))
        return runInfoNvdb(args);
    std::optional<SliceSpec> slice;
    if (!args.slice.empty()) {
        Result<SliceSpec> parsed = parseSlice(args.slice);
        if (!parsed)
            return reportBadInput(cmd, parsed.error().detail); // the detail names --slice
        slice = *parsed;
        if (Result<void> out = prepareOutputPath(args.png); !out)
            return reportFileError(cmd, "cannot write", args.png, out.error());
    }

    Result<format::ColliderAsset> asset = loadAsset(args.asset);
    if (!asset)
        return reportFileError(cmd, "cannot read asset", args.asset, asset.error());
    const bool vdb = hasExtension(args.asset, ".vdb");
    const format::AssetHeader header = vdb ? format::AssetHeader{} : readHeader(args.asset);
    const auto [lo, hi] = std::minmax_element(asset->distances.begin(), asset->distances.end());
    float minPhi = lo == asset->distances.end() ? 0.0f : *lo;
    float maxPhi = hi == asset->distances.end() ? 0.0f : *hi;
    std::optional<format::NanoVdbTreeStats> tree;
    if (asset->sparse()) { // stored values are clamped to +-background
        tree = *format::checkNanoVdbGrid(asset->grid, args.asset);
        minPhi = -tree->background;
        maxPhi = tree->background;
    }

    if (slice) {
        const Image image = renderSlice(*asset, *slice);
        if (Result<void> ok = format::writePng(args.png, image); !ok)
            return reportFileError(cmd, "cannot write", args.png, ok.error());
    }

    if (args.json) {
        nlohmann::ordered_json out = {{"file", args.asset},
                                      {"format", vdb ? "openvdb" : "sluice-collider"}};
        out["header"] = nullptr;
        if (!vdb)
            out["header"] = {{"major", header.major},
                             {"minor", header.minor},
                             {"headerSize", header.headerSize},
                             {"fileSize", header.fileSize},
                             {"metaOffset", header.metaOffset},
                             {"metaSize", header.metaSize},
                             {"payloadOffset", header.payloadOffset},
                             {"payloadSize", header.payloadSize},
                             {"checksum", format::hex64(header.checksum)}};
        const nlohmann::ordered_json meta = metaJson(asset->meta, vdb);
        for (const auto& [key, value] : meta.items())
            out[key] = value;
        out["distanceRange"] = {minPhi, maxPhi};
        out["tree"] = tree ? treeJson(*tree) : nlohmann::ordered_json(nullptr);
        out["bandServes"] = tree ? bandServesJson(asset->meta.bandWidth, asset->meta.voxelSize)
                                 : nlohmann::ordered_json(nullptr);
        out["volumeMaps"] = volumeMapsJson(*asset);
        if (slice)
            out["slicePng"] = args.png;
        std::cout << out.dump(2) << '\n';
    } else {
        printText(args, *asset, vdb, header, minPhi, maxPhi);
        if (slice)
            std::cout << "  slice         " << args.slice << " -> " << args.png << '\n';
    }
    return kExitOk;
}

/// The options of `info`, bound to `args`.
void addInfoOptions(CLI::App& app, InfoArgs& args) {
    app.add_option("ASSET", args.asset, "collider asset (.slc), .vdb or .nvdb file")->required();
    app.add_flag("--json", args.json, "print as JSON");
    CLI::Option* slice = app.add_option(
        "--slice", args.slice, "slice to draw: x|y|z=FRACTION of the grid extent, e.g. z=0.5");
    CLI::Option* png = app.add_option("--png", args.png, "PNG file for the --slice picture");
    slice->needs(png);
    png->needs(slice);
}

} // namespace

Command addInfoCommand(CLI::App& parent) {
    return addSubcommand(
        parent, "info",
        "Print an asset's header and metadata: grid, provenance, mesh diagnostics, "
        "mass properties, validation figures, and a sparse asset's NanoVDB tree. Also "
        "reads .vdb grids and .nvdb grids (the tree only).",
        addInfoOptions, runInfo);
}

} // namespace sluice::bake::cli
