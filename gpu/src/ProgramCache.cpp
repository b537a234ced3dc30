// The program binary cache: keyed files of glGetProgramBinary output, checked before use.
//
// File layout (little-endian, as every Sluice file):
//   0  8  magic  "SLCPROG" 0x01
//   8  8  key    XXH3-64 of the driver identity and the shader text (also the file's name)
//  16  4  format the driver's binary format (GLenum)
//  20  4  zero
//  24  8  size   of the binary [bytes]; the file is 40 + size bytes
//  32  8  hash   XXH3-64 of the binary
//  40     the binary
#include "sluice/gpu/ProgramCache.h"

#include <array>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "sluice/format/support/AtomicFile.h" // readFileBytes
#include "sluice/format/support/Hash.h"

namespace sluice::gpu {
namespace {

constexpr std::array<char, 8> kMagic = {'S', 'L', 'C', 'P', 'R', 'O', 'G', '\x01'};
constexpr std::size_t kHeaderBytes = 40;
/// Larger files are not cache files of ours (a compute binary is kilobytes to a few megabytes).
constexpr std::uint64_t kMaxFileBytes = std::uint64_t(256) << 20;

std::string glString(GLenum name) {
    const auto* text = reinterpret_cast<const char*>(glGetString(name));
    return text != nullptr ? text : "";
}

/// The folder of the cache files by the XDG base directory rules; empty if there is no home.
std::filesystem::path defaultDir() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && xdg[0] == '/')
        return std::filesystem::path(xdg) / "sluice";
    if (const char* home = std::getenv("HOME"); home != nullptr && home[0] != '\0')
        return std::filesystem::path(home) / ".cache" / "sluice";
    return {};
}

bool disabledByEnvironment() {
    const char* value = std::getenv("SLUICE_PROGRAM_CACHE");
    if (value == nullptr)
        return false;
    const std::string text(value);
    return text == "0" || text == "off" || text == "false" || text == "no";
}

template <class T> void put(std::vector<std::byte>& out, std::size_t offset, T value) {
    std::memcpy(out.data() + offset, &value, sizeof(T));
}
template <class T> T get(const std::vector<std::byte>& in, std::size_t offset) {
    T value;
    std::memcpy(&value, in.data() + offset, sizeof(T));
    return value;
}

std::uint64_t keyOf(const std::string& driver, const std::string& text) {
    std::string keyed = driver;
    keyed += '\0';
    keyed += text;
    return format::xxh3(std::as_bytes(std::span(keyed.data(), keyed.size())));
}

/// The binary a cache file holds, or why it is not usable.
Result<ProgramBinary> parse(const std::vector<std::byte>& file, std::uint64_t key) {
    if (file.size() < kHeaderBytes)
        return fail(ErrorCode::Truncated, "shorter than its header");
    if (std::memcmp(file.data(), kMagic.data(), kMagic.size()) != 0)
        return fail(ErrorCode::BadMagic, "not a program cache file");
    if (get<std::uint64_t>(file, 8) != key)
        return fail(ErrorCode::BadHeader, "made for another shader or driver");
    const auto size = get<std::uint64_t>(file, 24);
    if (size != file.size() - kHeaderBytes)
        return fail(ErrorCode::SizeMismatch, "its size does not match its header");
    ProgramBinary binary;
    binary.format = get<std::uint32_t>(file, 16);
    binary.bytes.assign(file.begin() + kHeaderBytes, file.end());
    if (format::xxh3(binary.bytes) != get<std::uint64_t>(file, 32))
        return fail(ErrorCode::ChecksumMismatch, "its checksum does not match");
    return binary;
}

