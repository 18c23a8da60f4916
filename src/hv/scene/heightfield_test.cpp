#include "hv/scene/heightfield.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hv {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// 3 x 2 north-up grid, 10 m cells; sample (i, j) at (1005 + 10 i, 1995 - 10 j):
//   row 0:  10  20  30
//   row 1:  40  70  NaN
Heightfield smallGrid() {
  Heightfield f;
  f.cols = 3;
  f.rows = 2;
  f.originX = 1000.0;
  f.originY = 2000.0;
  f.cellX = 10.0;
  f.cellY = -10.0;
  f.z = {10, 20, 30, 40, 70, kNaN};
  return f;
}

TEST(Heightfield, SamplePositionIsCellCentre) {
  const Heightfield f = smallGrid();
  EXPECT_EQ(f.samplePosition(0, 0), glm::dvec2(1005.0, 1995.0));
  EXPECT_EQ(f.samplePosition(2, 1), glm::dvec2(1025.0, 1985.0));
}

TEST(Heightfield, BilinearElevation) {
  const Heightfield f = smallGrid();
  // On samples.
  EXPECT_DOUBLE_EQ(*f.elevation(1005.0, 1995.0), 10.0);
  EXPECT_DOUBLE_EQ(*f.elevation(1015.0, 1985.0), 70.0);
  // Centre of the first four samples: (10 + 20 + 40 + 70) / 4.
  EXPECT_DOUBLE_EQ(*f.elevation(1010.0, 1990.0), 35.0);
  // A quarter of the way in both directions: weights 9/16, 3/16, 3/16, 1/16
  // -> 5.625 + 3.75 + 7.5 + 4.375 = 21.25.
  EXPECT_DOUBLE_EQ(*f.elevation(1007.5, 1992.5), 21.25);
  // Along the top row between 20 and 30, 0.3 of the way: 23.
  EXPECT_NEAR(*f.elevation(1018.0, 1995.0), 23.0, 1e-12);
  // A sample next to no-data keeps its value (its neighbour weighs zero) ...
  EXPECT_DOUBLE_EQ(*f.elevation(1025.0, 1995.0), 30.0);
  // ... but a point whose cell includes the missing sample has none.
  EXPECT_FALSE(f.elevation(1020.0, 1990.0).has_value());
  // The half cell between the outer samples and the raster edge extends the border samples.
  EXPECT_DOUBLE_EQ(*f.elevation(1001.0, 1999.0), 10.0);
  // Outside the raster.
  EXPECT_FALSE(f.elevation(999.0, 1995.0).has_value());
  EXPECT_FALSE(f.elevation(1005.0, 2000.5).has_value());
  EXPECT_FALSE(f.elevation(1005.0, 1979.0).has_value());
  EXPECT_FALSE(Heightfield{}.elevation(0.0, 0.0).has_value());
}

TEST(Heightfield, MinUnderUsesVerticesAndSkipsNoData) {
  const Heightfield f = smallGrid();
  // Ring over x in [1008, 1018], y in [1983, 1998]. Vertices (by hand, bilinear):
  // (1008, 1983) -> 0.7 * 40 + 0.3 * 70 = 49; (1018, 1983) -> cell with NaN, none;
  // (1018, 1998) -> 0.7 * 20 + 0.3 * 30 = 23; (1008, 1998) -> 0.7 * 10 + 0.3 * 20 = 13.
  // Samples inside: (1015, 1995) = 20 and (1015, 1985) = 70. Lowest: 13.
  const std::vector<glm::dvec2> ring = {{1008, 1983}, {1018, 1983}, {1018, 1998}, {1008, 1998}};
  EXPECT_NEAR(*f.minUnder(ring), 13.0, 1e-9);
  // Entirely outside: nothing.
  EXPECT_FALSE(f.minUnder({{0, 0}, {1, 0}, {1, 1}}).has_value());
}

TEST(Heightfield, MinUnderSeesInteriorSamples) {
  // 4 x 4, 1 m cells, origin (0, 0), north-up: sample (i, j) at (i + 0.5, -j - 0.5). All 100 but
  // (1, 1) = 5 (inside the ring) and (3, 3) = 1 (outside it).
  Heightfield f;
  f.cols = f.rows = 4;
  f.originX = f.originY = 0.0;
  f.cellX = 1.0;
  f.cellY = -1.0;
  f.z.assign(16, 100.0f);
  f.z[1 * 4 + 1] = 5.0f;
  f.z[3 * 4 + 3] = 1.0f;
  // Square around (1.5, -1.5); its vertices interpolate to 53.45 (e.g. weights .51 on 100, .49 on 5).
  const std::vector<glm::dvec2> ring = {{1.2, -1.8}, {1.8, -1.8}, {1.8, -1.2}, {1.2, -1.2}};
  EXPECT_DOUBLE_EQ(*f.minUnder(ring), 5.0);
}

glm::dvec3 normalOf(const Mesh& m, const glm::uvec3& t) {
  return glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
}

Heightfield flatGrid(int cols, int rows, double cellX, double cellY) {
  Heightfield f;
  f.cols = cols;
  f.rows = rows;
  f.originX = 500.0;
  f.originY = 800.0;
  f.cellX = cellX;
  f.cellY = cellY;
  f.z.assign(size_t(cols) * rows, 12.0f);
  return f;
}

TEST(Heightfield, ToMeshTrianglesAreUpFacing) {
  for (const double cellY : {-2.0, 2.0}) {  // north-up and south-up rasters
    const Heightfield f = flatGrid(4, 3, 2.0, cellY);
    const Mesh m = f.toMesh();
    EXPECT_EQ(m.positions.size(), 12u);
    EXPECT_EQ(m.triangles.size(), 3u * 2u * 2u);  // (cols - 1) * (rows - 1) cells, two triangles each
    for (const auto& t : m.triangles) EXPECT_GT(normalOf(m, t).z, 0.0);
    // Spans sample centres: 3 cells * 2 cells of 2 m x 2 m.
    EXPECT_NEAR(m.area(), 6.0 * 4.0, 1e-9);
    EXPECT_DOUBLE_EQ(m.bounds().lo.z, 12.0);
  }
}

TEST(Heightfield, ToMeshSkipsCellsWithoutData) {
  Heightfield f = flatGrid(4, 3, 2.0, -2.0);
  f.z[1 * 4 + 1] = kNaN;  // touches the four cells (0..1, 0..1); cells (2, 0) and (2, 1) remain
  const Mesh m = f.toMesh();
  EXPECT_EQ(m.triangles.size(), 4u);
  for (const auto& p : m.positions) EXPECT_FALSE(std::isnan(p.z));
}

TEST(Heightfield, ToMeshStrideDecimatesAndKeepsExtent) {
  const Heightfield f = flatGrid(5, 5, 1.0, -1.0);
  const Mesh m = f.toMesh(2);  // samples 0, 2, 4 in each direction
  EXPECT_EQ(m.positions.size(), 9u);
  EXPECT_EQ(m.triangles.size(), 8u);
  EXPECT_NEAR(m.area(), 16.0, 1e-9);
  // A stride that does not divide the grid keeps the last row/column: samples 0, 3, 4.
  const Mesh m3 = f.toMesh(3);
  EXPECT_EQ(m3.triangles.size(), 8u);
  EXPECT_NEAR(m3.area(), 16.0, 1e-9);
}

}  // namespace
}  // namespace hv
