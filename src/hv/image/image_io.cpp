#include "hv/image/image.h"

#include "hv/util/diagnostics.h"

#include <png.h>
#include <stb_image.h>
#include <stb_image_resize.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

namespace hv {

Image8 decodeImage(const std::uint8_t* bytes, size_t size, const std::string& name, int wantChannels) {
  if (size > size_t(INT32_MAX)) throw InputError(name + ": image file too large");
  int w = 0, h = 0, n = 0;
  stbi_uc* pixels = stbi_load_from_memory(bytes, int(size), &w, &h, &n, wantChannels);
  if (!pixels) {
    const char* reason = stbi_failure_reason();
    throw InputError(name + ": cannot decode image (expected JPEG or PNG): " + (reason ? reason : "unknown error"));
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

namespace {

template <typename Image>
void writePngImpl(const std::string& path, const Image& img, int bitDepth) {
  if (img.empty() || img.channels < 1 || img.channels > 4) throw std::runtime_error(path + ": nothing to write");
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f) throw std::runtime_error(path + ": cannot open for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error(path + ": libpng initialisation failed");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error(path + ": libpng write error");
  }
  static const int kColorType[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                   PNG_COLOR_TYPE_RGB_ALPHA};
  png_init_io(png, f.get());
  png_set_compression_level(png, 3);
  png_set_IHDR(png, info, img.width, img.height, bitDepth, kColorType[img.channels - 1], PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bitDepth == 16) png_set_swap(png);  // PNG is big-endian; our buffers are host (little) endian
  for (int y = 0; y < img.height; ++y)
    png_write_row(png, reinterpret_cast<png_const_bytep>(img.px(0, y)));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
}

}  // namespace

void writePng(const std::string& path, const Image8& img) { writePngImpl(path, img, 8); }
void writePng16(const std::string& path, const Image16& img) { writePngImpl(path, img, 16); }

void writeJpeg(const std::string& path, const Image8& img, int quality) {
  if (!stbi_write_jpg(path.c_str(), img.width, img.height, img.channels, img.data.data(), quality))
    throw std::runtime_error(path + ": cannot write JPEG");
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
