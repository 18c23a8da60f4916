// Elevation rasters through GDAL (any single-band raster GDAL reads: GeoTIFF, ASC, VRT, ...).
// GDAL itself is only included under hv/io/native/private/.
#pragma once

#include "hv/io/native/georef.h"
#include "hv/scene/heightfield.h"
#include "hv/util/diagnostics.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hv {

// The most cells a terrain raster is read at (docs/formats.md, Limits): 6144 x 6144, 144 MiB of
// samples and about 2 GiB once meshed (Heightfield::toMesh, 56 bytes a cell). A larger raster is
// read at the smallest integer decimation that fits (from an overview when the file has one),
// with a warning naming the file, its size and the step.
constexpr std::uint64_t kMaxRasterCells = std::uint64_t(6144) * 6144;

// Reads band 1 as elevations (metres), honouring no-data (-> NaN) and the geotransform.
// Rotated geotransforms are rejected, and so are rasters smaller than 2 x 2 or with no sample
// that has data. Throws InputError naming the file on failure.
Heightfield readHeightfield(const std::string& path);

struct GeoreferencedHeightfield {
  Heightfield field;      // in the scene frame: scene CRS, x, y and heights in metres
  // The CRS it was read in (terrain.crs, else the raster's): the one transformed from, or, when
  // the scene has no CRS, the one it declares (taken as it is); empty: none.
  std::string sourceCrs;
};

// A terrain raster brought into the scene frame (hv/io/georef.h). Its CRS: `georef.crs`, else the
// raster's own, else the scene's. Heights: band 1 in the band's declared unit (GDAL's unit type:
// m, ft, US survey foot), else in the CRS's height unit (CrsDescription::heightToMetre: a 2D CRS
// in feet has its heights in feet). When both CRSs have a vertical axis, every sample goes through
// PROJ (datum and geoid included); otherwise heights are only converted to metres, with a warning
// when the CRSs differ. When the horizontal CRSs differ, the grid is warped with GDAL (bilinear
// interpolation, exact transformation, no-data honoured, square cells as fine as the source's finer
// side). A
// scene without CRS takes the raster as it is. Throws InputError naming the file, or
// `georef.field` for a bad override, when the raster or a CRS cannot be read, and when the scene
// or the raster is geocentric (a heightfield needs z up).
GeoreferencedHeightfield readHeightfield(const std::string& path, const SourceGeoref& georef, Diagnostics& diag);

// Writes a single-band Float32 GeoTIFF (the demo city's DTM). `crs` is anything
// OGRSpatialReference::SetFromUserInput accepts ("EPSG:2154"); empty writes none. `heightUnit`:
// the band's unit type ("m", "ft"); empty writes none.
void writeGeoTiff(const std::string& path, const Heightfield& field, const std::string& crs,
                  const std::string& heightUnit = "");

// Writes a single-band Float32 GeoTIFF of cols x rows cells of `cell` metres (north up, corner
// of cell (0, 0) at originX, originY), tiled in blocks of 512 and DEFLATE-compressed, from
// `height(i, j)` (NaN: no data, written as -9999 and declared so), block by block: never the
// whole raster in memory. `sparse`: a block with no data is not written at all (GDAL's SPARSE_OK),
// so a mostly empty raster of 30000 x 30000 cells is a few hundred KB. For tests and benchmarks
// of large DTMs. Throws InputError naming the file on failure.
void writeTiledGeoTiff(const std::string& path, int cols, int rows, double originX, double originY, double cell,
                       const std::string& crs, const std::function<float(int, int)>& height, bool sparse);

// Adds overviews to a raster file, as `gdaladdo -r <resampling> path <factors...>` does
// (`resampling`: GDAL's names, "AVERAGE", "NEAREST", ...). Throws InputError naming the file.
void addOverviews(const std::string& path, const std::vector<int>& factors, const std::string& resampling);

}  // namespace hv
