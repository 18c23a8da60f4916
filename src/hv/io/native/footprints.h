// Building footprints from any OGR vector source (GeoJSON, GeoPackage, Shapefile, ...).
#pragma once

#include "hv/io/native/georef.h"
#include "hv/scene/native/lod1.h"
#include "hv/util/diagnostics.h"

#include <optional>
#include <string>
#include <vector>

namespace hv {

struct FootprintFields {
  std::string height = "height";       // attribute: height in metres above the base
  std::optional<std::string> base;     // attribute: absolute base elevation
  std::optional<std::string> top;      // attribute: absolute roof elevation
  std::optional<std::string> validFrom, validTo;
};

// Reads Polygon and MultiPolygon features (a MultiPolygon gives one footprint per part, ids
// "<fid>.<part>"), holes included. A feature with no geometry, another geometry type, fewer than
// 3 points or no usable height is skipped with a warning naming its feature id. Throws InputError
// naming the file when it cannot be opened at all.
// Coordinates and attributes as they are in the file.
std::vector<Footprint> readFootprints(const std::string& path, const FootprintFields& fields, Diagnostics& diag);

struct GeoreferencedFootprints {
  std::vector<Footprint> footprints;  // in the scene frame
  // The CRS they were read in (the first layer's): the one transformed from, or, when the scene
  // has no CRS, the one they declare (taken as they are); empty: none.
  std::string sourceCrs;
};

// The footprints brought into the scene frame (hv/io/georef.h). Each layer's CRS: `georef.crs`,
// else the layer's own (GeoJSON without a `crs` member is WGS 84 longitude, latitude: RFC 7946,
// and GDAL says so), else the scene's. A layer said to be geographic whose coordinates cannot be
// degrees (|lon| > 360, |lat| > 90: an old GeoJSON in projected coordinates) is taken in the scene
// CRS, with a warning. Vertices go through PROJ in longitude-latitude / easting-
// northing order. `height` is in the CRS's height unit (CrsDescription::heightToMetre: feet for a
// 2D CRS in feet) and becomes metres; absolute `base` and `top` go through PROJ at the
// footprint's first vertex when both CRSs have a vertical axis, else are only converted to metres,
// with a warning when the CRSs differ. A footprint PROJ cannot transform is skipped with a
// warning. Throws InputError naming the file, or `georef.field`, when the source or a CRS cannot
// be read, and when the scene is geocentric (LOD1 extrusion needs a vertical z).
GeoreferencedFootprints readFootprints(const std::string& path, const FootprintFields& fields,
                                       const SourceGeoref& georef, Diagnostics& diag);

}  // namespace hv
