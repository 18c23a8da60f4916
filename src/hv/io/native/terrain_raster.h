// A terrain raster read by window at any level of a TerrainQuadtree (hv/scene/terrain_quadtree.h),
// through GDAL, never whole at full resolution (docs/design.md, "Terrain tiles"). GDAL itself is
// only included under hv/io/native/private/.
//
// Where a level's samples come from: the coarsest of the raster's overviews (GDAL's, e.g. made by
// `gdaladdo -r average`) whose ratio does not exceed the level's step, else the full-resolution
// band. A raster over kTerrainTilesAboveCells whose coarsest overview (or itself, without any)
// holds more than kTerrainPyramidCells gets a pyramid of averages built in memory once, reading
// the band by strips (never the full resolution whole): its finest grid within
// kTerrainPyramidCells, then halved down to one tile. It is not written anywhere (no cache folder:
// nothing is left beside the user's data or elsewhere); a warning says it was built and how to
// avoid it. No-data as readHeightfield (hv/io/native/raster.h): GDAL's no-data value and NaN are
// no data, scale and offset applied; heights into the scene's metres as readHeightfield does.
#pragma once

#include "hv/io/native/georef.h"
#include "hv/scene/scene_frame.h"
#include "hv/scene/terrain_quadtree.h"
#include "hv/util/diagnostics.h"

#include <cstdint>
#include <memory>
#include <string>

namespace hv {

// Above kTerrainTilesAboveCells (hv/scene/scene_frame.h), `loadScene` makes the terrain from a
// quadtree of tiles (docs/formats.md, Limits); at or below it, the whole raster is meshed.
// The most samples of the pyramid built in memory (its finest grid), and of any one window read.
constexpr std::uint64_t kTerrainPyramidCells = std::uint64_t(2048) * 2048;

struct RasterSize {
  int cols = 0, rows = 0;
  int overviews = 0;  // GDAL overviews of band 1
};
// The size of band 1 without reading it. Throws InputError naming the file.
RasterSize rasterSize(const std::string& path);

// What a TerrainRaster read, for tests and `histoview info`.
struct TerrainRasterStats {
  std::uint64_t fullResolutionSamples = 0;  // read from band 1 at full resolution
  std::uint64_t overviewSamples = 0;        // read from GDAL overviews
  std::uint64_t pyramidSamples = 0;         // taken from the pyramid in memory
  std::uint64_t pyramidBuildSamples = 0;    // read once to build the pyramid
  std::uint64_t largestWindow = 0;          // the most samples one read asked for
  int reads = 0;                            // windows read
};

class TerrainRaster final : public TerrainSource {
 public:
  // Opens the raster and brings it into the scene frame as readHeightfield(path, georef, diag)
  // would, with the same checks and errors (InputError naming the file). Returns null with
  // `whyNot` set when the raster cannot be read by window: its horizontal CRS differs from the
  // scene's, so GDAL would have to warp it whole.
  static std::shared_ptr<TerrainRaster> open(const std::string& path, const SourceGeoref& georef, Diagnostics& diag,
                                             std::string& whyNot);
  ~TerrainRaster() override;

  const TerrainGrid& grid() const override;
  std::vector<float> levelSamples(int step, int kx0, int ky0, int nx, int ny) const override;

  const std::string& path() const;
  const std::string& sourceCrs() const;  // as GeoreferencedHeightfield::sourceCrs
  int gdalOverviews() const;             // overviews of band 1 in the file
  int pyramidLevels() const;             // levels of the pyramid built in memory; 0: none
  TerrainRasterStats stats() const;

 private:
  TerrainRaster();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hv
