// PNG files of rendered frames, written atomically.
#pragma once

#include <filesystem>

#include "sluice/format/Result.h"
#include "sluice/rt/render/Image.h"

namespace sluice::rt {

/// Encodes `image` as an 8-bit RGB PNG and writes it atomically (a temporary file in the same
/// folder, then a rename). InvalidArgument for an empty or malformed image, Io naming the path
/// when it cannot be written.
Result<void> writePng(const std::filesystem::path& path, const Image& image);

} // namespace sluice::rt
