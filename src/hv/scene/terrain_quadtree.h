// Terrain as a quadtree of tiles with levels of detail, read by window from a raster source and
// selected by screen-space error (docs/design.md, "Terrain tiles"). The city-scale layout of
// de Castro & Brédif (2022): the data in tiles, fetched for the view; the chunked level of detail
// with skirts and the screen-space error of Ulrich (2002, "Rendering massive terrains using
// chunked level of detail control").
//
// Grid convention (owned here, repeated in docs/design.md). The full-resolution raster is a
// Heightfield's grid (hv/scene/heightfield.h): cols x rows samples at cell centres. The quadtree
// has levels 0..L; level l has the step s = 2^(L - l) (level L is the raster itself) and its
// sample k (per axis) sits on the full-resolution sample min(k s, cols - 1): the levels' vertices
// are nested, so a tile's border is the same line at every level and the vertical skirts close
// the gaps between levels. K_l = ceil((cols - 1) / s) is the last sample of level l. Node
// (l, tx, ty) is the tile of level-l samples [tx n, min(tx n + n, K_l)] per axis (n = tileCells);
// level 0 is one tile (n 2^L >= cols - 1 and rows - 1). A tile is a grid of at most
// (n + 1) x (n + 1) samples; neighbouring tiles share their border samples.
#pragma once

#include "hv/camera/camera.h"
#include "hv/math/aabb.h"
#include "hv/scene/heightfield.h"
#include "hv/scene/mesh.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace hv {

// The full-resolution grid of a terrain raster in the scene frame (metres): Heightfield's fields.
struct TerrainGrid {
  int cols = 0, rows = 0;
  double originX = 0.0, originY = 0.0;  // corner of cell (0, 0)
  double cellX = 1.0, cellY = -1.0;
  // The world position of the full-resolution sample (i, j) (fractional indices allowed).
  glm::dvec2 position(double i, double j) const { return {originX + (i + 0.5) * cellX, originY + (j + 0.5) * cellY}; }
};

// Where a quadtree's samples come from: the native GDAL reader (hv/io/native/terrain_raster.h) or
// a Heightfield in memory (HeightfieldTerrainSource below).
class TerrainSource {
 public:
  virtual ~TerrainSource() = default;
  virtual const TerrainGrid& grid() const = 0;
  // The samples kx in [kx0, kx0 + nx), ky in [ky0, ky0 + ny) of the level of step `step` (a power
  // of two), row-major, heights in metres, NaN = no data. Sample k is the terrain at the
  // full-resolution sample min(k step, cols - 1) as seen at that step: the raster itself at step 1,
  // a low-passed copy (an overview) at coarser steps. Throws InputError naming the source when it
  // cannot be read. Safe to call from several threads.
  virtual std::vector<float> levelSamples(int step, int kx0, int ky0, int nx, int ny) const = 0;
};

// An overview of a raster (GDAL's, or a pyramid made by averaging): a grid over the same extent
// whose sample o (per axis) is the mean of the full-resolution cells [o r, (o + 1) r), r the
// overview's ratio (cols / overview cols for GDAL's overviews). The full-resolution sample p sits
// at the overview's sample coordinate (p + 0.5) / r - 0.5.
struct OverviewAxis {
  int fullCount = 0;      // full-resolution samples
  int overviewCount = 0;  // the overview's samples
  double ratio = 1.0;     // r
};
// The overview samples [lo, hi] that interpolating level samples [k0, k0 + n) of step `step` needs.
struct OverviewSpan {
  int lo = 0, hi = 0;
};
OverviewSpan overviewSpan(const OverviewAxis& axis, int step, int k0, int n);
// Level samples [kx0, kx0 + nx) x [ky0, ky0 + ny) of step `step`, bilinear in the overview's
// window `window` (its samples spanX x spanY, row-major); within half an overview cell of the
// raster's edge, linear extrapolation from the two outermost samples (exact for a plane, where
// clamping would shift the edge by half a cell times the slope). A no-data neighbour is left out
// of the weights (the others renormalised, no extrapolation); NaN where none of the four has data.
std::vector<float> resampleOverview(const std::vector<float>& window, const OverviewAxis& ax, const OverviewAxis& ay,
                                    OverviewSpan spanX, OverviewSpan spanY, int step, int kx0, int ky0, int nx, int ny);
