// Points from an OGC 3D Tiles tileset (docs/formats.md, "Points from 3D Tiles"; docs/services.md):
// `"points": {"tileset": "http://…/tileset.json"}` (or a `path` ending in tileset.json), a local
// file or a URL fetched through GDAL's HTTP client and the response cache (hv/io/native/remote.h).
// The tiles are chosen by screen-space error from the photographs' cameras (the resolution the
// depth maps are made at), within a point budget; their pnts contents are fetched a few at a time
// and parsed by hv/io/tiles3d.h. A tile that cannot be fetched or read is named and left out.
#pragma once

#include "hv/camera/camera.h"
#include "hv/io/native/georef.h"
#include "hv/scene/point_cloud.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hv {

// A tile is refined while its screen-space error (geometric error x focal length in pixels /
// distance from the camera to its bounding sphere) from some camera exceeds this many pixels
// (scene.json points.tolerance), as long as the points stay within kPointTilesBudget
// (points.budget).
constexpr double kPointTilesTolerancePx = 2.0;
constexpr std::size_t kPointTilesBudget = 20'000'000;
// Tiles fetched at once.
constexpr int kPointTilesConcurrency = 4;

// What was read of a tileset, for `histoview info`.
// What a tileset's reading read (kept in the scene for `histoview info`).
using PointTilesetInfo = Scene::PointTilesInfo;

struct PointTilesetRequest {
  std::string url;      // tileset.json: a local path or a URL
  SourceGeoref georef;  // the tileset's CRS (points.crs, else EPSG:4978) into the scene CRS
  double tolerancePx = kPointTilesTolerancePx;
  std::size_t budget = kPointTilesBudget;
};

// The tileset CRS when the points entry gives none: 3D Tiles 1.0 are earth-centred.
inline constexpr const char* kTilesetDefaultCrs = "EPSG:4978";

// True when a points path names a tileset (its name, query dropped, is or ends in "tileset.json").
bool isTilesetPath(const std::string& path);

// Reads the tiles chosen for `cameras` (in the scene frame; none: refined by geometric error,
// largest first, up to the budget). The points are returned in the tileset frame (crs set to
// the tileset's CRS), for the caller to georeference like a file's; `tileset` says what was read.
// Throws InputError when the tileset itself cannot be read; a tile that fails is reported in
// `diag` ("…/r04.pnts: points tile: HTTP error code : 404 (tile root.children[4] left out)").
PointCloud loadPointTileset(const PointTilesetRequest& request, const std::vector<Camera>& cameras, Diagnostics& diag,
                            PointTilesetInfo* info = nullptr);

}  // namespace hv
