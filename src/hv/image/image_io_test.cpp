#include "hv/image/image.h"

#include "hv/util/diagnostics.h"
#include "hv/image/image_header.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace hv {
namespace {

using Bytes = std::vector<std::uint8_t>;

void put32(Bytes& b, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(std::uint8_t(v >> s));
}

// A PNG signature and IHDR chunk (the CRC is not checked before the size is), then an empty IDAT
// and IEND: enough for the header probe.
Bytes png(std::uint32_t w, std::uint32_t h, std::uint8_t depth = 8) {
  Bytes b = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  put32(b, 13);
  for (char c : std::string("IHDR")) b.push_back(std::uint8_t(c));
  put32(b, w);
  put32(b, h);
  for (std::uint8_t v : {depth, std::uint8_t(2), std::uint8_t(0), std::uint8_t(0), std::uint8_t(0)}) b.push_back(v);
  put32(b, 0);  // CRC
  put32(b, 0);
  for (char c : std::string("IEND")) b.push_back(std::uint8_t(c));
  put32(b, 0);
  return b;
}

// SOI, a frame header of marker `sof` (ITU T.81 B.2.2: precision, height, width, one component),
// then EOI.
Bytes jpeg(std::uint8_t sof, std::uint8_t precision, std::uint16_t w, std::uint16_t h) {
  return {0xff, 0xd8, 0xff, sof, 0x00, 11, precision, std::uint8_t(h >> 8), std::uint8_t(h), std::uint8_t(w >> 8),
          std::uint8_t(w), 1, 1, 0x11, 0, 0xff, 0xd9};
}

std::string failure(const Bytes& b) {
  try {
    decodeImage(b.data(), b.size(), "photo");
  } catch (const InputError& e) {
    return e.what();
  }
  return "decoded";
}

TEST(ImageDecoderMessages, SayWhatTheFileIsAndWhyItIsRefused) {
  struct Case {
    Bytes bytes;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {png(0, 0), "photo: cannot decode image: a PNG of 0x0 pixels"},
      {png(30000000, 10), "a PNG of 30000000x10 pixels, larger than the decoder takes (16777216 per side)"},
      {png(100, 100, 7), "a PNG with 7-bit samples"},
      {jpeg(0xc0, 12, 64, 48), "a 12-bit JPEG: the decoder reads 8-bit samples only"},
      {jpeg(0xc9, 8, 64, 48), "an arithmetic-coded JPEG (SOF9)"},
      {jpeg(0xc3, 8, 64, 48), "a lossless JPEG (SOF3)"},
      {jpeg(0xc0, 8, 64, 0), "a JPEG of 64x0 pixels"},
  };
  for (const Case& c : cases) {
    const std::string m = failure(c.bytes);
    EXPECT_NE(m.find(c.expected), std::string::npos) << m;
    EXPECT_EQ(m.find("unknown image type"), std::string::npos) << m;
  }
}

TEST(ImageDecoderMessages, AValidHeaderIsNotBlamed) {
  EXPECT_EQ(undecodableReason(png(64, 48).data(), png(64, 48).size()), "");
  EXPECT_EQ(undecodableReason(jpeg(0xc0, 8, 64, 48).data(), jpeg(0xc0, 8, 64, 48).size()), "");
  EXPECT_EQ(undecodableReason(jpeg(0xc2, 8, 64, 48).data(), jpeg(0xc2, 8, 64, 48).size()), "");
}

}  // namespace
}  // namespace hv
