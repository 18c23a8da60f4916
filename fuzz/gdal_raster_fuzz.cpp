// Fuzz target: terrain rasters through GDAL (hv::readHeightfield: the size cap, decimation, no-data,
// scale and offset), as GeoTIFF and as an ESRI ASCII grid.
#include "fuzz_util.h"
#include "gdal_drivers.h"
#include "hv/io/native/raster.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hv::fuzz::keepOnlyGdalDrivers({"GTiff", "AAIGrid"});
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  // The first byte picks the name (GDAL tries every kept driver whatever the extension).
  const char* name = (size > 0 && (data[0] & 1)) ? "dtm.asc" : "dtm.tif";
  const std::string path = hv::fuzz::writeScratch(name, data, size);
  hv::fuzz::expectOnlyInputErrors("gdal_raster", [&] {
    hv::Diagnostics diag;
    const hv::Heightfield f = hv::readHeightfield(path, hv::SourceGeoref{}, diag).field;
    if (f.cols < 2 || f.rows < 2 || std::uint64_t(f.cols) * std::uint64_t(f.rows) > hv::kMaxRasterCells ||
        f.z.size() != size_t(f.cols) * size_t(f.rows)) {
      std::fprintf(stderr, "gdal_raster: BUG: %dx%d grid with %zu samples\n", f.cols, f.rows, f.z.size());
      std::abort();
    }
    // Meshed when small: a grid at the cap would take the replay ~2 GiB (docs/formats.md, Limits).
    if (f.z.size() <= (size_t(1) << 20)) (void)f.toMesh();
  });
  return 0;
}
