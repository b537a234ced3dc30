// XXH3-64 content hashes: checksums inside assets and source-mesh hashes for provenance.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "sluice/format/support/Result.h"

namespace sluice::format {

/// XXH3-64 (seed 0) of `bytes`; the same value `xxhsum -H3` prints.
std::uint64_t xxh3(std::span<const std::byte> bytes);

/// `value` as 16 lowercase hex digits, most significant first ("7e13095f1588691d").
std::string hex64(std::uint64_t value);

/// XXH3-64 of a file's bytes as 16 lowercase hex digits, read in fixed-size chunks (any file
/// size, constant memory). Io if the file cannot be opened or read.
Result<std::string> hashFileHex(const std::filesystem::path& path);

} // namespace sluice::format
