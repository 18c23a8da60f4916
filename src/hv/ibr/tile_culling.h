// Per-tile image lists. The view is cut into square tiles of its depth buffer; for each tile,
// the GPU reports the range of linear depth of its visible surface, and this code lists the
// images whose frustum may cover some point of the tile's slab (the tile's pixel rectangle between
// those depths). The shading pass then loops over that list only, so a fragment pays for the
// images that can see it, not for all those selected. On llvmpipe an in-shader `continue` saves
// nothing (PLATFORM.md): the loop itself must be shorter.
//
// The test is conservative: a tile's slab is the convex hull of 8 corners; if all of them are in
// front of image i, the projection of the slab lies inside the bounding box of the projected
// corners, which is tested against the ideal pixel rectangle that covers image i's (distorted)
// domain; a corner behind image i's camera keeps the image. So no image that covers a point of the
// tile is ever missing from its list.
#pragma once

#include "hv/ibr/frame_plan.h"

#include <cstdint>
#include <vector>

namespace hv::ibr {

struct TileGrid {
  int tileSize = 16;          // depth texels per tile side
  glm::ivec2 depthSize{0};    // the view's depth buffer, texels
  PinholeFrustum rect;        // ideal pixel rectangle the depth buffer covers, and its near/far
  int tilesX() const { return (depthSize.x + tileSize - 1) / tileSize; }
  int tilesY() const { return (depthSize.y + tileSize - 1) / tileSize; }
};

struct TileDepth {
  bool empty = true;  // no surface in the tile (background only)
  double zMin = 0.0, zMax = 0.0;  // linear depth along the view axis
};

struct TileLists {
  int tilesX = 0, tilesY = 0;
  std::vector<std::vector<std::uint16_t>> lists;  // per tile (row-major), indices into the params
  int maxCount() const;
  double meanCount() const;
};

TileLists buildTileLists(const Camera& view, const glm::dvec3& origin, const TileGrid& grid,
                         const std::vector<TileDepth>& depth, const std::vector<ImageParams>& images);

// The 8 corners (render frame) of a tile's slab; exposed for tests.
std::vector<glm::dvec3> tileSlabCorners(const Camera& view, const glm::dvec3& origin, const TileGrid& grid, int tx,
                                        int ty, const TileDepth& depth);

// Decodes the GPU's tile depth pass (RGBA8: 16-bit min in r,g and 16-bit max in b,a of the
// normalised depth, min rounded down and max up) into linear depth ranges.
std::vector<TileDepth> decodeTileDepth(const std::vector<std::uint8_t>& rgba, const TileGrid& grid);

}  // namespace hv::ibr
