#include "hv/io/native/raster.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace hv {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class RasterIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_raster_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  void writeText(const std::string& name, const std::string& text) const {
    std::ofstream(file(name)) << text;
  }

 private:
  fs::path dir_;
};

TEST_F(RasterIo, GeoTiffRoundTrip) {
  Heightfield f;
  f.cols = 4;
  f.rows = 3;
  f.originX = 651000.5;
  f.originY = 6862100.25;
  f.cellX = 0.5;
  f.cellY = -0.5;
  f.z = {30.0f, 30.5f, 31.0f, 31.25f, 29.0f,   std::numeric_limits<float>::quiet_NaN(),
         28.5f, 27.0f, -3.5f, 0.0f,   1234.5f, 42.0f};
  writeGeoTiff(file("dtm.tif"), f, "EPSG:2154");

  const Heightfield g = readHeightfield(file("dtm.tif"));
  EXPECT_EQ(g.cols, 4);
  EXPECT_EQ(g.rows, 3);
  EXPECT_DOUBLE_EQ(g.originX, 651000.5);
  EXPECT_DOUBLE_EQ(g.originY, 6862100.25);
  EXPECT_DOUBLE_EQ(g.cellX, 0.5);
  EXPECT_DOUBLE_EQ(g.cellY, -0.5);
  EXPECT_EQ(g.crs, "EPSG:2154");
  ASSERT_EQ(g.z.size(), f.z.size());
  for (size_t k = 0; k < f.z.size(); ++k) {
    if (std::isnan(f.z[k]))
      EXPECT_TRUE(std::isnan(g.z[k])) << k;
    else
      EXPECT_EQ(g.z[k], f.z[k]) << k;  // Float32 in, Float32 out: bit-exact
  }
  // Sample (1, 2) at (651000.5 + 1.5 * 0.5, 6862100.25 - 2.5 * 0.5).
  EXPECT_DOUBLE_EQ(*g.elevation(651001.25, 6862099.0), 0.0);
}

TEST_F(RasterIo, GeoTiffWithoutCrs) {
  Heightfield f;
  f.cols = f.rows = 2;
  f.originX = 10.0;
  f.originY = 20.0;
  f.z = {1, 2, 3, 4};
  writeGeoTiff(file("plain.tif"), f, "");
  const Heightfield g = readHeightfield(file("plain.tif"));
  EXPECT_TRUE(g.crs.empty());
  EXPECT_EQ(g.z, f.z);
}

TEST_F(RasterIo, AsciiGridNoDataAndGeotransform) {
  // ESRI ASCII grid: lower-left corner and square cells, rows from north to south.
  writeText("dtm.asc",
            "ncols 3\nnrows 2\nxllcorner 651000\nyllcorner 6862000\ncellsize 5\nNODATA_value -9999\n"
            "1.5 2.5 -9999\n4 5 6\n");
  const Heightfield g = readHeightfield(file("dtm.asc"));
  EXPECT_EQ(g.cols, 3);
  EXPECT_EQ(g.rows, 2);
  EXPECT_DOUBLE_EQ(g.originX, 651000.0);
  EXPECT_DOUBLE_EQ(g.originY, 6862000.0 + 2 * 5.0);  // top edge = yllcorner + nrows * cellsize
  EXPECT_DOUBLE_EQ(g.cellX, 5.0);
  EXPECT_DOUBLE_EQ(g.cellY, -5.0);
  ASSERT_EQ(g.z.size(), 6u);
  EXPECT_EQ(g.z[0], 1.5f);
  EXPECT_EQ(g.z[1], 2.5f);
  EXPECT_TRUE(std::isnan(g.z[2]));
  EXPECT_EQ(g.z[3], 4.0f);
  EXPECT_EQ(g.z[5], 6.0f);
}

TEST_F(RasterIo, NotARasterThrowsNamingTheFile) {
  writeText("notes.txt", "this is not an elevation model\n");
  for (const std::string& path : {file("notes.txt"), file("missing.tif")}) {
    try {
      readHeightfield(path);
      ADD_FAILURE() << "no exception for " << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST_F(RasterIo, UnwritablePathThrowsNamingTheFile) {
  Heightfield f;
  f.cols = f.rows = 1;
  f.z = {1.0f};
  const std::string path = file("no/such/dir/dtm.tif");
  try {
    writeGeoTiff(path, f, "");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hv