std::vector<std::byte> serialize(const ProgramBinary& binary, std::uint64_t key) {
    std::vector<std::byte> file(kHeaderBytes + binary.bytes.size());
    std::memcpy(file.data(), kMagic.data(), kMagic.size());
    put<std::uint64_t>(file, 8, key);
    put<std::uint32_t>(file, 16, binary.format);
    put<std::uint32_t>(file, 20, 0);
    put<std::uint64_t>(file, 24, binary.bytes.size());
    put<std::uint64_t>(file, 32, format::xxh3(binary.bytes));
    if (!binary.bytes.empty())
        std::memcpy(file.data() + kHeaderBytes, binary.bytes.data(), binary.bytes.size());
    return file;
}

/// Writes `bytes` to a temporary file beside `path` and renames it over `path`, so readers see
/// the old file or the whole new one. Unlike format::writeFileAtomic nothing is fsync'd (five
/// fsyncs cost more than compiling on some disks): a file a crash left short or empty fails
/// parse() and is compiled again. False when anything fails; the temporary file is removed.
bool writeCacheFile(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
    static std::atomic<unsigned> counter{0};
    const std::filesystem::path temporary =
        path.parent_path() / ("." + path.filename().string() + ".tmp-" +
                              std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::error_code ec;
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        if (out.close(), !out) {
            std::filesystem::remove(temporary, ec);
            return false;
        }
    }
    std::filesystem::rename(temporary, path, ec);
    if (ec)
        std::filesystem::remove(temporary, ec);
    return !ec;
}

} // namespace

ProgramCache ProgramCache::open(const ProgramCacheOptions& options) {
    ProgramCache cache;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &cache.m_binaryFormats);
    cache.m_driver = glString(GL_VENDOR) + '\n' + glString(GL_RENDERER) + '\n' +
                     glString(GL_VERSION) + '\n' + glString(GL_SHADING_LANGUAGE_VERSION);
    cache.m_dir = options.dir.empty() ? defaultDir() : options.dir;
    if (!options.enabled)
        cache.m_offReason = "disabled by the caller";
    else if (disabledByEnvironment())
        cache.m_offReason = "disabled by SLUICE_PROGRAM_CACHE=0";
    else if (cache.m_binaryFormats <= 0)
        cache.m_offReason = "the driver offers no program binary format";
    else if (cache.m_dir.empty())
        cache.m_offReason = "no cache folder: neither XDG_CACHE_HOME nor HOME is set";
    if (!cache.m_offReason.empty())
        return cache;
    std::error_code ec;
    std::filesystem::create_directories(cache.m_dir, ec);
    if (!std::filesystem::is_directory(cache.m_dir, ec)) {
        cache.m_offReason = "cannot create the folder " + cache.m_dir.string();
        return cache;
    }
    cache.m_enabled = true;
    return cache;
}

std::filesystem::path ProgramCache::fileFor(std::string_view source,
                                            std::span<const ShaderDefine> defines) const {
    const std::uint64_t key = keyOf(m_driver, assembleShaderSource(source, defines));
    return m_dir / (format::hex64(key) + ".glprog");
}

Result<Program> ProgramCache::compute(std::string_view name, std::string_view source,
                                      std::span<const ShaderDefine> defines) {
    if (!m_enabled)
        return Program::compute(name, source, defines);
    const std::uint64_t key = keyOf(m_driver, assembleShaderSource(source, defines));
    const std::filesystem::path path = m_dir / (format::hex64(key) + ".glprog");
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) {
        Result<std::vector<std::byte>> file = format::readFileBytes(path, kMaxFileBytes);
        Result<ProgramBinary> binary =
            file ? parse(*file, key) : Result<ProgramBinary>(file.error());
        if (binary) {
            if (Result<Program> program = Program::computeFromBinary(name, *binary); program) {
                ++m_stats.hits;
                return program;
            }
        }
        ++m_stats.rejected; // compiled below and written over
    }
    ++m_stats.misses;
    Result<Program> program = Program::compute(name, source, defines, true);
    if (!program)
        return program;
    const ProgramBinary binary = program->binary();
    // A cache that cannot be written is only slower: the program is good either way.
    if (!binary.bytes.empty() && writeCacheFile(path, serialize(binary, key)))
        ++m_stats.stored;
    return program;
}

} // namespace sluice::gpu
