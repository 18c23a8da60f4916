// Fuzz target: a 3D Tiles Point Cloud tile (hv::parsePnts): header, feature table JSON and binary
// body, the per-point batch table's Classification. What parses is a consistent cloud of finite points.
#include "fuzz_util.h"
#include "hv/io/tiles3d.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("pnts", [&] {
    const hv::PntsTile t = hv::parsePnts(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.pnts");
    if (!t.points.consistent()) __builtin_trap();
    for (const glm::dvec3& p : t.points.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
    for (const glm::vec3& n : t.points.normals)
      if (!(std::abs(glm::length(n) - 1.0f) < 1e-3f)) __builtin_trap();
  });
  return 0;
}
