// Fuzz target: building footprints through OGR (hv::readFootprints) from the vector formats other
// than GeoJSON (which fuzz/footprints_fuzz.cpp covers): CSV with WKT geometries, GeoPackage,
// FlatGeobuf. The first byte picks the file name; GDAL identifies the format by the content too.
#include "fuzz_util.h"
#include "gdal_drivers.h"
#include "hv/io/native/footprints.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hv::fuzz::keepOnlyGdalDrivers({"CSV", "GPKG", "SQLite", "FlatGeobuf"});
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kNames[] = {"footprints.csv", "footprints.gpkg", "footprints.fgb"};
  const std::string path = hv::fuzz::writeScratch(kNames[data[0] % 3], data + 1, size - 1);
  hv::fuzz::expectOnlyInputErrors("ogr_vector", [&] {
    hv::Diagnostics diag;
    hv::FootprintFields fields;
    fields.base = "base";
    fields.top = "top";
    (void)hv::readFootprints(path, fields, diag);
  });
  return 0;
}
