// Elevation rasters through GDAL (any single-band raster GDAL reads: GeoTIFF, ASC, VRT, ...).
// GDAL itself is only included under hv/io/private/.
#pragma once

#include "hv/scene/heightfield.h"
#include "hv/util/diagnostics.h"

#include <string>

namespace hv {

// Reads band 1 as elevations (metres), honouring no-data (-> NaN) and the geotransform.
// Rotated geotransforms are rejected. Throws InputError naming the file on failure.
Heightfield readHeightfield(const std::string& path);

// Writes a single-band Float32 GeoTIFF (the demo city's DTM). `crs` is anything
// OGRSpatialReference::SetFromUserInput accepts ("EPSG:2154"); empty writes none.
void writeGeoTiff(const std::string& path, const Heightfield& field, const std::string& crs);

}  // namespace hv
