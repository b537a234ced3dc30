// The renderer's pictures: format::Image (8-bit RGB, top row first) and its PNG writer.
#pragma once

#include "sluice/format/support/Image.h"

namespace sluice::rt {

using format::flipRows;
using format::Image;
using format::writePng;

} // namespace sluice::rt
