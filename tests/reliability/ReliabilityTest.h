// Helpers for the reliability tests: scratch folders, files as bytes, programs run with a pid.
#pragma once

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "Spawn.h"

extern char** environ;

namespace sluice::reliability {

namespace fs = std::filesystem;

/// A fresh folder SLUICE_TEST_TMP/<name> (emptied if it exists).
inline fs::path freshDir(const std::string& name) {
    const fs::path dir = fs::path(SLUICE_TEST_TMP) / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

inline void writeText(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

/// A whole file as bytes in a string; empty if it cannot be read.
inline std::string readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Names of the entries of `dir`, hidden ones included.
inline std::set<std::string> listDir(const fs::path& dir) {
    std::set<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
        names.insert(e.path().filename().string());
    return names;
}

/// A program started with posix_spawn: stdout and stderr go to files, the pid is at hand.
class Spawned {
public:
    /// Starts `argv[0]` with `argv`, plus `env` entries ("NAME=value") in front of ours.
    Spawned(const std::vector<std::string>& argv, const fs::path& outFile, const fs::path& errFile,
            const std::vector<std::string>& env = {}) {
        std::vector<std::string> envText = env;
        for (char** e = environ; *e; ++e)
            envText.emplace_back(*e);
        std::vector<char*> envp;
        for (const std::string& e : envText)
            envp.push_back(const_cast<char*>(e.c_str()));
        envp.push_back(nullptr);
        if (testrun::spawnToFiles(m_pid, argv, outFile.string(), errFile.string(), envp.data()) !=
            0)
            m_pid = -1;
    }
    Spawned(const Spawned&) = delete;
    Spawned& operator=(const Spawned&) = delete;
    ~Spawned() {
        if (m_pid > 0 && !m_reaped) {
            ::kill(m_pid, SIGKILL);
            wait();
        }
    }

    pid_t pid() const { return m_pid; }
    bool started() const { return m_pid > 0; }

    /// Waits for the exit; the wait status.
    int wait() {
        if (!m_reaped) {
            while (::waitpid(m_pid, &m_status, 0) < 0 && errno == EINTR) {
            }
            m_reaped = true;
        }
        return m_status;
    }

    /// True once the process has exited (reaps it).
    bool exited() {
        if (m_reaped)
            return true;
        const pid_t r = ::waitpid(m_pid, &m_status, WNOHANG);
        if (r == m_pid)
            m_reaped = true;
        return m_reaped;
    }

    void kill(int sig) const { ::kill(m_pid, sig); }

    /// Stops the process (SIGSTOP) and waits until it is stopped; false if it exited first.
    bool stop() {
        ::kill(m_pid, SIGSTOP);
        int status = 0;
        while (true) {
            const pid_t r = ::waitpid(m_pid, &status, WUNTRACED);
            if (r < 0 && errno == EINTR)
                continue;
            if (r == m_pid && WIFSTOPPED(status))
                return true;
            m_status = status;
            m_reaped = true;
            return false;
        }
    }

private:
    pid_t m_pid = -1;
    int m_status = 0;
    bool m_reaped = false;
};

/// Whether `pid` holds an open file descriptor on a file in `dir` other than `except` (its
/// path as /proc shows it: an unlinked O_TMPFILE file shows as "<dir>/#<inode> (deleted)").
inline bool holdsFileIn(pid_t pid, const fs::path& dir, const fs::path& except = {}) {
    std::error_code ec;
    const std::string prefix = fs::canonical(dir, ec).string() + "/";
    const std::string skip = except.empty() ? std::string() : fs::absolute(except).string();
    fs::directory_iterator it("/proc/" + std::to_string(pid) + "/fd", ec);
    if (ec)
        return false;
    for (const fs::directory_entry& e : it) {
        const fs::path target = fs::read_symlink(e.path(), ec);
        if (ec)
            continue;
        const std::string t = target.string();
        if (t.rfind(prefix, 0) == 0 && t != skip)
            return true;
    }
    return false;
}

/// Writes a UV sphere of `slices` x `stacks` quads (as triangles) as an OBJ file.
inline void writeSphereObj(const fs::path& path, double radius, int slices, int stacks) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    const double pi = 3.14159265358979323846;
    std::fprintf(f, "v 0 %.9g 0\n", radius);
    for (int i = 1; i < stacks; ++i) {
        const double phi = pi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double theta = 2.0 * pi * j / slices;
            std::fprintf(f, "v %.9g %.9g %.9g\n", radius * std::sin(phi) * std::cos(theta),
                         radius * std::cos(phi), radius * std::sin(phi) * std::sin(theta));
        }
    }
    std::fprintf(f, "v 0 %.9g 0\n", -radius);
    const int bottom = 2 + (stacks - 1) * slices; // 1-based index of the last vertex
    auto ring = [&](int i, int j) { return 2 + (i - 1) * slices + (j % slices); };
    for (int j = 0; j < slices; ++j)
        std::fprintf(f, "f 1 %d %d\n", ring(1, j + 1), ring(1, j));
    for (int i = 1; i + 1 < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            std::fprintf(f, "f %d %d %d\n", ring(i, j), ring(i, j + 1), ring(i + 1, j + 1));
            std::fprintf(f, "f %d %d %d\n", ring(i, j), ring(i + 1, j + 1), ring(i + 1, j));
        }
    for (int j = 0; j < slices; ++j)
        std::fprintf(f, "f %d %d %d\n", bottom, ring(stacks - 1, j), ring(stacks - 1, j + 1));
    std::fclose(f);
}

} // namespace sluice::reliability
