// Atomic replace-by-rename writes and size-bounded reads, on POSIX file descriptors.
#include "sluice/format/support/AtomicFile.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <optional>
#include <random>
#include <string>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

namespace sluice::format {

namespace {

std::string errnoText(int err) {
    return std::strerror(err);
}

// Closes a descriptor on scope exit unless released.
class Fd {
public:
    explicit Fd(int fd) : m_fd(fd) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() {
        if (m_fd >= 0)
            ::close(m_fd);
    }
    int get() const { return m_fd; }
    /// Closes now and reports the result (close can report a delayed write error).
    int close() {
        const int rc = ::close(m_fd);
        m_fd = -1;
        return rc;
    }

private:
    int m_fd;
};

bool writeAll(int fd, const std::byte* data, std::size_t size, int& err) {
    while (size > 0) {
        // Bounded chunks: Linux writes at most ~2 GiB per call anyway.
        const std::size_t chunk = size < (std::size_t(1) << 30) ? size : (std::size_t(1) << 30);
        const ssize_t n = ::write(fd, data, chunk);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            err = errno;
            return false;
        }
        if (n == 0) {
            err = EIO;
            return false;
        }
        data += n;
        size -= std::size_t(n);
    }
    return true;
}

std::filesystem::path uniqueTempName(const std::filesystem::path& target) {
    static std::atomic<std::uint64_t> s_counter{0};
    static thread_local std::mt19937_64 s_rng{std::random_device{}()};
    const std::uint64_t n = s_counter.fetch_add(1, std::memory_order_relaxed);
    // Appended piecewise: GCC 12 at -O3 warns falsely (-Wrestrict) on chained string `+`.
    std::string name = ".";
    name.append(target.filename().string());
    name.append(".tmp-");
    name.append(std::to_string(::getpid()));
    name.append("-");
    name.append(std::to_string(n));
    name.append("-");
    name.append(std::to_string(s_rng() & 0xFFFFFFFFu));
    return target.parent_path() / name;
}

/// The folder `path` is in ("." for a bare file name).
std::filesystem::path folderOf(const std::filesystem::path& path) {
    return path.parent_path().empty() ? "." : path.parent_path();
}

/// The writer's process id in a name uniqueTempName gave for `target`, or 0 if `name` is not
/// one.
pid_t tempNameWriter(const std::string& name, const std::filesystem::path& target) {
    const std::string prefix = "." + target.filename().string() + ".tmp-";
    if (name.compare(0, prefix.size(), prefix) != 0)
        return 0;
    pid_t pid = 0;
    std::size_t i = prefix.size();
    for (; i < name.size() && name[i] >= '0' && name[i] <= '9' && pid < (1 << 24); ++i)
        pid = pid * 10 + (name[i] - '0');
    return i < name.size() && name[i] == '-' ? pid : 0;
}

/// Removes the temporary files of `path` that writers no longer running left behind: a writer
/// killed between naming its complete file and renaming it, or (without O_TMPFILE) while
/// writing. A name whose process still runs, this one included, is left alone: it may be a
/// write in flight. Best effort: a folder that cannot be read is left as it is.
void removeStaleTemporaries(const std::filesystem::path& path) {
    const std::filesystem::path folder = folderOf(path);
    std::error_code ec;
    std::filesystem::directory_iterator it(folder, ec);
    for (; !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
        const pid_t writer = tempNameWriter(it->path().filename().string(), path);
        if (writer <= 0 || writer == ::getpid())
            continue;
        if (::kill(writer, 0) != 0 && errno == ESRCH)
            ::unlink(it->path().c_str());
    }
}

/// Makes a rename in `path`'s folder durable. Best effort: the data is already in place.
void syncFolder(const std::filesystem::path& path) {
    const std::filesystem::path folder = folderOf(path);
    const int dirFd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        ::fsync(dirFd);
        ::close(dirFd);
    }
}

