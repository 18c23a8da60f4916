// Fuzz target: the web scene manifest's entries for the page's service layers (hv/io/web_geocentric.h,
// hv/io/web_orthophoto.h): "geocentric" (the EPSG:4978 fit) and "orthophoto" (its file absent here,
// so a well-formed entry ends in a message too). What parses gives finite values; a bad entry is
// an InputError (the fit) or a message in the diagnostics (the orthophoto), never a crash.
#include "fuzz_util.h"
#include "hv/io/web_geocentric.h"
#include "hv/io/web_orthophoto.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const nlohmann::json j =
      nlohmann::json::parse(std::string(reinterpret_cast<const char*>(data), size), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return 0;
  hv::fuzz::expectOnlyInputErrors("web_extras", [&] {
    if (!j.contains("geocentric")) return;
    const hv::GeocentricFit fit = hv::geocentricFromJson(j["geocentric"], "scene_web.json");
    if (!(fit.scale > 0.0) || !std::isfinite(fit.scale)) __builtin_trap();
    const glm::dvec3 p = hv::applyGeocentric(fit, fit.centre);
    (void)p;
  });
  hv::fuzz::expectOnlyInputErrors("web_extras", [&] {
    hv::Diagnostics diag;
    const auto o = hv::readWebOrthophoto(j, "/nonexistent-web-extras-fuzz", "scene_web.json", diag);
    if (o && o->rgba.size() != std::size_t(o->width) * std::size_t(o->height) * 4) __builtin_trap();
  });
  return 0;
}
