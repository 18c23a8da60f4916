// Fuzz target: a COLMAP text model (hv::readColmapModel: cameras.txt and images.txt). The input is
// cameras.txt, a line "%%", then images.txt; without the separator the same text is both.
#include "fuzz_util.h"
#include "hv/io/native/colmap_cameras.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const size_t split = text.find("\n%%\n");
  const std::string cameras = split == std::string::npos ? text : text.substr(0, split + 1);
  const std::string images = split == std::string::npos ? text : text.substr(split + 4);
  hv::fuzz::writeScratch("cameras.txt", cameras);
  hv::fuzz::writeScratch("images.txt", images);
  hv::fuzz::expectOnlyInputErrors("colmap_text", [&] {
    hv::Diagnostics diag;
    const auto photos = hv::readColmapModel(hv::fuzz::scratchDir().string(), "images", diag, false);
    // What is read is a usable camera: validated, its pixel count within the loader's reach.
    for (const hv::Photo& p : photos) {
      const hv::Camera& c = p.camera;
      if (c.width <= 0 || c.height <= 0 || c.width > 65536 || c.height > 65536 || !std::isfinite(c.center.x) ||
          !(c.focal.x > 0.0)) {
        std::fprintf(stderr, "colmap_text: BUG: camera '%s' read with %dx%d pixels, focal %g\n", c.id.c_str(),
                     c.width, c.height, c.focal.x);
        std::abort();
      }
      (void)c.project(c.center + c.rayDirection(c.principal));
    }
  });
  return 0;
}
