// Fuzz target: a GeoJSON page of camera points as the browser's page fetches it from a WFS or an
// OGC API – Features layer (hv::parseGeoJsonCameras). Whatever the text: an InputError naming the
// page, or cameras that passed validation (finite, positive sizes), every other feature named.
#include "fuzz_util.h"
#include "hv/io/geojson_cameras.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("geojson_cameras", [&] {
    hv::Diagnostics diag;
    const hv::GeoJsonCameraPage page = hv::parseGeoJsonCameras(text, "http://127.0.0.1/wfs?page=0", diag);
    if (page.photos.size() + diag.errors.size() != page.features) __builtin_trap();
    for (const hv::Photo& p : page.photos) {
      const hv::Camera& c = p.camera;
      if (c.id.empty() || c.width <= 0 || c.height <= 0) __builtin_trap();
      for (int i = 0; i < 3; ++i)
        if (!std::isfinite(c.center[i])) __builtin_trap();
    }
    for (const std::string& e : diag.errors)
      if (e.rfind("http://127.0.0.1/wfs?page=0: feature ", 0) != 0) __builtin_trap();
  });
  return 0;
}
