// sluice-play --bench: steady-state step and pass timings of a scene, as a table and JSON.
#pragma once

#include <cstdint>
#include <string>

namespace sluice::rt {

struct BenchOptions {
    std::string scene;          ///< scene file
    std::uint64_t steps = 100;  ///< measured steps
    std::uint64_t warmup = 20;  ///< steps run first and not measured
    std::string json;           ///< results file, empty for none
    bool deterministic = false;
};

/// Runs the benchmark and prints its table; returns a sluice-play exit code.
int runBench(const BenchOptions& options);

} // namespace sluice::rt
