// ffmpeg as a child process (posix_spawn, no shell): raw RGB frames on its stdin, its messages
// in a log file beside the video, the MP4 renamed into place when it exits cleanly.
#include "capture/CaptureVideo.h"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace sluice::rt {
namespace fs = std::filesystem;
namespace {

bool isExecutableFile(const fs::path& path) {
    std::error_code ec;
    return fs::is_regular_file(path, ec) && ::access(path.c_str(), X_OK) == 0;
}

std::string fpsText(double fps) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", fps);
    return text;
}

} // namespace

Result<fs::path> findFfmpeg() {
    if (const char* env = std::getenv("SLUICE_FFMPEG"); env != nullptr && *env != '\0') {
        if (isExecutableFile(env))
            return fs::path(env);
        return fail(ErrorCode::Unsupported,
                    std::string("SLUICE_FFMPEG=") + env +
                        " is not an executable program (unset it to use ffmpeg from PATH)");
    }
    const char* pathVar = std::getenv("PATH");
    const std::string dirs = pathVar != nullptr ? pathVar : "";
    std::size_t begin = 0;
    while (begin <= dirs.size()) {
        const std::size_t end = std::min(dirs.find(':', begin), dirs.size());
        const std::string dir = dirs.substr(begin, end - begin);
        const fs::path candidate = fs::path(dir.empty() ? "." : dir) / "ffmpeg";
        if (isExecutableFile(candidate))
            return candidate;
        begin = end + 1;
    }
    return fail(ErrorCode::Unsupported,
                "ffmpeg was not found on PATH; video capture needs it "
                "(Debian: apt-get install ffmpeg, or set SLUICE_FFMPEG to the program)");
}

Result<VideoEncoder> VideoEncoder::start(const fs::path& path, glm::uvec2 size, double fps) {
    auto ffmpeg = findFfmpeg();
    if (!ffmpeg)
        return ffmpeg.error();
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(folder, ec) || !path.has_filename())
        return fail(ErrorCode::Io, "cannot write the video " + path.string() + ": " +
                                       folder.string() + " is not a folder");
    VideoEncoder encoder;
    const std::string tag = "." + path.filename().string() + "-" + std::to_string(::getpid());
    encoder.m_path = path;
    encoder.m_temp = folder / (tag + ".tmp.mp4");
    encoder.m_log = folder / (tag + ".ffmpeg.log");
    encoder.m_size = size;

    const std::string sizeText = std::to_string(size.x) + "x" + std::to_string(size.y);
    const std::string rate = fpsText(fps);
    std::vector<std::string> args = {
        ffmpeg->string(), "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt",
        "rgb24", "-s", sizeText, "-framerate", rate, "-i", "pipe:0", "-an",
        // yuv420p needs even sizes: pad odd ones by a pixel.
        "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-preset", "fast", "-crf", "20",
        "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4", encoder.m_temp.string()};
    std::vector<char*> argv;
    for (std::string& arg : args)
        argv.push_back(arg.data());
    argv.push_back(nullptr);

    int fds[2] = {-1, -1};
    if (::pipe2(fds, O_CLOEXEC) != 0)
        return fail(ErrorCode::Io,
                    std::string("cannot create a pipe to ffmpeg: ") + std::strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, encoder.m_log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t defaults;
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGPIPE);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    // Its own process group: a Ctrl-C at the terminal reaches sluice-play only, which then
    // finishes the video properly (Interrupt.h) instead of finding ffmpeg gone.
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
    pid_t pid = -1;
    const int rc = ::posix_spawn(&pid, ffmpeg->c_str(), &actions, &attr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    ::close(fds[0]);
    if (rc != 0) {
        ::close(fds[1]);
        fs::remove(encoder.m_log, ec);
        return fail(ErrorCode::Io, "cannot start " + ffmpeg->string() + ": " + std::strerror(rc));
    }
    // A dead ffmpeg must give write() an EPIPE error, not kill this process.
    std::signal(SIGPIPE, SIG_IGN);
    encoder.m_pipe = fds[1];
    encoder.m_pid = pid;
    return encoder;
}

