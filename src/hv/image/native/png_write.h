// PNG writers (libpng; native only, outside the portable core). Rows top row first, 1..4
// channels. Throw std::runtime_error naming the file on failure.
#pragma once

#include "hv/image/image.h"

#include <string>

namespace hv {

void writePng(const std::string& path, const Image8& image);
void writePng16(const std::string& path, const Image16& image);

}  // namespace hv
