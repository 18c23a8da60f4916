// Terrain benchmark: a 3000 x 3000 DTM (1 m cells, no overviews) loaded whole at full resolution
// (readHeightfield + Heightfield::toMesh, what a DTM at or below 2048^2 cells still gets) and as a
// quadtree of tiles selected for 36 street-level cameras (what loadScene does above 2048^2 cells:
// TerrainRaster, the pyramid in memory, selection by screen-space error <= 2 px, skirts), in one
// run: seconds, triangles, peak resident memory after each, and the ratios. Usage: terrain_bench.
// Figures: docs/performance.md.
#include "hv/io/native/raster.h"
#include "hv/io/native/scene_loader.h"
#include "hv/io/native/terrain_raster.h"
#include "hv/scene/terrain_quadtree.h"

#include "bench_common.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

// Rolling hills with metre-scale roughness (a DTM of a city's ground).
float height(int i, int j) {
  const double x = i, y = j;
  return float(40.0 + 15.0 * std::sin(x / 310.0) * std::cos(y / 270.0) + 3.0 * std::sin(x / 37.0 + y / 53.0) +
               0.4 * std::sin(x / 3.1) * std::cos(y / 4.3));
}

}  // namespace

int main() {
  constexpr int kSize = 3000;
  const std::string dir = (std::filesystem::temp_directory_path() / "histoview-terrain-bench").string();
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/dtm.tif";
  const double originX = 651000.0, originY = 6862000.0 + kSize;
  hv::writeTiledGeoTiff(path, kSize, kSize, originX, originY, 1.0, "EPSG:2154", height, false);
  std::printf("DTM %d x %d cells (%s); %s\n", kSize, kSize, path.c_str(), hv::bench::loadAverage().c_str());

  // 36 cameras along a street through the middle, 2.5 m above the ground, looking along it.
  std::vector<hv::Camera> cameras;
  for (int k = 0; k < 36; ++k) {
    const int i = 200 + k * 70, j = 1500;
    const glm::dvec3 c(originX + i + 0.5, originY - j - 0.5, height(i, j) + 2.5);
    cameras.push_back(hv::lookAtCamera("c" + std::to_string(k), c, c + glm::dvec3(30.0, (k % 2 ? 10.0 : -10.0), -2.0),
                                       2000, 1500, 1800.0));
  }

  auto t0 = hv::bench::Clock::now();
  size_t wholeTriangles = 0;
  {
    const hv::Heightfield whole = hv::readHeightfield(path);
    const hv::Mesh mesh = whole.toMesh();
    wholeTriangles = mesh.triangles.size();
  }
  const double wholeMs = hv::bench::msSince(t0);
  const long wholePeak = hv::bench::residentKb("VmHWM:");
  std::ofstream("/proc/self/clear_refs") << "5";  // Linux: the peak starts again from here

  t0 = hv::bench::Clock::now();
  hv::Diagnostics diag;
  std::string whyNot;
  auto raster = hv::TerrainRaster::open(path, {"", "EPSG:2154", "bench"}, diag, whyNot);
  if (!raster) {
    std::printf("not read as tiles: %s\n", whyNot.c_str());
    return 1;
  }
  hv::TerrainQuadtree tree(raster, hv::TerrainTileOptions{hv::kTerrainTileCells});
  const hv::TerrainSelection sel = tree.select(cameras, hv::kTerrainTolerancePx, hv::kTerrainTriangleBudget);
  const hv::Mesh tiles = tree.mesh(sel.nodes);
  const double tilesMs = hv::bench::msSince(t0);
  const long tilesPeak = hv::bench::residentKb("VmHWM:");

  std::printf("%-10s %10s %12s %14s\n", "terrain", "seconds", "triangles", "peak RSS MB");
  std::printf("%-10s %10.2f %12zu %14.0f\n", "whole", wholeMs / 1000.0, wholeTriangles, wholePeak / 1024.0);
  std::printf("%-10s %10.2f %12zu %14.0f\n", "quadtree", tilesMs / 1000.0, tiles.triangles.size(), tilesPeak / 1024.0);
  std::printf("quadtree: %zu tiles, levels %d..%d of 0..%d, %zu tiles read%s\n", sel.nodes.size(), sel.coarsestLevel,
              sel.finestLevel, tree.maxLevel(), tree.loadedTiles(), sel.budgetLimited ? ", budget reached" : "");
  std::printf("ratio whole / quadtree: time %.2f, triangles %.1f\n", wholeMs / tilesMs,
              double(wholeTriangles) / double(tiles.triangles.size()));
  std::filesystem::remove_all(dir);
  return 0;
}
