// Fuzz target: image decoding (hv::decodeImage, stb_image underneath: JPEG and PNG).
// Each input is decoded twice: with the file's channel count and with a forced one (1..4, picked
// from the input's length) so that the conversion paths are exercised too.
#include "fuzz_util.h"
#include "hv/image/image.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  for (const int want : {0, int(size % 4) + 1}) {
    hv::fuzz::expectOnlyInputErrors("image_decode", [&] {
      const hv::Image8 img = hv::decodeImage(data, size, "fuzz", want);
      // What callers rely on: the buffer matches the dimensions it reports.
      const bool consistent = img.width > 0 && img.height > 0 && img.channels >= 1 && img.channels <= 4 &&
                              img.data.size() == size_t(img.width) * size_t(img.height) * size_t(img.channels) &&
                              (want == 0 || img.channels == want);
      if (!consistent) {
        std::fprintf(stderr, "image_decode: BUG: inconsistent image %dx%dx%d, %zu bytes (want %d)\n", img.width,
                     img.height, img.channels, img.data.size(), want);
        std::abort();
      }
    });
  }
  return 0;
}