VideoEncoder::VideoEncoder(VideoEncoder&& other) noexcept
    : m_path(std::move(other.m_path)), m_temp(std::move(other.m_temp)),
      m_log(std::move(other.m_log)), m_size(other.m_size), m_pipe(std::exchange(other.m_pipe, -1)),
      m_pid(std::exchange(other.m_pid, -1)), m_frames(other.m_frames) {
    other.m_temp.clear();
    other.m_log.clear();
}

VideoEncoder& VideoEncoder::operator=(VideoEncoder&& other) noexcept {
    if (this != &other) {
        release();
        m_path = std::move(other.m_path);
        m_temp = std::move(other.m_temp);
        m_log = std::move(other.m_log);
        m_size = other.m_size;
        m_pipe = std::exchange(other.m_pipe, -1);
        m_pid = std::exchange(other.m_pid, -1);
        m_frames = other.m_frames;
        other.m_temp.clear();
        other.m_log.clear();
    }
    return *this;
}

VideoEncoder::~VideoEncoder() {
    release();
}

void VideoEncoder::release() {
    if (m_pid > 0)
        stop();
    // Unfinished (or failed): nothing of it stays. After finish() both are gone already.
    std::error_code ec;
    if (!m_temp.empty())
        fs::remove(m_temp, ec);
    if (!m_log.empty())
        fs::remove(m_log, ec);
    m_temp.clear();
    m_log.clear();
}

int VideoEncoder::stop() {
    if (m_pipe >= 0)
        ::close(m_pipe);
    m_pipe = -1;
    int status = 0;
    pid_t waited = -1;
    do {
        waited = ::waitpid(m_pid, &status, 0);
    } while (waited < 0 && errno == EINTR);
    m_pid = -1;
    return waited > 0 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string VideoEncoder::logTail() const {
    std::ifstream in(m_log, std::ios::binary);
    std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r'))
        text.pop_back();
    if (text.size() > 800)
        text = "..." + text.substr(text.size() - 800);
    return text.empty() ? "(ffmpeg printed nothing)" : text;
}

Result<void> VideoEncoder::write(const Image& frame) {
    SLUICE_ASSERT(frame.width == m_size.x && frame.height == m_size.y,
                  "VideoEncoder::write: frame size differs from the video's");
    SLUICE_ASSERT(m_pipe >= 0, "VideoEncoder::write after finish()");
    const std::uint8_t* data = frame.rgb.data();
    std::size_t left = frame.rgb.size();
    while (left > 0) {
        const ssize_t n = ::write(m_pipe, data, left);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            const int code = stop();
            return fail(ErrorCode::Io, "ffmpeg stopped taking frames for " + m_path.string() +
                                           " (exit " + std::to_string(code) + "): " + logTail());
        }
        data += n;
        left -= std::size_t(n);
    }
    ++m_frames;
    return {};
}

Result<void> VideoEncoder::finish() {
    if (m_pid <= 0)
        return fail(ErrorCode::Io, "ffmpeg stopped before " + m_path.string() + " was complete");
    const int code = stop();
    std::error_code ec;
    if (code != 0 || !fs::exists(m_temp, ec)) {
        const std::string why = logTail();
        fs::remove(m_temp, ec);
        fs::remove(m_log, ec);
        return fail(ErrorCode::Io, "ffmpeg could not write " + m_path.string() + " (exit " +
                                       std::to_string(code) + "): " + why);
    }
    fs::rename(m_temp, m_path, ec);
    std::error_code ignored;
    fs::remove(m_log, ignored);
    if (ec) {
        fs::remove(m_temp, ignored);
        return fail(ErrorCode::Io,
                    "cannot move the video into place at " + m_path.string() + ": " + ec.message());
    }
    return {};
}

} // namespace sluice::rt
