// Fuzz target: CityJSON buildings (hv::parseCityJson): the JSON, the transform, the nesting of
// boundaries by geometry type, vertex indices, the triangulation of planar polygons with holes.
#include "fuzz_util.h"
#include "hv/io/native/cityjson.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("cityjson", [&] {
    hv::Diagnostics diag;
    const hv::CityJsonBuildings b = hv::parseCityJson(text, "fuzz.city.json", diag);
    // What the scene relies on: every triangle indexes a vertex and carries a building's tag.
    if (b.mesh.triangleTags.size() != b.mesh.triangles.size()) std::abort();
    for (size_t t = 0; t < b.mesh.triangles.size(); ++t) {
      for (int c = 0; c < 3; ++c)
        if (b.mesh.triangles[t][c] >= b.mesh.positions.size()) std::abort();
      if (b.mesh.triangleTags[t] >= b.ids.size()) std::abort();
    }
    for (const auto& p : b.mesh.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
  });
  return 0;
}
