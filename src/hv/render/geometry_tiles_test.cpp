// CPU tests of the geometry tiles (render/geometry_tiles.h): every triangle in exactly one tile, a
// building never split, boxes that hold their triangles, the clip-volume test against point
// samples projected by hand, and the merged draw ranges.
#include "hv/render/geometry_tiles.h"

#include "hv/camera/frustum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

namespace hv::render {
namespace {

// A flat grid of n x n quads (2 triangles each) over [0, size]^2 at z = 0.
void gridMesh(int n, double size, std::vector<glm::dvec3>& positions, std::vector<glm::uvec3>& triangles) {
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) positions.push_back({size * x / n, size * y / n, 0.0});
  auto v = [&](int x, int y) { return std::uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      triangles.push_back({v(x, y), v(x + 1, y), v(x + 1, y + 1)});
      triangles.push_back({v(x, y), v(x + 1, y + 1), v(x, y + 1)});
    }
}

TEST(GeometryTiles, GridSizeFollowsTheTriangleCount) {
  const TileGridXY one = makeTileGrid({0, 0}, {100, 100}, 1000, 4096);
  EXPECT_EQ(one.nx * one.ny, 1);
  const TileGridXY many = makeTileGrid({0, 0}, {100, 100}, 64 * 4096, 4096);
  EXPECT_EQ(many.nx, 8);
  EXPECT_EQ(many.ny, 8);
  EXPECT_NEAR(many.cell, 12.5, 1e-9);
  // A long thin extent: square cells, more of them along x.
  const TileGridXY thin = makeTileGrid({0, 0}, {400, 100}, 16 * 4096, 4096);
  EXPECT_EQ(thin.nx, 8);
  EXPECT_EQ(thin.ny, 2);
  // Bounded, whatever the count; non-finite extents give one cell.
  const TileGridXY capped = makeTileGrid({0, 0}, {1, 1}, std::size_t(1) << 40, 1);
  EXPECT_LE(capped.nx, 256);
  EXPECT_LE(capped.ny, 256);
  const TileGridXY bad = makeTileGrid({0, 0}, {INFINITY, 1}, 1000000, 1);
  EXPECT_EQ(bad.nx * bad.ny, 1);
  EXPECT_EQ(bad.cellOf({NAN, 5.0}), 0);
}

TEST(GeometryTiles, EveryTriangleOnceAndBoxesHoldThem) {
  std::vector<glm::dvec3> positions;
  std::vector<glm::uvec3> triangles;
  gridMesh(40, 100.0, positions, triangles);  // 3200 triangles
  const TileGridXY grid = makeTileGrid({0, 0}, {100, 100}, triangles.size(), 200);
  ASSERT_GT(grid.nx * grid.ny, 4);
  std::vector<std::uint32_t> indices;
  std::vector<GeometryTile> tiles;
  appendTiledLayer(kLayerTerrain, positions, triangles, {}, 7, grid, indices, tiles);
  ASSERT_EQ(indices.size(), 3 * triangles.size());
  std::multiset<std::array<std::uint32_t, 3>> want, got;
  for (const auto& t : triangles) want.insert({t.x + 7, t.y + 7, t.z + 7});
  int next = 0;
  for (const GeometryTile& tile : tiles) {
    EXPECT_EQ(tile.layer, kLayerTerrain);
    EXPECT_EQ(tile.range.first, next);  // contiguous, in order
    next += tile.range.count;
    for (int i = tile.range.first; i < tile.range.first + tile.range.count; i += 3) {
      got.insert({indices[size_t(i)], indices[size_t(i) + 1], indices[size_t(i) + 2]});
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3& p = positions[indices[size_t(i + k)] - 7];
        for (int a = 0; a < 3; ++a) {
          EXPECT_LE(double(tile.lo[a]), p[a]);
          EXPECT_GE(double(tile.hi[a]), p[a]);
        }
      }
    }
  }
  EXPECT_EQ(next, int(indices.size()));
  EXPECT_EQ(got, want);
  EXPECT_EQ(int(tiles.size()), grid.nx * grid.ny);
}

