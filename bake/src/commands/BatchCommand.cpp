// `sluice-bake batch`: bakes every collider a JSON manifest lists, skipping those up to date.
//
// Manifest (format/BatchManifest.h; paths relative to the manifest's folder; every field but
// mesh and output optional, with the defaults of `bake`; resolution or voxelSize, not both):
//   { "colliders": [ { "mesh": "meshes/rock.obj", "output": "rock.slc", "resolution": 64,
//                      "padding": 3, "sign": "auto", "storage": "f32", "scale": 1,
//                      "backend": "cgal" } ] }
// The whole manifest is checked, and every output's folder created, before the first bake.
// An output is fresh when it reads as a valid asset that records the XXH3 hash of the mesh
// file's current bytes, the same bake settings and this tool version. Only content counts:
// touching a mesh without changing it bakes nothing, and no modification time is trusted.
// --force bakes everything. --jobs N bakes up to N entries at once, each in a child process of
// this program; GPU entries take turns (CGAL entries run beside them). --depfile writes a
// Makefile-syntax rule per output (output: mesh manifest) for build systems (Ninja's and
// Make's depfiles).
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "commands/CliSupport.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/jobs/BatchJob.h"
#include "sluice/bake/jobs/PhaseLog.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/scene/BatchManifest.h"
#include "sluice/format/support/AtomicFile.h"