/// The last steps of both ways of writing: closes `file` (its bytes are written and fsync'd),
/// renames `temp` over `path`, makes the rename durable and removes what killed writers of
/// `path` left. On failure `temp` is removed and `path` is as it was.
Result<void> closeAndReplace(Fd& file, const std::filesystem::path& temp,
                             const std::filesystem::path& path) {
    if (file.close() != 0) {
        const int err = errno;
        ::unlink(temp.c_str());
        return fail(ErrorCode::Io, path.string() + ": close failed: " + errnoText(err) +
                                       " (the previous file, if any, is unchanged)");
    }
    if (::rename(temp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        ::unlink(temp.c_str());
        return fail(ErrorCode::Io, path.string() + ": cannot replace it: " + errnoText(err) +
                                       " (the previous file, if any, is unchanged)");
    }
    syncFolder(path);
    removeStaleTemporaries(path);
    return {};
}

/// The first choice of writeFileAtomic: the bytes go to an unnamed file in the target's folder
/// (O_TMPFILE), which gets a temporary name only once it is complete and fsync'd, and is then
/// renamed over the target. A writer killed while writing (SIGKILL, power loss) leaves no file
/// behind: the unnamed one vanishes with its descriptor. Empty when this file system or kernel
/// has no O_TMPFILE, or /proc is missing for the link: the caller writes a named file then.
std::optional<Result<void>> writeUnnamedThenRename(const std::filesystem::path& path,
                                                   std::span<const std::byte> bytes) {
    const std::filesystem::path folder = folderOf(path);
    const int fd = ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (fd < 0)
        return std::nullopt;
    Fd file(fd);
    int err = 0;
    if (!writeAll(file.get(), bytes.data(), bytes.size(), err))
        return fail(ErrorCode::Io, path.string() + ": write failed: " + errnoText(err) +
                                       " (the previous file, if any, is unchanged)");
    if (::fsync(file.get()) != 0)
        return fail(ErrorCode::Io, path.string() + ": fsync failed: " + errnoText(errno) +
                                       " (the previous file, if any, is unchanged)");
    // linkat(AT_EMPTY_PATH) needs a capability; the /proc link of the descriptor does not.
    const std::string procPath = "/proc/self/fd/" + std::to_string(file.get());
    std::filesystem::path temp;
    int linked = -1;
    for (int attempt = 0; attempt < 16 && linked != 0; ++attempt) {
        temp = uniqueTempName(path);
        linked = ::linkat(AT_FDCWD, procPath.c_str(), AT_FDCWD, temp.c_str(), AT_SYMLINK_FOLLOW);
        if (linked != 0 && errno != EEXIST && errno != EINTR)
            return std::nullopt;
    }
    if (linked != 0)
        return std::nullopt;
    return closeAndReplace(file, temp, path);
}

} // namespace

Result<void> writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes) {
    if (path.filename().empty())
        return fail(ErrorCode::InvalidArgument,
                    path.string() + ": not a file path (it names no file)");

    if (std::optional<Result<void>> done = writeUnnamedThenRename(path, bytes))
        return std::move(*done);

    // No unnamed files here: a named temporary file, which a writer killed mid-write leaves
    // behind. O_EXCL makes the name ours alone; retry on the (unlikely) collision.
    std::filesystem::path temp;
    int fd = -1;
    for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
        temp = uniqueTempName(path);
        fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST && errno != EINTR)
            break;
    }
    if (fd < 0)
        return fail(ErrorCode::Io,
                    path.string() +
                        ": cannot create a temporary file in its folder: " + errnoText(errno));
    Fd file(fd);

    // From here on every failure removes the temporary file; the target is untouched until
    // the rename, which either happens whole or not at all.
    auto abandon = [&](const std::string& what, int err) -> Error {
        file.close();
        ::unlink(temp.c_str());
        return fail(ErrorCode::Io, path.string() + ": " + what + ": " + errnoText(err) +
                                       " (the previous file, if any, is unchanged)");
    };

    int err = 0;
    if (!writeAll(file.get(), bytes.data(), bytes.size(), err))
        return abandon("write failed", err);
    if (::fsync(file.get()) != 0)
        return abandon("fsync failed", errno);
    return closeAndReplace(file, temp, path);
}

Result<std::vector<std::byte>> readFileBytes(const std::filesystem::path& path,
                                             std::uint64_t maxBytes) {
    Fd file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (file.get() < 0)
        return fail(ErrorCode::Io, path.string() + ": cannot open: " + errnoText(errno));
    struct stat st {};
    if (::fstat(file.get(), &st) != 0)
        return fail(ErrorCode::Io, path.string() + ": cannot stat: " + errnoText(errno));
    if (!S_ISREG(st.st_mode))
        return fail(ErrorCode::Io, path.string() + ": not a regular file");
    const auto size = std::uint64_t(st.st_size);
    if (size > maxBytes)
        return fail(ErrorCode::SizeOverflow,
                    path.string() + ": " + std::to_string(size) + " bytes, more than the " +
                        std::to_string(maxBytes) + " allowed for this kind of file");

    std::vector<std::byte> bytes(static_cast<std::size_t>(size));
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::read(file.get(), bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return fail(ErrorCode::Io, path.string() + ": read failed: " + errnoText(errno));
        }
        if (n == 0)
            return fail(ErrorCode::Truncated, path.string() + ": file shrank while being read (" +
                                                  std::to_string(done) + " of " +
                                                  std::to_string(size) + " bytes)");
        done += std::size_t(n);
    }
    return bytes;
}

} // namespace sluice::format