TEST(GeometryTiles, ABuildingIsNeverSplit) {
  // Four "buildings" (tags) straddling the cell borders of a 2 x 2 grid over [0, 100]^2.
  std::vector<glm::dvec3> positions;
  std::vector<glm::uvec3> triangles;
  std::vector<std::uint32_t> tags;
  const glm::dvec2 corners[] = {{40, 40}, {60, 40}, {40, 60}, {48, 10}};
  for (std::uint32_t b = 0; b < 4; ++b) {
    const glm::dvec2 c = corners[b];
    const auto base = std::uint32_t(positions.size());
    for (glm::dvec2 d : {glm::dvec2(0, 0), glm::dvec2(8, 0), glm::dvec2(8, 8), glm::dvec2(0, 8)})
      positions.push_back({c.x + d.x, c.y + d.y, 10.0});
    triangles.push_back({base, base + 1, base + 2});
    triangles.push_back({base, base + 2, base + 3});
    tags.insert(tags.end(), {b, b});
  }
  TileGridXY grid;
  grid.origin = {0, 0};
  grid.cell = 50;
  grid.nx = grid.ny = 2;
  std::vector<std::uint32_t> indices;
  std::vector<GeometryTile> tiles;
  appendTiledLayer(kLayerBuildings, positions, triangles, tags, 0, grid, indices, tiles);
  std::map<std::uint32_t, std::set<size_t>> tilesOf;
  for (size_t t = 0; t < tiles.size(); ++t)
    for (int i = tiles[t].range.first; i < tiles[t].range.first + tiles[t].range.count; ++i)
      tilesOf[indices[size_t(i)] / 4].insert(t);
  ASSERT_EQ(tilesOf.size(), 4u);
  for (const auto& [building, in] : tilesOf) EXPECT_EQ(in.size(), 1u) << "building " << building;
  // The centres: (44,44) and (52,44), (44,64), (52,14) -> cells 0, 1, 2, 1.
  EXPECT_EQ(grid.cellOf({44, 44}), 0);
  EXPECT_EQ(*tilesOf[0].begin() == *tilesOf[1].begin(), false);
  EXPECT_EQ(*tilesOf[1].begin(), *tilesOf[3].begin());

  // Tiles given by the source (buildings read by tile): those, not the grid's cells.
  const std::vector<std::uint32_t> tileOfTag = {1, 0, 1, 0};  // buildings 0 and 2 together, 1 and 3
  indices.clear();
  tiles.clear();
  appendTiledLayer(kLayerBuildings, positions, triangles, tags, 0, grid, indices, tiles, tileOfTag);
  ASSERT_EQ(tiles.size(), 2u);
  // Tile 0 (buildings 1 and 3) first: its box spans x 60..68 and 48..56, y 10..48.
  EXPECT_EQ(tiles[0].range.count, 12);
  EXPECT_FLOAT_EQ(tiles[0].lo.x, 48.0f);
  EXPECT_FLOAT_EQ(tiles[0].hi.x, 68.0f);
  EXPECT_FLOAT_EQ(tiles[0].lo.y, 10.0f);
  EXPECT_FLOAT_EQ(tiles[0].hi.y, 48.0f);
  std::set<std::uint32_t> first;
  for (int i = 0; i < tiles[0].range.count; ++i) first.insert(indices[size_t(i)] / 4);
  EXPECT_EQ(first, (std::set<std::uint32_t>{1, 3}));
}

