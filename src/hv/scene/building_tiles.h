// Buildings read by tile on demand (docs/design.md, "Building streaming"): the tiles' boxes,
// known before any is read, and a function reading one tile. hv::footprintTileSet
// (hv/io/native/footprints.h) makes one from an OGR source; hv::render::BuildingStream
// (hv/render/building_stream.h) streams its tiles per view.
#pragma once

#include "hv/math/aabb.h"
#include "hv/scene/mesh.h"
#include "hv/util/dates.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hv {

// How far a camera is taken to see buildings: kBuildingReachMetresPerPixel x its focal length in
// pixels (farther, a pixel spans more than that on a facade facing it: too coarse to texture a
// building, and a building of a few metres is a pixel or less).
constexpr double kBuildingReachMetresPerPixel = 4.0;

// The buildings one tile owns (a building crossing tile borders is owned by one tile), extruded:
// world frame, `mesh.triangleTags` index `validity` (0 .. n-1, one per building of the tile).
struct BuildingTileData {
  Mesh mesh;
  std::vector<DateInterval> validity;
  std::vector<std::string> warnings;  // what reading and extruding it had to say (file, feature)
};

struct BuildingTileSet {
  // One box per tile, world frame: the tile's ground rectangle, and heights that hold whatever a
  // tile may contain (the terrain's range with a margin for towers). Conservative.
  std::vector<Aabb> boxes;
  // Reads and extrudes one tile (0 .. boxes.size() - 1). Called from worker threads, several at a
  // time: must be thread-safe. Throws (InputError naming the file) when the tile cannot be read.
  std::function<BuildingTileData(std::uint32_t tile)> read;
  // Where the tiles come from (the path or URL scene.json names), to name a tile that failed.
  std::string source;
};

}  // namespace hv
