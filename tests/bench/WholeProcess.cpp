// bake_bench --whole-process: the real sluice-bake process per backend, interleaved, timed whole.
#include "WholeProcess.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "Spawn.h"

extern char** environ;

namespace sluice::bench {
namespace {

/// One finished run of sluice-bake.
struct Run {
    int code = -1;
    double wall = 0.0;     ///< [s] spawn to exit, measured here
    double cpu = 0.0;      ///< [s] user + system of the process and its waited-for children
    nlohmann::json report; ///< its --json output; null if it printed none
};

double seconds(const timeval& t) {
    return double(t.tv_sec) + 1e-6 * double(t.tv_usec);
}

/// Spawns `args` with stdout into `stdoutPath` and stderr into `stderrPath`, waits for it.
Run spawnAndWait(const std::vector<std::string>& args, const std::string& stdoutPath,
                 const std::string& stderrPath) {
    Run run;
    const auto start = std::chrono::steady_clock::now();
    pid_t pid = 0;
    const int spawned = testrun::spawnToFiles(pid, args, stdoutPath, stderrPath, environ);
    if (spawned != 0) {
        std::fprintf(stderr, "bake_bench: cannot start %s: %s\n", args[0].c_str(),
                     std::strerror(spawned));
        return run;
    }
    int status = 0;
    rusage usage{};
    while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    run.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // wait4's usage of the child covers its threads and the children it waited for.
    run.cpu = seconds(usage.ru_utime) + seconds(usage.ru_stime);
    run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(stdoutPath);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    run.report = nlohmann::json::parse(text, nullptr, false);
    if (run.report.is_discarded())
        run.report = nullptr;
    return run;
}

double median(std::vector<double> values) {
    if (values.empty())
        return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// "1.234 (1.200-1.300)": median and range.
std::string spread(const std::vector<double>& values, int digits = 3) {
    if (values.empty())
        return "-";
    char text[96];
    std::snprintf(text, sizeof text, "%.*f (%.*f-%.*f)", digits, median(values), digits,
                  *std::min_element(values.begin(), values.end()), digits,
                  *std::max_element(values.begin(), values.end()));
    return text;
}

/// The runs of one backend at one resolution.
struct Series {
    std::vector<double> wall, cpu, profileTotal, afterLastPhase;
    std::map<std::string, std::vector<double>> phaseWall, phaseCpu; ///< by phase name
    std::vector<std::string> phaseOrder;                            ///< first run's order

    void add(const Run& run) {
        wall.push_back(run.wall);
        cpu.push_back(run.cpu);
        if (!run.report.is_object() || !run.report.contains("profile"))
            return;
        const nlohmann::json& profile = run.report["profile"];
        const double total = profile["totalSeconds"].get<double>();
        profileTotal.push_back(total);
        // The process's own total runs from its start to its last phase; what the spawn took
        // beyond that is the exit (and the spawn itself).
        afterLastPhase.push_back(run.wall - total);
        std::map<std::string, int> seen;
        for (const char* list : {"phases", "overlapped"})
            for (const nlohmann::json& phase : profile[list]) {
                std::string name = phase["name"].get<std::string>();
                if (std::strcmp(list, "overlapped") == 0)
                    name = "| " + name;
                if (++seen[name] > 1) // a phase run twice (a bake again) keeps both
                    name += " #" + std::to_string(seen[name]);
                if (!phaseWall.count(name))
                    phaseOrder.push_back(name);
                phaseWall[name].push_back(phase["wallSeconds"].get<double>());
                phaseCpu[name].push_back(phase["cpuSeconds"].get<double>());
            }
    }
};

void printPhases(const Series& gpu) {
    std::printf("  GPU runs, median of each phase (wall s, CPU s of the whole process; '|' ran "
                "beside the others):\n");
    for (const std::string& name : gpu.phaseOrder)
        std::printf("    %-62s %7.3f %7.3f\n", name.c_str(), median(gpu.phaseWall.at(name)),
                    median(gpu.phaseCpu.at(name)));
}

} // namespace

int runWholeProcess(const WholeProcessOptions& options) {
    std::filesystem::create_directories(options.outDir);
    const auto bakeArgs = [&](const char* backend, std::uint32_t resolution) {
        return std::vector<std::string>{options.exe,
                                        "bake",
                                        options.mesh,
                                        "-o",
                                        options.outDir + "/" + backend + ".slc",
                                        "--backend",
                                        backend,
                                        "--resolution",
                                        std::to_string(resolution),
                                        "--json",
                                        "--profile"};
    };
    const std::string out = options.outDir + "/stdout.json", err = options.outDir + "/stderr.txt";
    std::printf("whole process: %s bake %s, %d run(s) per backend and resolution, gpu and cgal "
                "alternating\n",
                options.exe.c_str(), options.mesh.c_str(), options.repeat);
    if (options.warmup) {
        const Run warm = spawnAndWait(bakeArgs("gpu", 16), out, err);
        if (warm.code != 0) {
            std::fprintf(stderr, "bake_bench: the warm-up bake failed (exit %d); see %s\n",
                         warm.code, err.c_str());
            return 4;
        }
        std::printf("warm-up: gpu at 16, %.3f s (not counted)\n", warm.wall);
    }
    for (std::uint32_t resolution : options.resolutions) {
        Series gpu, cgal;
        std::vector<double> pairRatio, pairCpuRatio;
        for (int r = 0; r < options.repeat; ++r) {
            Run runs[2];
            // Alternate which goes first, so neither always follows the other.
            for (int k = 0; k < 2; ++k) {
                const bool isGpu = (k == 0) == (r % 2 == 0);
                Run run = spawnAndWait(bakeArgs(isGpu ? "gpu" : "cgal", resolution), out, err);
                if (run.code != 0) {
                    std::fprintf(stderr,
                                 "bake_bench: sluice-bake --backend %s failed (exit %d); "
                                 "see %s\n",
                                 isGpu ? "gpu" : "cgal", run.code, err.c_str());
                    return 4;
                }
                (isGpu ? gpu : cgal).add(run);
                runs[isGpu ? 0 : 1] = std::move(run);
            }
            pairRatio.push_back(runs[1].wall / runs[0].wall);
            pairCpuRatio.push_back(runs[1].cpu / runs[0].cpu);
            std::printf("  res %u run %d: gpu %.3f s (%.3f CPU), cgal %.3f s (%.3f CPU), "
                        "cgal/gpu %.2f\n",
                        resolution, r + 1, runs[0].wall, runs[0].cpu, runs[1].wall, runs[1].cpu,
                        pairRatio.back());
            std::fflush(stdout);
        }
        std::printf("resolution %u, median (min-max) of %d:\n", resolution, options.repeat);
        std::printf("  gpu  wall s %s   CPU s %s   own profile total %s   after its last "
                    "phase %s\n",
                    spread(gpu.wall).c_str(), spread(gpu.cpu).c_str(),
                    spread(gpu.profileTotal).c_str(), spread(gpu.afterLastPhase).c_str());
        std::printf("  cgal wall s %s   CPU s %s   own profile total %s   after its last "
                    "phase %s\n",
                    spread(cgal.wall).c_str(), spread(cgal.cpu).c_str(),
                    spread(cgal.profileTotal).c_str(), spread(cgal.afterLastPhase).c_str());
        std::printf("  cgal/gpu: wall %.2f (ratio of medians), per pair %s; CPU %.2f, per pair "
                    "%s\n",
                    median(cgal.wall) / median(gpu.wall), spread(pairRatio, 2).c_str(),
                    median(cgal.cpu) / median(gpu.cpu), spread(pairCpuRatio, 2).c_str());
        printPhases(gpu);
        std::fflush(stdout);
    }
    return 0;
}

} // namespace sluice::bench
