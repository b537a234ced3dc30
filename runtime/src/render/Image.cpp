// Row flipping for images read back from OpenGL.
#include "sluice/rt/render/Image.h"

#include <algorithm>

namespace sluice::rt {

void flipRows(std::uint8_t* data, std::size_t rowBytes, std::size_t rows) {
    for (std::size_t top = 0, bottom = rows; top + 1 < bottom; ++top) {
        --bottom;
        std::swap_ranges(data + top * rowBytes, data + (top + 1) * rowBytes,
                         data + bottom * rowBytes);
    }
}

} // namespace sluice::rt
