// In-memory images. Rows are stored top row first (row 0 is the top of the picture, matching the
// pixel convention of hv/camera/camera.h); channels are interleaved.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hv {

template <typename T>
struct ImageT {
  int width = 0, height = 0, channels = 0;
  std::vector<T> data;

  ImageT() = default;
  ImageT(int w, int h, int c, T fill = T{}) : width(w), height(h), channels(c), data(size_t(w) * h * c, fill) {}
  bool empty() const { return data.empty(); }
  T* px(int x, int y) { return data.data() + (size_t(y) * width + x) * channels; }
  const T* px(int x, int y) const { return data.data() + (size_t(y) * width + x) * channels; }
  T& at(int x, int y, int c) { return data[(size_t(y) * width + x) * channels + c]; }
  const T& at(int x, int y, int c) const { return data[(size_t(y) * width + x) * channels + c]; }
};

using Image8 = ImageT<std::uint8_t>;
using Image16 = ImageT<std::uint16_t>;
using ImageF = ImageT<float>;

// Decodes a JPEG or PNG (8-bit; 16-bit PNGs are reduced to 8 bits) into 1..4 channels.
// `wantChannels` 0 keeps the file's. Throws InputError naming the file on failure.
Image8 readImage(const std::string& path, int wantChannels = 0);
// Same, from memory (fuzzing, web).
Image8 decodeImage(const std::uint8_t* bytes, size_t size, const std::string& nameForErrors, int wantChannels = 0);
// Checks what stb_image is about to parse: a JPEG or PNG signature, and for a JPEG its marker
// segments up to the scan (Huffman tables of at most 256 codes: Debian's stb_image 2.27 writes
// past its tables otherwise). `complete` false: `bytes` is a prefix of the file. Throws InputError.
void checkImageBytes(const std::uint8_t* bytes, size_t size, const std::string& name, bool complete);
// 16-bit PNG reading (raw counts), for tests of --debug count.
Image16 readPng16(const std::string& path);

// The colour of an RGBA image (alpha dropped), and its alpha as a mask (255 where alpha > 0).
Image8 rgbOf(const Image8& rgba);
Image8 alphaMask(const Image8& rgba);

// JPEG writer (stb_image_write). The PNG writers (libpng, native only) are in hv/image/png_write.h.
void writeJpeg(const std::string& path, const Image8& image, int quality = 92);

// Resize for scaling photographs into texture slices (stb_image_resize: filtered, so shrinking by a
// large factor does not alias). Pixel-centre aligned: the image keeps covering [0,W]x[0,H].
Image8 resizeImage(const Image8& src, int width, int height);

}  // namespace hv
