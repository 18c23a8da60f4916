// Building footprints and a DTM as web services give them, read without GDAL (portable: the
// browser build reads what its page fetched; docs/services.md, "In the browser"):
// - a GeoJSON FeatureCollection of Polygon / MultiPolygon features (a page of a WFS 2.0
//   GetFeature answered as GeoJSON, or of an OGC API – Features `items`), coordinates taken as
//   they are (the page asks the service for the scene's CRS: no reprojection here);
// - an ESRI ASCII grid (AAIGrid, a WCS GetCoverage answered in GDAL's AAIGrid format) as a
//   Heightfield.
#pragma once

#include "hv/scene/footprint.h"
#include "hv/scene/heightfield.h"
#include "hv/util/diagnostics.h"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace hv {

// The attributes read from each feature's `properties` (scene.json's `buildings` keys).
struct GeoJsonFootprintFields {
  std::string height = "height";
  std::optional<std::string> base, top, validFrom, validTo;
};

struct GeoJsonFootprintPage {
  std::vector<Footprint> footprints;
  std::size_t features = 0;  // in the page, kept or not
  std::string next;          // the `next` link's href (OGC API), empty: none
};

// One page. A MultiPolygon gives one footprint per part (ids "<id>.<part>"); a feature with no
// geometry, another geometry type or a broken ring is skipped with a warning naming `name` and
// the feature (as readFootprints warns). Heights: a number, or a string that is one. Throws
// InputError naming `name` when the text is not JSON or not a FeatureCollection.
GeoJsonFootprintPage parseGeoJsonFootprints(const std::string& text, const GeoJsonFootprintFields& fields,
                                            const std::string& name, Diagnostics& diag);

// An ESRI ASCII grid: `ncols`, `nrows`, `xllcorner` / `xllcenter`, `yllcorner` / `yllcenter`,
// `cellsize` (or `dx` and `dy`), optional `NODATA_value`, then nrows x ncols values, north row
// first. Throws InputError naming `name` and the field or value at fault.
Heightfield parseAaiGrid(const std::string& text, const std::string& name);

}  // namespace hv