// The box test never drops a box that holds a point inside the clip volume, and drops boxes that
// are plainly outside (behind the camera, beside the frustum, beyond far).
TEST(GeometryTiles, BoxTestIsConservativeAndCulls) {
  const Camera cam = lookAtCamera("c", {10, 20, 5}, {10, 120, 5}, 200, 100, 150.0);
  PinholeFrustum fr = idealRectCoveringImage(cam, 0.0);
  fr.near = 1.0;
  fr.far = 200.0;
  const glm::dvec3 origin(3, 4, 1);
  const glm::dmat4 clip = clipFromRender(cam, fr, origin);
  auto inside = [&](const glm::dvec3& world) {
    const auto pr = cam.project(world);
    if (pr.depth < fr.near || pr.depth > fr.far) return false;
    return pr.pxIdeal.x >= fr.pxMin.x && pr.pxIdeal.x <= fr.pxMax.x && pr.pxIdeal.y >= fr.pxMin.y &&
           pr.pxIdeal.y <= fr.pxMax.y;
  };
  // A point straight ahead is inside; the hand-made projection agrees with the clip matrix.
  ASSERT_TRUE(inside(cam.center + glm::dvec3(0, 50, 0)));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int kept = 0, culled = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const glm::dvec3 c = cam.center + glm::dvec3(300 * u(rng), 300 * u(rng), 60 * u(rng));
    const glm::dvec3 half(20 * std::abs(u(rng)) + 0.1, 20 * std::abs(u(rng)) + 0.1, 10 * std::abs(u(rng)) + 0.1);
    const glm::vec3 lo(c - half - origin), hi(c + half - origin);
    bool anyInside = false;
    for (int s = 0; s < 400 && !anyInside; ++s) {
      const glm::dvec3 f(0.5 + 0.5 * u(rng), 0.5 + 0.5 * u(rng), 0.5 + 0.5 * u(rng));
      const glm::dvec3 p = glm::dvec3(lo) + (glm::dvec3(hi) - glm::dvec3(lo)) * f;
      anyInside = inside(p + origin);
    }
    const bool may = boxMayBeVisible(clip, lo, hi);
    if (anyInside) EXPECT_TRUE(may) << "box around " << c.x << "," << c.y << "," << c.z;
    kept += may;
    culled += !may;
  }
  EXPECT_GT(culled, 1000);  // most random boxes around the camera are outside its narrow frustum
  EXPECT_GT(kept, 100);
  // Plainly outside: behind, beside, beyond far.
  auto box = [&](glm::dvec3 c, double h) {
    return boxMayBeVisible(clip, glm::vec3(c - glm::dvec3(h) - origin), glm::vec3(c + glm::dvec3(h) - origin));
  };
  EXPECT_FALSE(box(cam.center + glm::dvec3(0, -30, 0), 5));
  EXPECT_FALSE(box(cam.center + glm::dvec3(200, 30, 0), 5));
  EXPECT_FALSE(box(cam.center + glm::dvec3(0, 400, 0), 5));
  EXPECT_TRUE(box(cam.center + glm::dvec3(0, 30, 0), 5));
  // A box around the camera itself is kept.
  EXPECT_TRUE(box(cam.center, 2));
}

TEST(GeometryTiles, RangesMergeAndFollowTheLayers) {
  std::vector<GeometryTile> tiles(5);
  const glm::dvec3 far(1000, 0, 0);
  for (int i = 0; i < 5; ++i) {
    tiles[size_t(i)].layer = i < 3 ? kLayerTerrain : kLayerBuildings;
    tiles[size_t(i)].range = {i * 30, 30};
    tiles[size_t(i)].lo = glm::vec3(-1);
    tiles[size_t(i)].hi = glm::vec3(1);
  }
  tiles[1].lo = glm::vec3(far) - 1.0f;  // far away from everything
  tiles[1].hi = glm::vec3(far) + 1.0f;
  // Orthographic clip volume [-2, 2]^3.
  glm::dmat4 clip(0.5);
  clip[3][3] = 1.0;
  int drawn = 0;
  const auto all = visibleRanges(tiles, {true, true, true}, clip, false, &drawn);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].first, 0);
  EXPECT_EQ(all[0].count, 150);
  EXPECT_EQ(drawn, 5);
  const auto culled = visibleRanges(tiles, {true, true, true}, clip, true, &drawn);
  ASSERT_EQ(culled.size(), 2u);
  EXPECT_EQ(culled[0].count, 30);
  EXPECT_EQ(culled[1].first, 60);
  EXPECT_EQ(culled[1].count, 90);
  EXPECT_EQ(drawn, 4);
  const auto noTerrain = visibleRanges(tiles, {false, true, true}, clip, true, &drawn);
  ASSERT_EQ(noTerrain.size(), 1u);
  EXPECT_EQ(noTerrain[0].first, 90);
  EXPECT_EQ(drawn, 2);
}

}  // namespace
}  // namespace hv::render
