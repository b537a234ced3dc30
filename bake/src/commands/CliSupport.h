// What the sluice-bake subcommands share: registration, error reporting, loading, JSON, names.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "sluice/bake/import/MeshImport.h"
#include "sluice/bake/validate/Validate.h"
#include "sluice/format/support/CliErrors.h"
#include "sluice/format/asset/ColliderAsset.h"
#include "sluice/format/support/ExitCodes.h"
#include "sluice/format/support/Result.h"
#include "sluice/format/support/Suggest.h"

namespace sluice::bake::cli {

/// A registered subcommand: its CLI11 app and what runs it once parsing succeeded. `run`
/// returns a process exit code (Cli.h) and may throw only on internal failures.
struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

/// The options of one bake, as `bake` parses them (and `batch` reads them from a manifest).
struct BakeArgs {
    std::string mesh;
    std::string output;
    std::string backend = "auto";  ///< "auto" (gpu where GL 4.5 opens, else cgal) | "gpu" | "cgal"
    std::uint32_t resolution = 64; ///< [voxels] along the longest side; unused if voxelSize > 0
    double voxelSize = 0.0;        ///< [world units]
    double padding = 3.0;          ///< [voxels]
    std::string sign = "auto";
    double scale = 1.0;
    std::string storage = "f32";
    bool quiet = false;
    bool json = false;
    bool profile = false;
    bool programCache = true; ///< cache compiled GPU programs between runs (gpu::ProgramCache)
    bool sparse = false; ///< a narrow-band NanoVDB asset instead of a dense grid
    double band = 3.0;   ///< [voxels] sparse: half-width of the band of exact values
    double forSpacing = 0.0;      ///< [world units] sparse: pick the band for this spacing (0: no)
    double forKernelRadius = 0.0; ///< [world units] with forSpacing: the kernel (0: default)
    std::vector<double> volumeMaps; ///< [asset units] supports of the volume maps to bake
};

/// Binds the options of `bake` to `args` (BakeOptions.cpp).
void addBakeOptions(CLI::App& app, BakeArgs& args);

/// Registers subcommand `name` of `parent` with a fresh Args that lives as long as the Command:
/// `addOptions` binds the subcommand's options to it, and the Command runs `run` on it once
/// parsing succeeded.
template <class Args>
Command addSubcommand(CLI::App& parent, const std::string& name, const std::string& description,
                      void (*addOptions)(CLI::App& app, Args& args), int (*run)(const Args& args)) {
    auto args = std::make_shared<Args>();
    CLI::App* app = parent.add_subcommand(name, description);
    addOptions(*app, *args);
    return {app, [args, run] { return run(*args); }};
}

/// Runs one bake (BakeCommand.cpp) and returns its exit code; prints as `bake` does.
int runBake(const BakeArgs& args);

// One per subcommand, each in its own file (<Name>Command.cpp).
Command addBakeCommand(CLI::App& parent);
Command addValidateCommand(CLI::App& parent);
Command addInfoCommand(CLI::App& parent);
Command addExportCommand(CLI::App& parent);
Command addGlInfoCommand(CLI::App& parent);
Command addBatchCommand(CLI::App& parent);
Command addSurfaceCommand(CLI::App& parent);

// Number checks for options, shared with sluice-play (their messages read well after the
// option's name and value, as reportParseError prints them).
using format::cli::finiteNumber;
using format::cli::numberIn;
using format::cli::wholeNumber;

/// "sluice-bake <SLUICE_VERSION>", what --version prints and assets record.
std::string toolVersion();

/// Prints "sluice-bake <command>: <what>: <detail> [<Code>]" on stderr and returns
/// exitCodeFor(error). `what` names the file ("cannot read mesh 'a.obj'").
int reportError(std::string_view command, const std::string& what, const Error& error);

/// reportError for a failure about one file: "<what> '<path>'", or just "<what>" when the
/// error's detail already names the path (as the readers' messages do), so it is said once.
int reportFileError(std::string_view command, const std::string& what,
                    const std::filesystem::path& path, const Error& error);

/// Prints "sluice-bake <command>: <message>" on stderr and returns kExitBadInput.
int reportBadInput(std::string_view command, const std::string& message);

/// True if the file name ends in `ext` (".vdb"), ignoring case.
bool hasExtension(const std::filesystem::path& path, std::string_view ext);

/// A mesh through assimp, or the zero isosurface of a level-set .vdb, at the given scale.
Result<ImportedMesh> loadMesh(const std::filesystem::path& path, double scale);

/// loadMesh with the import's options (scale, phases, deferred self-intersection test, work
/// while importing). A level set (isLevelSetFile) is read in this process and diagnosed whole,
/// whatever selfIntersectionTest says; whileImporting then runs after it.
Result<ImportedMesh> loadMesh(const std::filesystem::path& path, const ImportOptions& options);

/// Whether loadMesh reads `path` as a level set (.vdb, .nvdb) rather than through assimp.
bool isLevelSetFile(const std::filesystem::path& path);

/// A collider asset file, or the first float grid of a .vdb read densely.
Result<format::ColliderAsset> loadAsset(const std::filesystem::path& path);

/// Makes `path` ready to be a new output file, before any long work: creates its missing
/// folders (as `mkdir -p`), and fails naming the path when they cannot be created (Io) or when
/// the path is a folder (InvalidArgument). The atomic write still has the last word.
Result<void> prepareOutputPath(const std::filesystem::path& path);

using format::signMethodName;
using format::storageName;

/// "1280 triangles, 642 vertices, closed, not self-intersecting, ..." for people.
std::string describeMesh(const format::MeshDiagnostics& mesh);

using format::plural;

/// "70 x 70 x 70 = 343000 points".
std::string describeDims(const glm::uvec3& dims);

/// Compact number for tables: up to `digits` significant digits ("%.*g").
std::string num(double value, int digits = 6);

// JSON views of the metadata (field names as in ColliderAsset.h); validation figures that were
// not recorded are null. Mass properties are {"volume", "centerOfMass": [x, y, z], "inertia":
// [[row 0], [row 1], [row 2]]}, null when the asset has none; the metadata holds them as
// "massProperties".
nlohmann::ordered_json toJson(const format::MeshDiagnostics& mesh);
nlohmann::ordered_json toJson(const format::ValidationFigures& figures);
nlohmann::ordered_json toJson(const std::optional<format::MassProperties>& mass);
nlohmann::ordered_json toJson(const format::ColliderMeta& meta);

/// [bytes] the process's peak resident memory so far (getrusage), 0 if unknown.
std::uint64_t peakRssBytes();

} // namespace sluice::bake::cli
