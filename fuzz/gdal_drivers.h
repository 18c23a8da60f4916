// Fuzz targets that go through GDAL keep only the drivers histoview's own files use, so that the
// fuzzer explores histoview's handling of their results rather than every GDAL format (GDAL is
// fuzzed upstream by OSS-Fuzz).
#pragma once

#include "hv/io/native/footprints.h"

#include <gdal.h>

#include <initializer_list>
#include <string>

namespace hv::fuzz {

inline void keepOnlyGdalDrivers(std::initializer_list<const char*> keep) {
  // Let histoview register GDAL its own way first (std::call_once inside), so that it does not
  // register the removed drivers again later.
  try {
    hv::Diagnostics diag;
    (void)hv::readFootprints("/nonexistent/hv-fuzz-init.geojson", hv::FootprintFields{}, diag);
  } catch (const hv::InputError&) {
  }
  for (int i = GDALGetDriverCount() - 1; i >= 0; --i) {
    GDALDriverH driver = GDALGetDriver(i);
    const std::string name = GDALGetDriverShortName(driver);
    bool kept = false;
    for (const char* k : keep) kept = kept || name == k;
    if (!kept) {
      GDALDeregisterDriver(driver);
      GDALDestroyDriver(driver);
    }
  }
}

}  // namespace hv::fuzz
