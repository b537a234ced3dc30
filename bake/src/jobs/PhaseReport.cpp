// The phase timeline of a bake for people and for JSON (`sluice-bake bake --profile`).
#include "jobs/PhaseReport.h"

#include <algorithm>
#include <cstdio>

namespace sluice::bake::cli {
namespace {

double cpuSum(const PhaseLog& log) {
    double sum = 0.0;
    for (const Phase& phase : log.phases())
        if (!phase.overlapped)
            sum += phase.cpuSeconds;
    return sum;
}

std::string line(const char* format, const std::string& name, double wall, double cpu) {
    char text[256];
    std::snprintf(text, sizeof text, format, name.c_str(), wall, cpu);
    return text;
}

} // namespace

nlohmann::ordered_json phasesJson(const PhaseLog& log) {
    nlohmann::ordered_json phases = nlohmann::ordered_json::array();
    nlohmann::ordered_json overlapped = nlohmann::ordered_json::array();
    for (const Phase& phase : log.phases())
        (phase.overlapped ? overlapped : phases)
            .push_back({{"name", phase.name},
                        {"wallSeconds", phase.wallSeconds},
                        {"cpuSeconds", phase.cpuSeconds}});
    return {{"totalSeconds", log.totalSeconds()},
            {"phasesSeconds", log.sumSeconds()},
            {"unaccountedSeconds", log.totalSeconds() - log.sumSeconds()},
            {"cpuSeconds", cpuSum(log)},
            {"phases", phases},
            {"overlapped", overlapped}};
}

std::string describePhases(const PhaseLog& log) {
    std::size_t width = 0;
    for (const Phase& phase : log.phases())
        width = std::max(width, phase.name.size() + (phase.overlapped ? 2 : 0));
    std::string text;
    char head[256];
    std::snprintf(head, sizeof head,
                  "  profile  %.3f s from process start, %.3f s CPU; phases sum to %.3f s, "
                  "%.3f s unaccounted\n",
                  log.totalSeconds(), cpuSum(log), log.sumSeconds(),
                  log.totalSeconds() - log.sumSeconds());
    text += head;
    for (const Phase& phase : log.phases()) {
        std::string name = phase.overlapped ? "| " + phase.name : phase.name;
        name.resize(width, ' ');
        text += line("           %s %8.3f s wall %8.3f s CPU", name, phase.wallSeconds,
                     phase.cpuSeconds);
        text += phase.overlapped ? " (beside the timeline: not in the sum)\n" : "\n";
    }
    return text;
}

} // namespace sluice::bake::cli
