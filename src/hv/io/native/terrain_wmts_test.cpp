// The terrain read from a WMTS of elevation tiles equals the terrain read from the file the
// server tiles (docs/services.md, "Elevation by WMTS"). Needs the server: tests/terrain_wmts_test.sh
// starts MapCache and MapServer on loopback and runs this test with
//   HV_TEST_WMTS_TERRAIN       the WMTS source (a GDAL_WMTS description naming the capabilities)
//   HV_TEST_WMTS_TERRAIN_FILE  the DTM file the server tiles
// Without them it is skipped (the unit test run has no server).
#include "hv/io/native/raster.h"
#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

namespace hv {
namespace {

TEST(TerrainWmts, SameHeightsAsTheFile) {
  const char* wmts = std::getenv("HV_TEST_WMTS_TERRAIN");
  const char* file = std::getenv("HV_TEST_WMTS_TERRAIN_FILE");
  // Only tests/terrain_wmts_test.sh runs this test (ctest terrain_wmts), with the server it starts;
  // the discovered hv_tests list leaves it out (CMakeLists.txt), so a missing server is a failure.
  ASSERT_TRUE(wmts && file) << "HV_TEST_WMTS_TERRAIN and HV_TEST_WMTS_TERRAIN_FILE unset: run tests/terrain_wmts_test.sh";
  SourceGeoref georef;
  georef.sceneCrs = "EPSG:2154";
  Diagnostics diag;
  const Heightfield a = readHeightfield(file, georef, diag).field;
  const Heightfield b = readHeightfield(wmts, georef, diag).field;
  for (const std::string& e : diag.errors) ADD_FAILURE() << e;
  ASSERT_EQ(b.cols, a.cols);
  ASSERT_EQ(b.rows, a.rows);
  // The same grid: MapCache's grid is the file's (its corner, its cell size at the finest level).
  EXPECT_NEAR(b.originX, a.originX, 1e-6 * std::abs(a.cellX));
  EXPECT_NEAR(b.originY, a.originY, 1e-6 * std::abs(a.cellY));
  EXPECT_NEAR(b.cellX, a.cellX, 1e-9 * std::abs(a.cellX));
  EXPECT_NEAR(b.cellY, a.cellY, 1e-9 * std::abs(a.cellY));
  // The same heights: float32 tiles of the float32 file, sampled at the file's own cells.
  double worst = 0.0;
  std::size_t missing = 0;
  for (std::size_t i = 0; i < a.z.size(); ++i) {
    if (std::isnan(a.z[i]) != std::isnan(b.z[i])) {
      ++missing;
      continue;
    }
    if (!std::isnan(a.z[i])) worst = std::max(worst, double(std::abs(a.z[i] - b.z[i])));
  }
  EXPECT_EQ(missing, 0u) << "cells with data in one and no data in the other";
  EXPECT_LE(worst, 1e-3) << "the largest height difference, in metres";
  std::printf("terrain from WMTS: %d x %d cells, largest height difference %.6g m\n", a.cols, a.rows, worst);
}

}  // namespace
}  // namespace hv
