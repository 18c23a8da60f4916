// A regular elevation grid (a DTM) in the world frame. Plain data: the GDAL reader in
// hv/io/raster.h fills it; the mesh builder and the LOD1 base heights read it.
// Grid convention: sample (i, j) (column i, row j, row 0 = north edge) sits at the *centre* of
// its raster cell: x = originX + (i + 0.5) * cellX, y = originY + (j + 0.5) * cellY, with
// cellY < 0 for north-up rasters (GDAL geotransform, PixelIsArea).
#pragma once

#include "hv/scene/mesh.h"

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace hv {

struct Heightfield {
  int cols = 0, rows = 0;
  double originX = 0.0, originY = 0.0;  // corner of cell (0, 0) (GDAL geotransform [0], [3])
  double cellX = 1.0, cellY = -1.0;     // GDAL geotransform [1], [5]
  std::vector<float> z;                 // rows * cols, row-major; NaN = no data
  std::string crs;                      // WKT or "EPSG:n" of x, y: as read, or the scene CRS once georeferenced; informative

  bool empty() const { return z.empty(); }
  float at(int i, int j) const { return z[size_t(j) * cols + i]; }
  glm::dvec2 samplePosition(int i, int j) const;
  // Bilinear elevation at (x, y); nullopt outside the grid or on no-data.
  std::optional<double> elevation(double x, double y) const;
  // Lowest elevation over a polygon (outer ring; holes ignored): the vertices and every grid
  // sample inside it. nullopt when none of them has data.
  std::optional<double> minUnder(const std::vector<glm::dvec2>& ring) const;
  // Triangulated surface, two triangles per grid cell whose four samples have data, up-facing.
  // `stride` > 1 decimates the grid.
  Mesh toMesh(int stride = 1) const;
};

}  // namespace hv
