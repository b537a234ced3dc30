// Forked-child isolation for third-party parsers: the answer travels back through a pipe.
#include "sluice/bake/import/Isolated.h"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <exception>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <oneapi/tbb/global_control.h>

#include "sluice/bake/jobs/PhaseLog.h"
#include "sluice/format/support/Sanitizers.h"

namespace sluice::bake {

namespace {

// Wire format (host byte order: both ends are this process image):
//   u8 ok=1, u64 positions, u64 triangles, f64[3*positions], u32[3*triangles]
//   u8 ok=0, u32 error code, u64 detail length, detail bytes
template <class T> void put(std::vector<char>& out, const T& v) {
    const char* p = reinterpret_cast<const char*>(&v);
    out.insert(out.end(), p, p + sizeof(T));
}

std::vector<char> serialize(const Result<TriangleSoup>& r) {
    std::vector<char> out;
    if (r.ok()) {
        const TriangleSoup& s = r.value();
        put<std::uint8_t>(out, 1);
        put<std::uint64_t>(out, s.positions.size());
        put<std::uint64_t>(out, s.triangles.size());
        for (const glm::dvec3& p : s.positions)
            for (int a = 0; a < 3; ++a)
                put<double>(out, p[a]);
        for (const glm::uvec3& t : s.triangles)
            for (int a = 0; a < 3; ++a)
                put<std::uint32_t>(out, t[a]);
    } else {
        put<std::uint8_t>(out, 0);
        put<std::uint32_t>(out, static_cast<std::uint32_t>(r.error().code));
        put<std::uint64_t>(out, r.error().detail.size());
        out.insert(out.end(), r.error().detail.begin(), r.error().detail.end());
    }
    return out;
}

/// Reads a message produced by serialize(); false if it is incomplete or inconsistent.
class Reader {
public:
    explicit Reader(const std::vector<char>& bytes) : m_bytes(bytes) {}
    template <class T> bool get(T& v) {
        if (m_bytes.size() - m_pos < sizeof(T))
            return false;
        std::memcpy(&v, m_bytes.data() + m_pos, sizeof(T));
        m_pos += sizeof(T);
        return true;
    }
    std::size_t remaining() const { return m_bytes.size() - m_pos; }
    const char* cursor() const { return m_bytes.data() + m_pos; }

private:
    const std::vector<char>& m_bytes;
    std::size_t m_pos = 0;
};

bool deserialize(const std::vector<char>& bytes, Result<TriangleSoup>& out) {
    Reader in(bytes);
    std::uint8_t ok = 0;
    if (!in.get(ok))
        return false;
    if (ok == 0) {
        std::uint32_t code = 0;
        std::uint64_t len = 0;
        if (!in.get(code) || !in.get(len) || len != in.remaining() ||
            code > static_cast<std::uint32_t>(ErrorCode::Unsupported))
            return false;
        out = Error{static_cast<ErrorCode>(code), std::string(in.cursor(), len)};
        return true;
    }
    std::uint64_t np = 0, nt = 0;
    if (!in.get(np) || !in.get(nt))
        return false;
    // Both ends are us, but sizes are still checked before anything is allocated from them.
    if (np > in.remaining() / (3 * sizeof(double)) ||
        nt > in.remaining() / (3 * sizeof(std::uint32_t)) ||
        np * 3 * sizeof(double) + nt * 3 * sizeof(std::uint32_t) != in.remaining())
        return false;
    TriangleSoup soup;
    soup.positions.resize(np);
    soup.triangles.resize(nt);
    for (glm::dvec3& p : soup.positions)
        for (int a = 0; a < 3; ++a)
            in.get(p[a]);
    for (glm::uvec3& t : soup.triangles)
        for (int a = 0; a < 3; ++a)
            in.get(t[a]);
    out = std::move(soup);
    return true;
}

bool writeAll(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        data += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

/// The child's answer: its wall time [s] as a double, then the serialized result.
[[noreturn]] void childMain(int fd, const IsolationLimits& limits,
                            const std::function<Result<TriangleSoup>()>& work) {
    const auto start = std::chrono::steady_clock::now();
    const rlimit noCore{0, 0}; // a crash here is an answer, not something to debug
    ::setrlimit(RLIMIT_CORE, &noCore);
    if (limits.maxAddressSpaceBytes > 0 && !kAddressSanitizer) {
        const rlimit cap{limits.maxAddressSpaceBytes, limits.maxAddressSpaceBytes};
        ::setrlimit(RLIMIT_AS, &cap);
    }
    std::vector<char> message;
    try {
        message = serialize(work());
    } catch (const std::bad_alloc&) {
        message = serialize(Error{ErrorCode::SizeOverflow, "out of memory while importing"});
    } catch (const std::exception& e) {
        message =
            serialize(Error{ErrorCode::MeshImport, std::string("import failed: ") + e.what()});
    } catch (...) {
        message = serialize(Error{ErrorCode::MeshImport, "import failed (unknown exception)"});
    }
    const double seconds = secondsSince(start);
    const bool sent = writeAll(fd, reinterpret_cast<const char*>(&seconds), sizeof seconds) &&
                      writeAll(fd, message.data(), message.size());
    ::close(fd);
    ::_exit(sent ? 0 : 3);
}

std::string describeDeath(int status) {
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        const char* name = ::sigabbrev_np(sig);
        return std::string("crashed with SIG") + (name ? name : std::to_string(sig).c_str());
    }
    if (WIFEXITED(status))
        return "exited with status " + std::to_string(WEXITSTATUS(status)) + " without an answer";
    return "stopped without an answer";
}

/// The threads of this process (1 where /proc cannot tell).
std::size_t threadCount() {
    std::error_code ec;
    std::size_t count = 0;
    for (std::filesystem::directory_iterator it("/proc/self/task", ec), end; !ec && it != end;
         it.increment(ec))
        ++count;
    return std::max<std::size_t>(count, 1);
}

/// fork() copies only the calling thread. A thread that holds a lock of the memory allocator
/// (or of AddressSanitizer's thread registry, while it starts or ends) at that instant leaves
/// the child deadlocked in its first allocation; GCC 12's ASan allocator has no fork handlers.
/// Two libraries start threads of their own in sluice-bake:
/// - OpenVDB links log4cplus, whose library starts a pool of worker threads as it is loaded, so
///   every sluice-bake is multithreaded from its first instruction (about one import in 150
///   hung for good under ASan, found by CI). Nothing of ours logs through log4cplus: its pool
///   is stopped, once. Looked up at run time, so builds without log4cplus need nothing.
/// - TBB starts workers on the first parallel algorithm (OpenVDB reading a .vdb, the CGAL
///   path) and keeps them: `validate grid.vdb mesh.obj` forked beside them, and CI saw one such
///   validate hang until the test's timeout. Their scheduler is finalized before each fork,
///   which joins them; the next parallel algorithm starts new ones.
/// Then the threads still exiting (log4cplus's pool does not wait for its own) get time to go:
/// until one thread is left, the count has stood still for 20 ms (threads that stay, such as
/// an embedder's: a Python interpreter's BLAS pool), or a second has passed. The import's
/// timeout is what remains between a child forked beside such threads and a hang.
void stopLibraryThreads() {
    static std::once_flag once;
    std::call_once(once, [] {
        using Shutdown = void (*)();
        if (void* symbol = ::dlsym(RTLD_DEFAULT, "_ZN9log4cplus18shutdownThreadPoolEv"))
            reinterpret_cast<Shutdown>(symbol)();
    });
    tbb::task_scheduler_handle scheduler{tbb::attach{}};
    (void)tbb::finalize(scheduler, std::nothrow); // false while another thread runs TBB work
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    Clock::time_point changed = start;
    std::size_t threads = threadCount();
    while (threads > 1 && Clock::now() - start < std::chrono::seconds(1) &&
           Clock::now() - changed < std::chrono::milliseconds(20)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        if (const std::size_t now = threadCount(); now != threads) {
            threads = now;
            changed = Clock::now();
        }
    }
}

/// What the child wrote before it closed its end of the pipe or ran out of time.
struct ChildAnswer {
    std::vector<char> bytes;
    bool timedOut = false;
};

/// Reads the child's answer while it runs (it may write more than a pipe buffer holds), until
/// it closes the pipe or `deadline` passes.
ChildAnswer drainPipe(int fd, std::chrono::steady_clock::time_point deadline) {
    ChildAnswer answer;
    char buffer[1 << 16];
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            answer.timedOut = true;
            break;
        }
        pollfd pfd{fd, POLLIN, 0};
        const int ready =
            ::poll(&pfd, 1, static_cast<int>(std::min<long long>(left.count(), 1000)));
        if (ready < 0 && errno == EINTR)
            continue;
        if (ready <= 0)
            continue;
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break; // EOF: the child closed its end (finished or died)
        answer.bytes.insert(answer.bytes.end(), buffer, buffer + n);
    }
    return answer;
}

