// A disk cache of linked compute programs as driver binaries, so a later process skips compiling.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Program.h"

namespace sluice::gpu {

/// Whether and where ProgramCache keeps its files.
struct ProgramCacheOptions {
    /// false: compile every program (as does SLUICE_PROGRAM_CACHE=0 in the environment).
    bool enabled = true;
    /// Folder of the cache files; empty: $XDG_CACHE_HOME/sluice, else $HOME/.cache/sluice.
    std::filesystem::path dir;
};

/// What a ProgramCache did in this process.
struct ProgramCacheStats {
    std::uint32_t hits = 0;     ///< programs loaded from a cache file
    std::uint32_t misses = 0;   ///< programs compiled (no file, or a rejected one)
    std::uint32_t stored = 0;   ///< cache files written
    std::uint32_t rejected = 0; ///< cache files ignored: damaged, foreign, or refused by the driver
};

/// Linked compute programs cached on disk as the driver's binaries (glGetProgramBinary), one
/// file per program, named by the XXH3-64 of the shader text handed to the compiler and the
/// driver's identity (GL_VENDOR, GL_RENDERER, GL_VERSION, GL_SHADING_LANGUAGE_VERSION): a new
/// shader, driver or GPU makes new files and never reads old ones. A file holds a magic, its key,
/// the binary format, the size and an XXH3-64 of the binary; a file that fails any check, or
/// that the driver refuses, is ignored and replaced, and compiling proceeds as without a cache.
/// Files are written under a temporary name and renamed (not fsync'd: a damaged file is only
/// compiled again), so processes may share the folder.
/// The cache is off when asked, when the folder cannot be made, or when the driver offers no
/// binary format (GL_NUM_PROGRAM_BINARY_FORMATS = 0); compute() then just compiles. Needs the
/// context it was opened with to be current.
class ProgramCache {
public:
    /// For the current context. Never fails: a cache that cannot work is off, with the reason.
    static ProgramCache open(const ProgramCacheOptions& options = {});

    /// Program::compute, through the cache. Errors: those of Program::compute.
    Result<Program> compute(std::string_view name, std::string_view source,
                            std::span<const ShaderDefine> defines = {});

    bool enabled() const { return m_enabled; }
    /// Why the cache is off ("disabled by SLUICE_PROGRAM_CACHE=0", ...); empty when it is on.
    const std::string& offReason() const { return m_offReason; }
    const std::filesystem::path& dir() const { return m_dir; }
    /// GL_NUM_PROGRAM_BINARY_FORMATS of the context.
    int binaryFormats() const { return m_binaryFormats; }
    const ProgramCacheStats& stats() const { return m_stats; }
    /// The file that holds (or would hold) the program of this shader text on this driver.
    std::filesystem::path fileFor(std::string_view source,
                                  std::span<const ShaderDefine> defines = {}) const;

private:
    bool m_enabled = false;
    std::string m_offReason;
    std::filesystem::path m_dir;
    int m_binaryFormats = 0;
    std::string m_driver; ///< the driver's identity, part of every key
    ProgramCacheStats m_stats;
};

} // namespace sluice::gpu
