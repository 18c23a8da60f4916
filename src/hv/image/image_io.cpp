#include "hv/image/image.h"

#include "hv/util/diagnostics.h"

#include <stb_image.h>
#include <stb_image_resize.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace hv {

namespace {

bool isPng(const std::uint8_t* b, size_t n) {
  static const std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return n >= 8 && std::equal(sig, sig + 8, b);
}
bool isJpeg(const std::uint8_t* b, size_t n) { return n >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff; }

// Checks the JPEG marker segments up to the scan: each segment's length fits in the file, and
// each Huffman table (DHT) holds at most 256 codes. stb_image 2.27 (Debian 12) trusts that count
// and writes past its tables otherwise (found by fuzz/image_decode_fuzz), so such files are
// rejected before stb sees them.
void checkJpegSegments(const std::uint8_t* b, size_t n, const std::string& name, bool complete) {
  size_t pos = 2;  // after SOI
  while (pos + 4 <= n) {
    if (b[pos] != 0xff) throw InputError(name + ": JPEG: expected a marker at byte " + std::to_string(pos));
    const std::uint8_t marker = b[pos + 1];
    if (marker == 0xff) {  // fill byte
      ++pos;
      continue;
    }
    if (marker == 0xd9 || marker == 0xda) return;  // end of image, start of scan: entropy data follows
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7)) {  // markers without a length
      pos += 2;
      continue;
    }
    const size_t len = size_t(b[pos + 2]) << 8 | b[pos + 3];
    if (len < 2) throw InputError(name + ": JPEG: bad segment length at byte " + std::to_string(pos));
    if (pos + 2 + len > n) {
      if (!complete) return;  // a prefix of the file: the rest is checked when it is decoded
      throw InputError(name + ": JPEG: truncated segment at byte " + std::to_string(pos));
    }
    if (marker == 0xc4) {  // DHT: one or more tables of (class/id, 16 counts, values)
      size_t q = pos + 4;
      const size_t end = pos + 2 + len;
      while (q < end) {
        if (q + 17 > end) throw InputError(name + ": JPEG: truncated Huffman table");
        size_t codes = 0;
        for (int i = 1; i <= 16; ++i) codes += b[q + size_t(i)];
        if (codes > 256) throw InputError(name + ": JPEG: Huffman table with more than 256 codes");
        q += 17 + codes;
      }
    }
    pos += 2 + len;
  }
}

}  // namespace

void checkImageBytes(const std::uint8_t* bytes, size_t size, const std::string& name, bool complete) {
  // JPEG and PNG only: stb_image also guesses BMP, GIF, PSD, PIC, PNM, HDR and TGA (which has no
  // signature), formats the camera files do not promise.
  if (isJpeg(bytes, size)) {
    checkJpegSegments(bytes, size, name, complete);
  } else if (!isPng(bytes, size)) {
    throw InputError(name + ": not a JPEG or PNG file (unknown signature)");
  }
}

Image8 decodeImage(const std::uint8_t* bytes, size_t size, const std::string& name, int wantChannels) {
  if (size > size_t(INT32_MAX)) throw InputError(name + ": image file too large");
  checkImageBytes(bytes, size, name, true);
  int w = 0, h = 0, n = 0;
  stbi_uc* pixels = stbi_load_from_memory(bytes, int(size), &w, &h, &n, wantChannels);
  if (!pixels) {
    const char* reason = stbi_failure_reason();
    throw InputError(name + ": cannot decode image (expected JPEG or PNG): " + (reason ? reason : "unknown error"));
  }
  if (w <= 0 || h <= 0) {
    stbi_image_free(pixels);
    throw InputError(name + ": image has no pixels (" + std::to_string(w) + "x" + std::to_string(h) + ")");
  }
  const int c = wantChannels ? wantChannels : n;
  Image8 img;
  img.width = w;
  img.height = h;
  img.channels = c;
  img.data.assign(pixels, pixels + size_t(w) * h * c);
  stbi_image_free(pixels);
  return img;
}

namespace {
std::vector<std::uint8_t> readFile(const std::string& path) {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw InputError(path + ": cannot open file");
  std::vector<std::uint8_t> bytes;
  std::uint8_t buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f.get())) > 0) bytes.insert(bytes.end(), buf, buf + n);
  return bytes;
}
}  // namespace

Image8 readImage(const std::string& path, int wantChannels) {
  const auto bytes = readFile(path);
  return decodeImage(bytes.data(), bytes.size(), path, wantChannels);
}

Image16 readPng16(const std::string& path) {
  const auto bytes = readFile(path);
  int w = 0, h = 0, n = 0;
  if (!isPng(bytes.data(), bytes.size())) throw InputError(path + ": not a PNG file");
  stbi_us* pixels = stbi_load_16_from_memory(bytes.data(), int(bytes.size()), &w, &h, &n, 0);
  if (!pixels) throw InputError(path + ": cannot decode 16-bit PNG");
  Image16 img;
  img.width = w;
  img.height = h;
  img.channels = n;
  img.data.assign(pixels, pixels + size_t(w) * h * n);
  stbi_image_free(pixels);
  return img;
}

void writeJpeg(const std::string& path, const Image8& img, int quality) {
  if (!stbi_write_jpg(path.c_str(), img.width, img.height, img.channels, img.data.data(), quality))
    throw std::runtime_error(path + ": cannot write JPEG");
}

Image8 rgbOf(const Image8& rgba) {
  Image8 rgb(rgba.width, rgba.height, 3);
  const size_t n = size_t(rgba.width) * rgba.height;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) rgb.data[3 * i + size_t(c)] = rgba.data[size_t(rgba.channels) * i + size_t(c)];
  return rgb;
}

Image8 alphaMask(const Image8& rgba) {
  Image8 mask(rgba.width, rgba.height, 1);
  const size_t n = size_t(rgba.width) * rgba.height;
  for (size_t i = 0; i < n; ++i) mask.data[i] = rgba.data[size_t(rgba.channels) * i + 3] > 0 ? 255 : 0;
  return mask;
}

Image8 resizeImage(const Image8& src, int width, int height) {
  // stb_image_resize's default filters (Mitchell when shrinking, so large reductions do not alias;
  // Catmull-Rom when enlarging). Pixel centres stay aligned: the image maps onto [0,W]x[0,H].
  Image8 out(width, height, src.channels);
  if (!stbir_resize_uint8(src.data.data(), src.width, src.height, 0, out.data.data(), width, height, 0,
                          src.channels))
    throw std::runtime_error("image resize failed");
  return out;
}

}  // namespace hv
