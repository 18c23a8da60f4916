// scene.json "orthophoto" through GDAL: a cloud-optimised GeoTIFF written and read back over a
// terrain extent, as it is, coarser, beyond its edges, warped from another CRS, and its failures.
#include "hv/io/native/orthophoto_reader.h"

#include "hv/io/native/georef.h"
#include "hv/io/native/raster.h"
#include "hv/io/native/scene_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

class OrthophotoReaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_orthophoto_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// w x h texels of `pixel` metres from (x0, y1), the north-west corner: red 2 i, green 3 j (mod 256),
// blue 77, opaque.
Orthophoto gradient(double x0, double y1, double pixel, int w, int h) {
  Orthophoto o;
  o.width = w, o.height = h;
  o.minX = x0, o.maxX = x0 + w * pixel, o.maxY = y1, o.minY = y1 - h * pixel;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) o.rgba.insert(o.rgba.end(), {std::uint8_t(2 * i), std::uint8_t(3 * j), 77, 255});
  return o;
}

OrthophotoRequest over(const std::string& path, const Orthophoto& o, const std::string& sceneCrs) {
  OrthophotoRequest r;
  r.path = path;
  r.field = "orthophoto.path";
  r.sceneCrs = sceneCrs;
  r.minX = o.minX, r.minY = o.minY, r.maxX = o.maxX, r.maxY = o.maxY;
  return r;
}

TEST_F(OrthophotoReaderTest, ReadOverItsOwnGridItIsTheSamePixels) {
  const Orthophoto o = gradient(651000, 6862100, 0.5, 90, 60);
  const std::string path = (dir_ / "ortho.tif").string();
  writeOrthophotoCog(path, o, "EPSG:2154");
  Diagnostics diag;
  const Orthophoto back = readOrthophoto(over(path, o, "EPSG:2154"), diag);
  EXPECT_TRUE(diag.warnings.empty());
  ASSERT_EQ(back.width, 90);
  ASSERT_EQ(back.height, 60);
  EXPECT_DOUBLE_EQ(back.metresPerPixelX(), 0.5);
  EXPECT_EQ(back.rgba, o.rgba);
  // No scene CRS: the raster as it is, the same.
  EXPECT_EQ(readOrthophoto(over(path, o, ""), diag).rgba, o.rgba);
}

TEST_F(OrthophotoReaderTest, ResolutionAndExtentChooseTheSizeAndOutsideIsTransparent) {
  const Orthophoto o = gradient(651000, 6862100, 0.5, 90, 60);
  const std::string path = (dir_ / "ortho.tif").string();
  writeOrthophotoCog(path, o, "EPSG:2154");
  Diagnostics diag;
  OrthophotoRequest r = over(path, o, "EPSG:2154");
  r.resolution = 1.5;
  const Orthophoto coarse = readOrthophoto(r, diag);
  EXPECT_EQ(coarse.width, 30);
  EXPECT_EQ(coarse.height, 20);
  // Ten metres more to the east than the raster covers: those columns are transparent.
  r = over(path, o, "EPSG:2154");
  r.maxX += 10.0;
  const Orthophoto wider = readOrthophoto(r, diag);
  ASSERT_EQ(wider.width, 110);
  EXPECT_EQ(wider.rgba[(std::size_t(30) * 110 + 105) * 4 + 3], 0);
  EXPECT_EQ(wider.rgba[(std::size_t(30) * 110 + 40) * 4 + 3], 255);
  EXPECT_EQ(wider.rgba[(std::size_t(30) * 110 + 40) * 4 + 0], 80);
  EXPECT_EQ(wider.rgba[(std::size_t(30) * 110 + 40) * 4 + 1], 90);
  // A larger extent than kMaxOrthophotoSide pixels of the raster's own: capped.
  r = over(path, o, "EPSG:2154");
  r.maxX = r.minX + 3000.0;
  const Orthophoto capped = readOrthophoto(r, diag);
  EXPECT_EQ(capped.width, kMaxOrthophotoSide);
}

