// Fuzz target: building footprints (GeoJSON through GDAL/OGR, hv::readFootprints) followed by
// LOD1 extrusion (hv::buildLod1: GEOS validity check and constrained Delaunay triangulation of
// arbitrary polygons).
#include "fuzz_util.h"
#include "gdal_drivers.h"
#include "hv/io/native/footprints.h"
#include "hv/scene/native/lod1.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hv::fuzz::keepOnlyGdalDrivers({"GeoJSON", "GeoJSONSeq", "ESRIJSON", "TopoJSON"});
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string path = hv::fuzz::writeScratch("footprints.geojson", data, size);
  hv::fuzz::expectOnlyInputErrors("footprints", [&] {
    hv::Diagnostics diag;
    hv::FootprintFields fields;
    fields.base = "base";
    fields.top = "top";
    fields.validFrom = "from";
    fields.validTo = "to";
    const auto footprints = hv::readFootprints(path, fields, diag);
    // buildLod1 reports bad footprints as warnings and never throws.
    hv::Mesh mesh;
    try {
      mesh = hv::buildLod1(footprints, nullptr, diag);
    } catch (const hv::InputError& e) {
      std::fprintf(stderr, "footprints: BUG: buildLod1 threw InputError: %s\n", e.what());
      std::abort();
    }
    // The mesh only references its own vertices.
    for (const auto& t : mesh.triangles)
      for (int c = 0; c < 3; ++c)
        if (size_t(t[c]) >= mesh.positions.size()) {
          std::fprintf(stderr, "footprints: BUG: triangle index %u out of %zu vertices\n", unsigned(t[c]),
                       mesh.positions.size());
          std::abort();
        }
  });
  return 0;
}
