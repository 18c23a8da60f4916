// PNG writers (libpng; native only, outside the portable core). Rows top row first, 1..4
// channels. Throw std::runtime_error naming the file on failure.
#pragma once

#include "hv/image/image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hv {

void writePng(const std::string& path, const Image8& image);
void writePng16(const std::string& path, const Image16& image);
// The PNG file of an 8-bit image, in memory (for archives: OpenRaster layers). Throws
// std::runtime_error naming `nameForErrors`.
std::vector<std::uint8_t> encodePng(const Image8& image, const std::string& nameForErrors);

}  // namespace hv