TEST_F(OrthophotoReaderTest, AnotherCrsIsWarpedIntoTheScenes) {
  // Web Mercator around the demo city: red west of x = cx, blue east of it.
  Diagnostics diag;
  const GeoTransform toMercator("EPSG:2154", "EPSG:3857", diag);
  const glm::dvec3 c = toMercator.point({651000, 6862000, 0});
  Orthophoto m;
  m.width = m.height = 200;
  m.minX = c.x - 100, m.maxX = c.x + 100, m.minY = c.y - 100, m.maxY = c.y + 100;
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 200; ++i)
      m.rgba.insert(m.rgba.end(), {std::uint8_t(i < 100 ? 255 : 0), 0, std::uint8_t(i < 100 ? 0 : 255), 255});
  const std::string path = (dir_ / "mercator.tif").string();
  writeOrthophotoCog(path, m, "EPSG:3857");
  // The split, in Lambert-93, on the row through the centre.
  const GeoTransform back("EPSG:3857", "EPSG:2154", diag);
  const glm::dvec3 split = back.point({c.x, c.y, 0});
  OrthophotoRequest r;
  r.path = path;
  r.field = "orthophoto.path";
  r.sceneCrs = "EPSG:2154";
  r.resolution = 0.5;
  r.minX = 651000 - 40, r.maxX = 651000 + 40, r.minY = 6862000 - 20, r.maxY = 6862000 + 20;
  const Orthophoto o = readOrthophoto(r, diag);
  ASSERT_EQ(o.width, 160);
  ASSERT_EQ(o.height, 80);
  auto at = [&](double x) {
    const glm::dvec2 uv = orthophotoTexCoord(o, x, split.y);
    const int i = int(uv.x * o.width), j = int(uv.y * o.height);
    return glm::ivec3(o.rgba[(std::size_t(j) * o.width + i) * 4], o.rgba[(std::size_t(j) * o.width + i) * 4 + 1],
                      o.rgba[(std::size_t(j) * o.width + i) * 4 + 2]);
  };
  EXPECT_EQ(at(split.x - 2.0), glm::ivec3(255, 0, 0));
  EXPECT_EQ(at(split.x + 2.0), glm::ivec3(0, 0, 255));
  // The split is about 0.66 m of Lambert-93 per Mercator metre from the centre: not where the
  // raster's own centre column would be without the warp (|split.x - 651000| is small, the scale
  // is not 1).
  EXPECT_NE(at(split.x - 2.0), at(split.x + 2.0));
}

TEST_F(OrthophotoReaderTest, FailuresNameThePathAndTheFieldAndWhatWasExpected) {
  Diagnostics diag;
  OrthophotoRequest r = over((dir_ / "none.tif").string(), gradient(0, 10, 1, 10, 10), "");
  try {
    readOrthophoto(r, diag);
    FAIL() << "a missing file was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none.tif"), std::string::npos) << e.what();
  }
  // No terrain extent.
  const std::string path = (dir_ / "ortho.tif").string();
  writeOrthophotoCog(path, gradient(0, 10, 1, 10, 10), "");
  r = over(path, Orthophoto{}, "");
  try {
    readOrthophoto(r, diag);
    FAIL() << "read without an extent";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expected a terrain"), std::string::npos) << e.what();
  }
}

// Through scene.json: a bad field or file leaves the orthophoto out with a warning naming it, the
// scene loading as without one; a good one is read over the terrain.
TEST_F(OrthophotoReaderTest, SceneJsonOrthophotoIsReadOverTheTerrainOrLeftOutWithAWarning) {
  const std::string path = (dir_ / "ortho.tif").string();
  writeOrthophotoCog(path, gradient(-5, 25, 0.5, 60, 60), "");
  Heightfield dtm;
  dtm.cols = dtm.rows = 20;
  dtm.originX = 0, dtm.originY = 20, dtm.cellX = 1, dtm.cellY = -1;
  dtm.z.assign(400, 3.0f);
  writeGeoTiff((dir_ / "dtm.tif").string(), dtm, "");
  auto scene = [&](const std::string& ortho) {
    std::ofstream((dir_ / "scene.json").string())
        << R"({"terrain": {"path": "dtm.tif"}, "orthophoto": )" << ortho << "}";
    Diagnostics diag;
    const Scene s = loadScene((dir_ / "scene.json").string(), diag);
    Diagnostics o;
    auto ortho2 = loadOrthophoto(s, o);
    return std::make_pair(ortho2, o.warnings);
  };
  {
    const auto [o, warnings] = scene(R"({"path": "ortho.tif"})");
    ASSERT_TRUE(o) << (warnings.empty() ? "" : warnings[0]);
    EXPECT_GT(o->width, 0);
  }
  {
    const auto [o, warnings] = scene(R"({"path": "missing.tif"})");
    EXPECT_FALSE(o);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("missing.tif"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("orthophoto left out"), std::string::npos) << warnings[0];
  }
  {
    const auto [o, warnings] = scene(R"({"path": "ortho.tif", "resolution": -1})");
    EXPECT_FALSE(o);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("orthophoto.resolution: expected metres per pixel"), std::string::npos) << warnings[0];
  }
}

}  // namespace
}  // namespace hv
