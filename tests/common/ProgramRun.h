// Runs one of the Sluice programs from tests and captures its exit code and output.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <sys/wait.h>

namespace sluice::testrun {

/// What one run of a program did.
struct RunResult {
    int code = -1; ///< exit code, -1 if it did not exit normally
    std::string out;
    std::string err;
};

/// A fresh folder for test files: SLUICE_TEST_TMP/<name> if the test target defines it, else
/// under the system temp folder. Emptied if it exists.
inline std::filesystem::path tempDir(const std::string& name) {
#ifdef SLUICE_TEST_TMP
    const std::filesystem::path root = SLUICE_TEST_TMP;
#else
    const std::filesystem::path root = std::filesystem::temp_directory_path() / "sluice-tests";
#endif
    const std::filesystem::path dir = root / name;
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    std::filesystem::create_directories(dir);
    return dir;
}

/// A whole file as bytes in a string (empty if it cannot be read).
inline std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// `arg` single-quoted for the shell.
inline std::string quote(const std::string& arg) {
    std::string quoted = "'";
    for (char c : arg)
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

/// Runs `exe` with `args` (each quoted for the shell), capturing stdout and stderr in files in
/// `dir`.
inline RunResult runProgram(const std::string& exe, const std::filesystem::path& dir,
                            const std::vector<std::string>& args) {
    std::string command = quote(exe);
    for (const std::string& arg : args)
        command += " " + quote(arg);
    const std::filesystem::path out = dir / "stdout.txt", err = dir / "stderr.txt";
    command += " >" + quote(out.string()) + " 2>" + quote(err.string());
    const int status = std::system(command.c_str());
    RunResult run;
    run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = readText(out);
    run.err = readText(err);
    return run;
}

/// `what` printed for a failed expectation: the command's output.
inline std::string shown(const RunResult& run) {
    return "exit " + std::to_string(run.code) + "\nstdout:\n" + run.out + "\nstderr:\n" + run.err;
}

} // namespace sluice::testrun