// The overview of ratio `factor` of a cols x rows grid: means of the samples with data in each
// factor x factor block (NaN where none); ceil(cols / factor) x ceil(rows / factor) samples.
std::vector<float> averageBlocks(const std::vector<float>& z, int cols, int rows, int factor, int& outCols,
                                 int& outRows);

// A Heightfield in memory as a TerrainSource: level steps above 1 are read from a pyramid made by
// averaging 2 x 2 blocks (made on first use). For tests and for the browser, which has the DTM in
// memory anyway.
class HeightfieldTerrainSource final : public TerrainSource {
 public:
  explicit HeightfieldTerrainSource(Heightfield field);
  const TerrainGrid& grid() const override { return grid_; }
  std::vector<float> levelSamples(int step, int kx0, int ky0, int nx, int ny) const override;

 private:
  struct Overview {
    int cols = 0, rows = 0, ratio = 1;
    std::vector<float> z;
  };
  const Overview& overview(int ratio) const;
  Heightfield field_;
  TerrainGrid grid_;
  mutable std::mutex mutex_;
  mutable std::vector<std::unique_ptr<Overview>> pyramid_;  // ratios 2, 4, 8, ...
};

// A node: level (8 bits) | ty (28 bits) | tx (28 bits).
using TerrainNodeId = std::uint64_t;

struct TerrainTile {
  int level = 0, tx = 0, ty = 0;
  int kx0 = 0, ky0 = 0;  // its first level sample
  int nx = 0, ny = 0;    // cells; (nx + 1) x (ny + 1) samples
  std::vector<float> z;  // (ny + 1) rows of (nx + 1), NaN = no data
  Aabb bounds;           // world frame, heights from its samples; empty when it has no data
  // Geometric error (metres): the largest vertical deviation of the tile's surface (its two
  // triangles a cell, as in tileMesh) from the samples of the next level (its children's), 0 at
  // level L. One level only: detail two levels down that the next level averages away is not in it.
  double error = 0.0;
};

struct TerrainTileOptions {
  int tileCells = 64;  // n: a tile has (n + 1) x (n + 1) samples
  // The skirts' margin below what they must cover, as a fraction of the level's cell size.
  double skirtMarginCells = 0.1;
};

struct TerrainSelection {
  std::vector<TerrainNodeId> nodes;
  std::size_t triangles = 0;   // estimated: 2 a cell, 2 a skirt segment
  bool budgetLimited = false;  // some node above the tolerance was left unrefined by the budget
  int coarsestLevel = 0, finestLevel = 0;
};

class TerrainQuadtree {
 public:
  explicit TerrainQuadtree(std::shared_ptr<const TerrainSource> source, TerrainTileOptions options = {});

  const TerrainGrid& grid() const { return grid_; }
  const TerrainSource& source() const { return *source_; }
  const std::shared_ptr<const TerrainSource>& sharedSource() const { return source_; }
  const TerrainTileOptions& options() const { return options_; }
  int maxLevel() const { return maxLevel_; }  // L
  int tileCells() const { return options_.tileCells; }
  int step(int level) const { return 1 << (maxLevel_ - level); }
  // K_l: the last level-l sample per axis.
  int lastSampleX(int level) const;
  int lastSampleY(int level) const;

  static TerrainNodeId makeId(int level, int tx, int ty);
  static int levelOf(TerrainNodeId id) { return int(id >> 56); }
  static int txOf(TerrainNodeId id) { return int(id & 0xFFFFFFFu); }
  static int tyOf(TerrainNodeId id) { return int((id >> 28) & 0xFFFFFFFu); }
  static TerrainNodeId root() { return makeId(0, 0, 0); }
  bool exists(TerrainNodeId id) const;
  std::vector<TerrainNodeId> children(TerrainNodeId id) const;
  TerrainNodeId parent(TerrainNodeId id) const;