namespace sluice::bake::cli {
namespace {

namespace fs = std::filesystem;

struct BatchArgs {
    std::string manifest;
    std::string depfile;
    unsigned jobs = 1;
    bool force = false;
    bool quiet = false;
};

/// One manifest entry: the bake it asks for (paths resolved against the manifest's folder) and
/// its name in the summary, as runBake takes it (a child prints as `bake` does) and as the
/// library's freshness rule takes it.
struct Entry {
    BakeArgs bake;
    BatchEntry job;
};

/// What happened to one entry.
enum class Status { Fresh, Baked, Failed };

struct Outcome {
    Status status = Status::Failed;
    int exitCode = kExitOk;         ///< runBake's code for a failed entry
    double seconds = 0.0;           ///< [s] freshness check and bake
    std::uint64_t points = 0;       ///< [grid points] of the asset, 0 if unknown
    std::optional<double> maxError; ///< [voxels] recorded by `validate --write`, if any
};

/// The bake a manifest entry asks for, its paths resolved against the manifest's folder.
Entry entryFor(const format::BatchEntry& manifestEntry) {
    Entry entry;
    entry.job = batchEntryFor(manifestEntry);
    const BakeRequest& request = entry.job.request;
    BakeArgs& args = entry.bake;
    args.mesh = entry.job.mesh;
    args.output = entry.job.output;
    args.resolution = request.resolution;
    args.voxelSize = request.voxelSize;
    args.padding = request.padding;
    args.sign = request.sign;
    args.storage = request.storage;
    args.scale = request.scale;
    args.backend = request.backend;
    args.sparse = request.sparse;
    args.band = request.band;
    args.forSpacing = request.forSpacing;
    args.forKernelRadius = request.forKernelRadius;
    args.volumeMaps = request.volumeMaps;
    args.quiet = true;
    return entry;
}

/// The manifest's entries, checked whole (format::readBatchManifest), with every output's
/// folder created: a manifest error or an output that cannot be written fails here, before any
/// entry bakes. The detail names the manifest and the JSON path.
Result<std::vector<Entry>> readManifest(const std::string& path) {
    Result<format::BatchManifest> manifest = format::readBatchManifest(path);
    if (!manifest)
        return manifest.error();
    std::vector<Entry> entries;
    for (std::size_t n = 0; n < manifest->colliders.size(); ++n) {
        const format::BatchEntry& entry = manifest->colliders[n];
        if (Result<void> out = prepareOutputPath(entry.outputPath); !out)
            return fail(out.error().code, path + ": colliders[" + std::to_string(n) +
                                              "].output: " + out.error().detail);
        entries.push_back(entryFor(entry));
    }
    return entries;
}

/// Figures of an asset for the summary.
void describeAsset(const format::ColliderAsset& asset, Outcome& outcome) {
    outcome.points = asset.pointCount();
    if (asset.meta.validation.known)
        outcome.maxError = asset.meta.validation.maxError;
}

/// `value` with the fewest digits that read back as the same double, for a child's arguments.
std::string exactNumber(double value) {
    char text[32];
    const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
    return ec == std::errc() ? std::string(text, end) : std::to_string(value);
}

/// A path as a child's argument: relative ones start with "./", so none reads as an option.
std::string argumentPath(const std::string& path) {
    return fs::path(path).is_relative() ? (fs::path(".") / path).string() : path;
}

/// Runs `sluice-bake bake` with `args` in a child process of this program and returns its exit
/// code. With --jobs > 1 every bake runs this way: mesh import forks (Isolated.h), and a fork
/// taken while other threads bake can copy a lock another thread holds (the sanitizers'
/// allocator does deadlock so). A child that forks only for its own import is the single
/// threaded case `bake` is tested for, and a crash stays in the child.
int bakeInChild(const BakeArgs& args) {
    std::vector<std::string> words = {"sluice-bake", "bake", "--quiet", "-o",
                                      argumentPath(args.output)};
    words.insert(words.end(),
                 {"--backend", args.backend, "--sign", args.sign, "--storage", args.storage});
    words.insert(words.end(),
                 {"--padding", exactNumber(args.padding), "--scale", exactNumber(args.scale)});
    if (args.sparse && args.forSpacing > 0.0)
        words.insert(words.end(), {"--sparse", "--for-spacing", exactNumber(args.forSpacing)});
    else if (args.sparse)
        words.insert(words.end(), {"--sparse", "--band", exactNumber(args.band)});
    if (args.forKernelRadius > 0.0)
        words.insert(words.end(), {"--for-kernel-radius", exactNumber(args.forKernelRadius)});
    for (double support : args.volumeMaps)
        words.insert(words.end(), {"--volume-map", exactNumber(support)});
    if (args.voxelSize > 0.0)
        words.insert(words.end(), {"--voxel-size", exactNumber(args.voxelSize)});
    else
        words.insert(words.end(), {"--resolution", std::to_string(args.resolution)});
    words.push_back(argumentPath(args.mesh));
    std::vector<char*> argv;
    for (std::string& word : words)
        argv.push_back(word.data());
    argv.push_back(nullptr);

    // posix_spawn execs at once (no code of ours runs in between), which is safe beside threads.
    pid_t pid = 0;
    if (const int err =
            ::posix_spawn(&pid, "/proc/self/exe", nullptr, nullptr, argv.data(), environ);
        err != 0) {
        std::cerr << "sluice-bake batch: cannot start a bake of '" << args.mesh
                  << "': " << std::strerror(err) << '\n';
        return kExitInternal;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            return kExitInternal;
    if (WIFEXITED(status))
        return WEXITSTATUS(status);
    std::cerr << "sluice-bake batch: the bake of '" << args.mesh << "' was killed by signal "
              << WTERMSIG(status) << '\n';
    return kExitInternal;
}

/// Checks one entry and bakes it if it is not fresh, in this process or (`inChild`) in a child
/// process. GPU bakes hold `gpuTurn` throughout: they share the machine's one GPU (or
/// llvmpipe's cores), so one runs at a time, beside any number of CGAL bakes.
Outcome process(const Entry& entry, bool force, bool inChild, std::mutex& gpuTurn) {
    const auto start = std::chrono::steady_clock::now();
    auto finish = [&](Outcome outcome) {
        outcome.seconds = secondsSince(start);
        return outcome;
    };
    Outcome outcome;
    if (!force) {
        if (std::optional<format::ColliderAsset> fresh = freshBatchOutput(entry.job)) {
            outcome.status = Status::Fresh;
            describeAsset(*fresh, outcome);
            return finish(outcome);
        }
    }
    std::unique_lock<std::mutex> turn(gpuTurn, std::defer_lock);
    if (entry.bake.backend == "gpu" || entry.bake.backend == "auto")
        turn.lock();
    outcome.exitCode = inChild ? bakeInChild(entry.bake) : runBake(entry.bake);
    if (turn.owns_lock())
        turn.unlock();
    if (outcome.exitCode != kExitOk) {
        outcome.status = Status::Failed;
        return finish(outcome);
    }
    outcome.status = Status::Baked;
    if (Result<format::ColliderAsset> written = format::readAsset(entry.bake.output))
        describeAsset(*written, outcome);
    return finish(outcome);
}

/// Runs `process` over every entry, `jobs` at a time; outcomes in manifest order. One job bakes
/// in this process; several check freshness on threads and bake in child processes.
std::vector<Outcome> processAll(const std::vector<Entry>& entries, unsigned jobs, bool force) {
    std::vector<Outcome> outcomes(entries.size());
    std::mutex gpuTurn;
    std::atomic<std::size_t> next{0};
    const std::size_t threads = std::min<std::size_t>(jobs, entries.size());
    const bool inChild = threads > 1;
    auto worker = [&] {
        for (std::size_t i = next++; i < entries.size(); i = next++) {
            // runCli turns an internal exception into exit 4; off the main thread it would
            // terminate the process, so each entry catches its own.
            try {
                outcomes[i] = process(entries[i], force, inChild, gpuTurn);
            } catch (const std::exception& e) {
                std::cerr << "sluice-bake batch: internal error on '" << entries[i].job.label
                          << "': " << e.what() << '\n';
                outcomes[i] = Outcome{.status = Status::Failed, .exitCode = kExitInternal};
            }
        }
    };
    if (!inChild) {
        worker();
        return outcomes;
    }
    std::vector<std::jthread> pool;
    for (std::size_t t = 0; t < threads; ++t)
        pool.emplace_back(worker);
    pool.clear(); // joins
    return outcomes;
}

const char* statusName(Status status) {
    switch (status) {
    case Status::Fresh:
        return "fresh";
    case Status::Baked:
        return "baked";
    case Status::Failed:
        return "FAILED";
    }
    return "?";
}

/// The table printed after a batch: one row per entry, in manifest order, then the totals.
void printSummary(const std::vector<Entry>& entries, const std::vector<Outcome>& outcomes,
                  double seconds) {
    std::size_t width = std::string_view("collider").size();
    for (const Entry& entry : entries)
        width = std::max(width, entry.job.label.size());
    const int w = int(width);
    std::printf("%-*s  %-6s  %8s  %11s  %s\n", w, "collider", "status", "time [s]", "grid points",
                "max error [voxels]");
    std::size_t counts[3] = {0, 0, 0};
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const Outcome& o = outcomes[i];
        ++counts[int(o.status)];
        const std::string points = o.points > 0 ? std::to_string(o.points) : "-";
        const std::string error = o.maxError ? num(*o.maxError, 3) : "-";
        std::printf("%-*s  %-6s  %8.2f  %11s  %s\n", w, entries[i].job.label.c_str(),
                    statusName(o.status), o.seconds, points.c_str(), error.c_str());
    }
    std::printf("%s: %zu baked, %zu fresh, %zu failed in %.2f s\n",
                plural(entries.size(), "collider").c_str(), counts[int(Status::Baked)],
                counts[int(Status::Fresh)], counts[int(Status::Failed)], seconds);
    std::fflush(stdout);
}

/// A path in a Makefile rule: spaces and '#' escaped with a backslash, '$' doubled.
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

Result<void> writeDepfile(const std::string& path, const std::string& manifest,
                          const std::vector<Entry>& entries) {
    std::string rules;
    for (const Entry& entry : entries)
        rules += makePath(entry.bake.output) + ": " + makePath(entry.bake.mesh) + " " +
                 makePath(manifest) + "\n";
    const auto* bytes = reinterpret_cast<const std::byte*>(rules.data());
    return format::writeFileAtomic(path, {bytes, rules.size()});
}

int runBatch(const BatchArgs& args) {
    constexpr std::string_view cmd = "batch";
    const auto start = std::chrono::steady_clock::now();
    // Everything that can be checked is checked before the first bake.
    if (!args.depfile.empty())
        if (Result<void> out = prepareOutputPath(args.depfile); !out)
            return reportFileError(cmd, "cannot write the depfile", args.depfile, out.error());
    Result<std::vector<Entry>> entries = readManifest(args.manifest);
    if (!entries)
        return reportBadInput(cmd, entries.error().detail);

    const std::vector<Outcome> outcomes = processAll(*entries, args.jobs, args.force);
    // The first failure in manifest order decides the exit code, whatever order threads ran in.
    int result = kExitOk;
    for (const Outcome& outcome : outcomes)
        if (outcome.status == Status::Failed && result == kExitOk)
            result = outcome.exitCode;

    if (!args.depfile.empty())
        if (Result<void> written = writeDepfile(args.depfile, args.manifest, *entries); !written)
            return reportFileError(cmd, "cannot write", args.depfile, written.error());
    if (!args.quiet)
        printSummary(*entries, outcomes, secondsSince(start));
    return result;
}

/// The options of `batch`, bound to `args`.
void addBatchOptions(CLI::App& app, BatchArgs& args) {
    app.add_option("MANIFEST", args.manifest, "manifest file (.json)")->required();
    app.add_option("--depfile", args.depfile,
                   "write a Makefile-syntax depfile (output: mesh manifest) for build systems");
    app.add_option("-j,--jobs", args.jobs,
                   "bake up to N entries at once, each in a child process (GPU entries take "
                   "turns on the GPU)")
        ->check(wholeNumber(1, 256))
        ->capture_default_str();
    app.add_flag("--force", args.force, "bake every entry, fresh or not");
    app.add_flag("-q,--quiet", args.quiet, "print nothing but errors");
}

} // namespace

Command addBatchCommand(CLI::App& parent) {
    return addSubcommand(
        parent, "batch",
        "Bake every collider a JSON manifest lists ({\"colliders\": [{\"mesh\", "
        "\"output\", and optionally \"resolution\", \"voxelSize\", \"padding\", "
        "\"sign\", \"storage\", \"scale\", \"backend\", \"sparse\", \"band\", "
        "\"forSpacing\", \"forKernelRadius\"}]}, paths "
        "relative to the manifest, output folders created), skipping outputs that are fresh: "
        "they record the hash of the mesh's current bytes, the same settings and this tool "
        "version. Prints a summary table; exits with the first failed entry's code, and a failed "
        "entry's previous output is left untouched.",
        addBatchOptions, runBatch);
}

} // namespace sluice::bake::cli
