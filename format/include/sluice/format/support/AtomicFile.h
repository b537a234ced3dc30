// Whole-file writes that replace the target atomically, and bounded whole-file reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "sluice/format/support/Result.h"

namespace sluice::format {

/// Writes `bytes` to `path` atomically: the bytes go to an unnamed file in the same folder
/// (O_TMPFILE), which is fsync'd, linked under a unique temporary name
/// (".<name>.tmp-<pid>-<n>-<random>") and renamed over `path`; the folder is fsync'd after the
/// rename. Readers see either the old file or the whole new one, never a mix. A writer killed
/// while writing (SIGKILL, power loss) leaves no file behind, but in the two system calls
/// between the link and the rename, where it leaves the complete temporary file. Where the file
/// system has no unnamed files, the bytes go to the named temporary file directly, which a
/// writer killed at any moment before the rename leaves. A successful write removes the
/// temporary files of `path` whose writer no longer runs (its process id names no process).
/// On any failure (folder missing or not writable, disk full, `path` is a folder, ...) the
/// temporary file is removed, `path` is left as it was, and Io is returned naming the path and
/// the system's reason. The new file gets mode 0666 minus the umask; a symbolic link at `path`
/// is replaced by the file, not followed. InvalidArgument if `path` names no file (empty, or
/// ends in a separator).
Result<void> writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes);

/// Reads a whole regular file. The size is checked against `maxBytes` before anything is
/// allocated: a larger file returns SizeOverflow. Io if it cannot be opened or read, or is not a
/// regular file; Truncated if it shrank while being read.
Result<std::vector<std::byte>> readFileBytes(const std::filesystem::path& path,
                                             std::uint64_t maxBytes);

} // namespace sluice::format
