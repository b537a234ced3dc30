// PNG encoding with stb_image_write (Debian's libstb) into memory, then an atomic write.
#include "CapturePng.h"

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include "sluice/format/AtomicFile.h"

namespace sluice::rt {

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
    return format::writeFileAtomic(path, std::span<const std::byte>(png));
}

} // namespace sluice::rt
