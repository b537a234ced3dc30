// Row flipping for images read back from OpenGL, and PNG files through stb_image_write (Debian's
// libstb) encoded into memory, then written atomically.
#include "sluice/format/support/Image.h"

#include <algorithm>
#include <span>
#include <string>

// The encoder is compiled into this file with internal linkage, so the library (and its
// installed package) needs the header at build time only, and no libstb at link time.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include "sluice/format/support/AtomicFile.h"

namespace sluice::format {

void flipRows(std::uint8_t* data, std::size_t rowBytes, std::size_t rows) {
    for (std::size_t top = 0, bottom = rows; top + 1 < bottom; ++top) {
        --bottom;
        std::swap_ranges(data + top * rowBytes, data + (top + 1) * rowBytes,
                         data + bottom * rowBytes);
    }
}

Result<void> writePng(const std::filesystem::path& path, const Image& image) {
    if (image.empty() || image.rgb.size() != std::size_t(image.width) * image.height * 3)
        return fail(ErrorCode::InvalidArgument,
                    "cannot write " + path.string() + ": the image is empty or malformed");
    std::vector<std::byte> png;
    auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<std::byte>*>(context);
        const auto* bytes = static_cast<const std::byte*>(data);
        out->insert(out->end(), bytes, bytes + size);
    };
    const int ok = stbi_write_png_to_func(append, &png, int(image.width), int(image.height), 3,
                                          image.rgb.data(), int(image.width) * 3);
    if (ok == 0 || png.empty())
        return fail(ErrorCode::Io, "cannot encode the PNG for " + path.string());
    return writeFileAtomic(path, std::span<const std::byte>(png));
}

} // namespace sluice::format
