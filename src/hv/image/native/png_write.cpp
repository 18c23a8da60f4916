// PNG writing through libpng: native only (the browser build decodes, it does not write files).
#include "hv/image/native/png_write.h"

#include <png.h>

#include <cstdio>
#include <memory>
#include <stdexcept>

namespace hv {

namespace {

void appendToVector(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}

void flushNothing(png_structp) {}

// Writes to the file `f`, or when it is null to `memory`.
template <typename Image>
void encodePngImpl(const std::string& path, const Image& img, int bitDepth, FILE* f,
                   std::vector<std::uint8_t>* memory) {
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
  if (f)
    png_init_io(png, f);
  else
    png_set_write_fn(png, memory, &appendToVector, &flushNothing);
  png_set_compression_level(png, 3);
  png_set_IHDR(png, info, img.width, img.height, bitDepth, kColorType[img.channels - 1], PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bitDepth == 16) png_set_swap(png);  // PNG is big-endian; our buffers are host (little) endian
  for (int y = 0; y < img.height; ++y) png_write_row(png, reinterpret_cast<png_const_bytep>(img.px(0, y)));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
}

template <typename Image>
void writePngImpl(const std::string& path, const Image& img, int bitDepth) {
  if (img.empty() || img.channels < 1 || img.channels > 4) throw std::runtime_error(path + ": nothing to write");
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f) throw std::runtime_error(path + ": cannot open for writing");
  encodePngImpl(path, img, bitDepth, f.get(), nullptr);
}

}  // namespace

void writePng(const std::string& path, const Image8& img) { writePngImpl(path, img, 8); }
void writePng16(const std::string& path, const Image16& img) { writePngImpl(path, img, 16); }

std::vector<std::uint8_t> encodePng(const Image8& img, const std::string& nameForErrors) {
  if (img.empty() || img.channels < 1 || img.channels > 4)
    throw std::runtime_error(nameForErrors + ": nothing to write");
  std::vector<std::uint8_t> out;
  encodePngImpl(nameForErrors, img, 8, nullptr, &out);
  return out;
}

}  // namespace hv