  // The tile's samples, bounds and error, read through the source on first use and kept (not
  // thread-safe: one quadtree per thread, or a lock around it). Throws InputError from the source.
  const TerrainTile& tile(TerrainNodeId id);
  std::size_t loadedTiles() const { return tiles_.size(); }
  // The same tile read through the source without keeping it: safe to call from several threads
  // (the source is), for the tiles streamed per view (hv/render/terrain_stream.h).
  TerrainTile readTile(TerrainNodeId id) const;
  // The most cells a node's tile has per axis (nx, ny of its TerrainTile), known without reading it.
  glm::ivec2 tileCellCount(TerrainNodeId id) const;
  // A node's extent on the ground, world frame: its first and last samples' positions, (x0, y0)
  // the lower corner, (x1, y1) the upper one. Known without reading it.
  glm::dvec4 footprint(TerrainNodeId id) const;

  // Screen-space error of a node seen from a camera: error * focal / distance, focal the larger of
  // fx, fy (pixels), distance from the centre to the node's box (at least 1e-3 of the box's size).
  double screenSpaceError(TerrainNodeId id, const Camera& camera);
  static double screenSpaceError(const TerrainTile& tile, const Camera& camera);
  // The nodes to draw for one view: every node is refined while its screen-space error exceeds
  // `tolerancePx`. They cover the raster's extent once (no overlap, no hole).
  std::vector<TerrainNodeId> select(const Camera& camera, double tolerancePx);
  // For a set of viewpoints (the photographs' cameras and the view): a node is refined while its
  // screen-space error from any of them exceeds `tolerancePx` (the finest level any viewpoint
  // needs), the largest error first, as long as the estimated triangles stay within
  // `triangleBudget`; so the farthest tiles are the ones left coarse when the budget runs out.
  // Without cameras, the nodes with the largest geometric error are refined first.
  TerrainSelection select(const std::vector<Camera>& cameras, double tolerancePx, std::size_t triangleBudget);

  // The tile's mesh (hv/scene/mesh.h: world frame, up-facing, as Heightfield::toMesh: two
  // triangles a cell whose four samples have data, no tags) with its skirts: along each border
  // that is not the raster's edge, a vertical strip going down by the skirt depth (outward-facing).
  Mesh tileMesh(TerrainNodeId id, bool skirts = true);
  // The tiles' meshes, appended.
  Mesh mesh(const std::vector<TerrainNodeId>& ids, bool skirts = true);
  // How far a tile's skirts go down: the margin, plus the tile's own error (a neighbour one level
  // finer may lie that much below it), plus the largest height by which the tile's border lies
  // above any coarser level's surface along the same line (every coarser neighbour's border: the
  // levels are nested, so that surface is its ancestors' along the line).
  double skirtDepth(TerrainNodeId id);
  // The same from the tile and its ancestors (any order; all of them, up to the root).
  double skirtDepth(const TerrainTile& tile, const std::vector<const TerrainTile*>& ancestors) const;
  // tileMesh from the tile and its skirt depth (0: no skirts).
  Mesh tileMesh(const TerrainTile& tile, bool skirts, double skirtDepth) const;

  // A whole level as a Heightfield (uniform cells of step * cell, its samples the level's samples
  // k <= (cols - 1) / step): the base heights of the buildings on a DTM too large to read whole.
  Heightfield levelHeightfield(int level) const;

 private:
  // The surface of a loaded tile at full-resolution sample coordinates (i, j), on its triangles;
  // NaN outside the tile or on no-data.
  double surfaceAt(const TerrainTile& t, double i, double j) const;
  double samplePos(int level, int k, bool yAxis) const;  // min(k s, count - 1)
  int estimatedTriangles(TerrainNodeId id) const;

  std::shared_ptr<const TerrainSource> source_;
  TerrainTileOptions options_;
  TerrainGrid grid_;
  int maxLevel_ = 0;
  std::map<TerrainNodeId, TerrainTile> tiles_;
};

}  // namespace hv
