#include "hv/scene/point_cloud.h"

#include <gtest/gtest.h>

namespace hv {
namespace {

PointCloud cloud(std::size_t n, const PointFields& fields, float base) {
  PointCloud c;
  c.resize(n, fields);
  for (std::size_t i = 0; i < n; ++i) {
    c.positions[i] = glm::dvec3(base + double(i), 0.0, 0.0);
    if (fields.classification) c.classification[i] = std::uint8_t(base + float(i));
  }
  return c;
}

TEST(PointCloudAppend, JoinsTheFieldsBothHaveAndDropsTheOthers) {
  PointFields withClasses;
  withClasses.classification = true;
  withClasses.rgb = true;
  PointFields classesOnly;
  classesOnly.classification = true;

  PointCloud into;
  into.crs = "EPSG:2154";
  into.sourcePath = "http://127.0.0.1/tileset.json";
  PointCloud first = cloud(2, withClasses, 10.0f);
  first.crs = "EPSG:4978";
  first.sourcePath = "http://127.0.0.1/0.pnts";
  into.append(first);
  // An empty cloud takes the first tile whole but keeps its own CRS and source.
  EXPECT_EQ(into.crs, "EPSG:2154");
  EXPECT_EQ(into.sourcePath, "http://127.0.0.1/tileset.json");
  ASSERT_EQ(into.size(), 2u);
  EXPECT_TRUE(into.fields().rgb);

  into.append(cloud(3, classesOnly, 20.0f));
  ASSERT_EQ(into.size(), 5u);
  EXPECT_TRUE(into.consistent());
  EXPECT_TRUE(into.fields().classification);
  EXPECT_FALSE(into.fields().rgb);  // the second tile has no colours: dropped for all
  const std::vector<std::uint8_t> classes{10, 11, 20, 21, 22};
  EXPECT_EQ(into.classification, classes);
  EXPECT_DOUBLE_EQ(into.positions[4].x, 22.0);

  into.append(PointCloud{});  // nothing to add
  EXPECT_EQ(into.size(), 5u);

  PointCloud bare;  // no CRS or source of its own: takes the tile's
  bare.append(first);
  EXPECT_EQ(bare.crs, "EPSG:4978");
  EXPECT_EQ(bare.sourcePath, "http://127.0.0.1/0.pnts");
}

}  // namespace
}  // namespace hv