/// Waits for the child (killed first when it ran out of time) and returns its exit status;
/// `report`, if set, gets its wall time (the answer's first 8 bytes, taken off) and CPU time.
int reapChild(pid_t pid, ChildAnswer& answer, IsolationReport* report) {
    if (answer.timedOut)
        ::kill(pid, SIGKILL);
    int status = 0;
    rusage usage{};
    while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    double childSeconds = 0.0;
    std::vector<char>& bytes = answer.bytes;
    if (bytes.size() >= sizeof childSeconds) {
        std::memcpy(&childSeconds, bytes.data(), sizeof childSeconds);
        bytes.erase(bytes.begin(), bytes.begin() + sizeof childSeconds);
    }
    if (report) {
        report->wallSeconds = childSeconds;
        report->cpuSeconds = double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                             1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    }
    return status;
}

/// The import's result from the child's answer and exit status, or why there is none.
Result<TriangleSoup> childResult(const std::string& what, const IsolationLimits& limits,
                                 const ChildAnswer& answer, int status) {
    if (answer.timedOut)
        return fail(ErrorCode::MeshImport,
                    what + ": the importer did not finish within " +
                        std::to_string(limits.timeout.count() / 1000.0) +
                        " s and was stopped; the file is probably malformed");
    Result<TriangleSoup> result = Error{ErrorCode::MeshImport, {}};
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && deserialize(answer.bytes, result))
        return result;
    return fail(ErrorCode::MeshImport, what + ": the importer " + describeDeath(status) +
                                           " while reading it; the file is probably malformed");
}

} // namespace

void prepareForFork() {
    stopLibraryThreads();
}

Result<TriangleSoup> runIsolated(const std::string& what, const IsolationLimits& limits,
                                 const std::function<Result<TriangleSoup>()>& work,
                                 const std::function<void()>& meanwhile, IsolationReport* report) {
    stopLibraryThreads();
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
        return fail(ErrorCode::Io, what + ": cannot create a pipe for the import process (" +
                                       std::strerror(errno) + ")");
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int err = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        return fail(ErrorCode::Io,
                    what + ": cannot start the import process (" + std::strerror(err) + ")");
    }
    if (pid == 0) {
        ::close(fds[0]);
        childMain(fds[1], limits, work);
    }
    ::close(fds[1]);
    const auto deadline = std::chrono::steady_clock::now() + limits.timeout;
    // The child may fill the pipe and wait for the drain below meanwhile; that is all it costs.
    if (meanwhile)
        meanwhile();
    ChildAnswer answer = drainPipe(fds[0], deadline);
    ::close(fds[0]);
    const int status = reapChild(pid, answer, report);
    return childResult(what, limits, answer, status);
}

} // namespace sluice::bake
