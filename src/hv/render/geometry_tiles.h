// The scene's surfaces cut into tiles with bounding boxes, so that each pass draws only what its
// frustum can see (de Castro & Brédif 2022: data in tiles, joined at render time). The view and
// every photograph's depth map cull the tiles against their clip volume; what remains is drawn as
// a few index ranges (neighbouring tiles merged). Plain C++, no GL: the GL backend only draws the
// ranges it is given.
//
// Tiling: a square grid over the ground plane (x, y of the render frame) of the geometry's extent,
// sized for about kTrianglesPerTile triangles per tile. Each layer's triangles are sorted into the
// grid cells, layer by layer, so a layer stays one contiguous range of the index buffer. A building
// is never split: all its triangles (one tag, hv::Mesh::triangleTags) belong to the tile it was
// read in (buildings read by tile, Scene::tileOfBuilding), else to the cell of its bounding box's
// centre, so it is drawn once or not at all. Terrain and mesh triangles go by their
// centroid. A tile's box is the box of its triangles' vertices, so a triangle crossing a cell
// border is inside its tile's box.
#pragma once

#include "hv/render/frame.h"
#include "hv/scene/mesh.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace hv::render {

inline constexpr int kTrianglesPerTile = 4096;

// The grid over the ground plane that tiles are cut by (render frame).
struct TileGridXY {
  glm::dvec2 origin{0.0};
  double cell = 1.0;
  int nx = 1, ny = 1;
  int cellOf(glm::dvec2 p) const;  // clamped into the grid
};

// A grid of square cells over `lo`..`hi` (x, y) with about `triangles / perTile` cells (at least
// one; at most 256 x 256).
TileGridXY makeTileGrid(glm::dvec2 lo, glm::dvec2 hi, std::size_t triangles, int perTile = kTrianglesPerTile);

// Orders the triangles of one layer by grid cell and appends them to `indices` (offset by `base`,
// the layer's first vertex), one GeometryTile per non-empty cell. `positions` are the layer's
// vertices in the render frame; `tags` (empty: none) keep each tag's triangles in one tile.
// `tileOfTag` (empty: the grid): the tile of each tag, given by the source (Scene::tileOfBuilding,
// buildings read by tile), used instead of the grid; a tag past its end goes by the grid.
void appendTiledLayer(int layer, const std::vector<glm::dvec3>& positions, const std::vector<glm::uvec3>& triangles,
                      const std::vector<std::uint32_t>& tags, std::uint32_t base, const TileGridXY& grid,
                      std::vector<std::uint32_t>& indices, std::vector<GeometryTile>& tiles,
                      const std::vector<std::uint32_t>& tileOfTag = {});

// Whether an axis-aligned box may be inside the clip volume of `clipFromRender` (-w <= x, y, z <= w):
// false only when all 8 corners are outside one of the six planes (each plane is a half-space of
// the render frame, so the whole box is then outside: conservative, behind the camera included).
bool boxMayBeVisible(const glm::dmat4& clipFromRender, const glm::vec3& lo, const glm::vec3& hi);

// The index ranges to draw for the tiles of the layers that are on and, when `cull`, whose boxes
// may be visible through `clipFromRender`; tiles adjacent in the index buffer merge into one range.
// `tilesDrawn` (optional) receives the number of tiles kept.
std::vector<DrawRange> visibleRanges(const std::vector<GeometryTile>& tiles, const std::array<bool, kLayerCount>& layers,
                                     const glm::dmat4& clipFromRender, bool cull, int* tilesDrawn = nullptr);

}  // namespace hv::render
