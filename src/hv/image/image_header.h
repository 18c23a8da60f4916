// What an image file's header says about it, for messages (hv/image/image_io.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace hv {

// Why the decoder refuses a JPEG or PNG, from its header, in words ("a 12-bit JPEG: ..."), or ""
// when the header says nothing against it: stb_image itself answers "unknown image type" for a
// PNG larger than it takes, a 0x0 one, 12-bit, arithmetic-coded, lossless and hierarchical JPEGs.
std::string undecodableReason(const std::uint8_t* bytes, size_t size);

}  // namespace hv
