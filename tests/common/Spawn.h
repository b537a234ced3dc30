// Starting a program with posix_spawn, its stdout and stderr into files: for the tests and
// benches that need the child's pid or its resource usage, which testrun::runProgram's shell hides.
#pragma once

#include <string>
#include <vector>

#include <fcntl.h>
#include <spawn.h>

namespace sluice::testrun {

/// Starts argv[0] with `argv` and the environment `envp` (null-terminated; `environ` for ours),
/// stdout into `outFile` and stderr into `errFile` (created, or emptied). posix_spawn's result:
/// 0 and `pid` set, or the error number.
inline int spawnToFiles(pid_t& pid, const std::vector<std::string>& argv,
                        const std::string& outFile, const std::string& errFile, char* const* envp) {
    std::vector<char*> args;
    for (const std::string& a : argv)
        args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    const int flags = O_WRONLY | O_CREAT | O_TRUNC;
    posix_spawn_file_actions_addopen(&actions, 1, outFile.c_str(), flags, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, errFile.c_str(), flags, 0644);
    const int result = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), envp);
    posix_spawn_file_actions_destroy(&actions);
    return result;
}

} // namespace sluice::testrun
