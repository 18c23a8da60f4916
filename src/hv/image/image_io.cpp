#include "hv/image/image.h"

#include "hv/image/image_header.h"
#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"

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
    if (marker == 0xd9 || marker == 0xda) return;                // end of image, start of scan: entropy data follows
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

std::uint32_t bigEndian32(const std::uint8_t* b) {
  return std::uint32_t(b[0]) << 24 | std::uint32_t(b[1]) << 16 | std::uint32_t(b[2]) << 8 | b[3];
}

// stb_image's STBI_MAX_DIMENSIONS default: it refuses a side over 2^24 pixels.
constexpr std::uint32_t kDecoderMaxSide = 1u << 24;

std::string sizeWords(std::uint32_t w, std::uint32_t h) { return std::to_string(w) + "x" + std::to_string(h); }

// The PNG header (IHDR, PNG specification 11.2.2), then the JPEG frame header (SOFn, ITU T.81
// B.2.2): what stb_image decodes is 8-bit (and 16-bit PNG) baseline or progressive Huffman JPEG.
std::string pngReason(const std::uint8_t* b, size_t n) {
  if (n < 8 + 8 + 13) return "a PNG cut before its header (IHDR)";
  const std::uint32_t w = bigEndian32(b + 16), h = bigEndian32(b + 20);
  if (w == 0 || h == 0) return "a PNG of " + sizeWords(w, h) + " pixels: no image";
  if (w > kDecoderMaxSide || h > kDecoderMaxSide)
    return "a PNG of " + sizeWords(w, h) + " pixels, larger than the decoder takes (" +
           std::to_string(kDecoderMaxSide) + " per side)";
  const int depth = b[24], colour = b[25];
  if (depth != 1 && depth != 2 && depth != 4 && depth != 8 && depth != 16)
    return "a PNG with " + std::to_string(depth) + "-bit samples (the format has 1, 2, 4, 8 or 16)";
  if (colour != 0 && colour != 2 && colour != 3 && colour != 4 && colour != 6)
    return "a PNG of colour type " + std::to_string(colour) + " (the format has 0, 2, 3, 4 and 6)";
  if (std::uint64_t(w) * h > (std::uint64_t(1) << 31) / 8)
    return "a PNG of " + sizeWords(w, h) + " pixels, more than the decoder can hold in memory at once";
  return "";
}

std::string jpegReason(const std::uint8_t* b, size_t n) {
  size_t pos = 2;
  while (pos + 4 <= n) {
    if (b[pos] != 0xff) return "";
    const std::uint8_t marker = b[pos + 1];
    if (marker == 0xff) {
      ++pos;
      continue;
    }
    if (marker == 0xd9 || marker == 0xda) return "a JPEG without a frame header (SOF) before its scan";
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7)) {
      pos += 2;
      continue;
    }
    const size_t len = size_t(b[pos + 2]) << 8 | b[pos + 3];
    const bool frame = marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
    if (frame) {
      if (marker >= 0xc9)
        return "an arithmetic-coded JPEG (SOF" + std::to_string(marker - 0xc0) +
               "): the decoder reads Huffman-coded JPEGs only; re-encode it";
      if (marker == 0xc3 || marker == 0xc7)
        return "a lossless JPEG (SOF" + std::to_string(marker - 0xc0) +
               "): the decoder reads baseline and progressive JPEGs only";
      if (marker >= 0xc5)
        return "a hierarchical JPEG (SOF" + std::to_string(marker - 0xc0) +
               "): the decoder reads baseline and progressive JPEGs only";
      if (pos + 9 > n) return "a JPEG cut in its frame header";
      const int precision = b[pos + 4];
      const std::uint32_t h = std::uint32_t(b[pos + 5]) << 8 | b[pos + 6],
                          w = std::uint32_t(b[pos + 7]) << 8 | b[pos + 8];
      if (precision != 8)
        return "a " + std::to_string(precision) + "-bit JPEG: the decoder reads 8-bit samples only; re-encode it";
      if (w == 0 || h == 0)
        return "a JPEG of " + sizeWords(w, h) +
               " pixels (a height of 0 is given later by a DNL marker, which "
               "the decoder does not read)";
      return "";
    }
    if (len < 2) return "";
    pos += 2 + len;
  }
  return "";
}

}  // namespace

std::string undecodableReason(const std::uint8_t* bytes, size_t size) {
  if (isPng(bytes, size)) return pngReason(bytes, size);
  if (isJpeg(bytes, size)) return jpegReason(bytes, size);
  return "";
}

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
    if (const std::string why = undecodableReason(bytes, size); !why.empty())
      throw InputError(name + ": cannot decode image: " + why);
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
  // A photograph by URL (docs/services.md), from the response cache when it holds it.
  if (isHttpUrl(path)) return readInputBytes(path, kMaxImageBytes, "", RemoteCache::Yes);
  // A FIFO or device named as a photograph would block the open or never end.
  if (const std::string reason = notRegularFileReason(path); !reason.empty()) throw InputError(path + ": " + reason);
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
  if (!stbir_resize_uint8(src.data.data(), src.width, src.height, 0, out.data.data(), width, height, 0, src.channels))
    throw std::runtime_error("image resize failed");
  return out;
}

}  // namespace hv
