// bake_bench --whole-process: the real sluice-bake process per backend, interleaved, timed whole.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sluice::bench {

/// What --whole-process runs.
struct WholeProcessOptions {
    std::string exe;  ///< the sluice-bake program
    std::string mesh; ///< the mesh every run bakes
    std::vector<std::uint32_t> resolutions;
    int repeat = 5;       ///< runs per backend and resolution
    std::string outDir;   ///< where the runs write their assets and output
    bool warmup = true;   ///< one GPU bake first (page cache, shader caches), not counted
};

/// Runs `exe bake MESH --backend gpu|cgal --resolution R --json --profile` `repeat` times per
/// backend, gpu and cgal alternating, and prints per backend the median and range (min-max) of
/// the wall seconds (spawn to exit) and CPU seconds (wait4: every thread, the import child
/// included), the ratio cgal/gpu of the medians and of each interleaved pair, and the median
/// of each phase of the GPU runs' profiles. Returns a process exit code.
int runWholeProcess(const WholeProcessOptions& options);

} // namespace sluice::bench
