// Building footprints from any OGR vector source (GeoJSON, GeoPackage, Shapefile, ...).
#pragma once

#include "hv/scene/lod1.h"
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
std::vector<Footprint> readFootprints(const std::string& path, const FootprintFields& fields, Diagnostics& diag);

}  // namespace hv
