// An 8-bit RGB picture in memory, top row first, and its PNG file: what the renderer reads back,
// the capture code writes, and the baker's slice pictures are.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

#include "sluice/format/support/Result.h"

namespace sluice::format {

/// width x height pixels of 3 bytes (R, G, B), rows top to bottom, no padding.
struct Image {
    std::uint32_t width = 0;  ///< [pixels]
    std::uint32_t height = 0; ///< [pixels]
    std::vector<std::uint8_t> rgb;

    /// A black image of this size.
    static Image blank(std::uint32_t width, std::uint32_t height) {
        return {width, height, std::vector<std::uint8_t>(std::size_t(width) * height * 3, 0)};
    }
    bool empty() const { return width == 0 || height == 0; }
    /// Pixel (x, y), y counted from the top. Precondition: inside the image.
    glm::u8vec3 at(std::uint32_t x, std::uint32_t y) const {
        const std::size_t i = (std::size_t(y) * width + x) * 3;
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

/// Reverses the row order of `rows` rows of `rowBytes` bytes in place (OpenGL reads bottom row
/// first; images are stored top row first).
void flipRows(std::uint8_t* data, std::size_t rowBytes, std::size_t rows);

/// Encodes `image` as an 8-bit RGB PNG and writes it atomically (a temporary file in the same
/// folder, then a rename). InvalidArgument for an empty or malformed image, Io naming the path
/// when it cannot be encoded or written. The encoder (stb_image_write) is compiled into this
/// library, so users of it need no stb headers.
Result<void> writePng(const std::filesystem::path& path, const Image& image);

} // namespace sluice::format
