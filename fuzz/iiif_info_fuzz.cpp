// Fuzz target: a IIIF Image API description (hv::parseIiifInfo), then the checks and the request a
// camera would make from it.
#include "fuzz_util.h"
#include "hv/io/iiif.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("iiif_info", [&] {
    const hv::IiifImageInfo info = hv::parseIiifInfo(text, "http://127.0.0.1/iiif/photo/info.json");
    // What parsed is a usable description: a positive size, and a request within it.
    if (info.width <= 0 || info.height <= 0) __builtin_trap();
    (void)hv::iiifSizeMismatch(info, 1024, 768);
    for (int want : {1, 256, 1024, 1 << 20}) {
      const hv::IiifRequest r = hv::iiifRequest(info, want);
      if (r.url.empty() || r.width <= 0 || r.height <= 0) __builtin_trap();
    }
  });
  return 0;
}
