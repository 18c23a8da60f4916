// scene.json: what a scene is made of (paths relative to the file). Schema in docs/formats.md.
#pragma once

#include "hv/scene/scene.h"
#include "hv/scene/scene_frame.h"
#include "hv/util/diagnostics.h"

#include <cstddef>
#include <string>

namespace hv {

// A terrain raster over kTerrainTilesAboveCells becomes a quadtree of tiles of kTerrainTileCells
// cells; Scene::terrain holds the tiles whose screen-space error from every photograph's camera is
// within kTerrainTolerancePx, refined largest error first within kTerrainTriangleBudget
// (hv/scene/scene_frame.h: the rules the page's service scenes share).
// Buildings are read by tile (hv/io/native/footprints.h), about kBuildingsPerTile footprints per
// tile; with photographs, only the tiles some photograph may see closer than
// kBuildingReachMetresPerPixel (hv/scene/building_tiles.h) x its focal length in pixels. A source
// with more tiles than those is also streamed per view (Scene::buildingTiles) for the renderer.
constexpr std::size_t kBuildingsPerTile = 256;
// The tiles' boxes span the terrain's and the cameras' heights, widened by this much (towers,
// basements) until a tile's own box is known from its buildings.
constexpr double kBuildingTileMarginMetres = 1000.0;

// Loads terrain, buildings and cameras. A broken source (missing file, unreadable raster, bad
// camera) is reported in `diag` and left out; the rest loads. Throws InputError only when
// scene.json itself cannot be read or parsed.
Scene loadScene(const std::string& path, Diagnostics& diag);

struct SceneLoadOptions {
  // Only the photographs (their cameras, georeferenced, and colour corrections): no terrain,
  // buildings, mesh or points are read (`histoview catalog load`, `cameras convert`).
  bool camerasOnly = false;
};
Scene loadScene(const std::string& path, Diagnostics& diag, const SceneLoadOptions& options);

}  // namespace hv
