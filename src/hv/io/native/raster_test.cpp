#include "hv/io/native/raster.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
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

// A tiled Float32 GeoTIFF of cols x rows cells whose tiles are all absent (offset and byte count 0:
// GDAL reads them as zeros), so a raster of billions of cells is a few hundred kilobytes on disk.
// Classic little-endian TIFF (TIFF 6.0 tags) with the GeoTIFF pixel scale and tie point.
void writeSparseGeoTiff(const std::string& path, std::uint32_t cols, std::uint32_t rows) {
  const std::uint32_t tile = 256;
  const std::uint32_t tiles = ((cols + tile - 1) / tile) * ((rows + tile - 1) / tile);
  std::string out;
  auto u16 = [&](std::uint16_t v) { out.append(reinterpret_cast<const char*>(&v), 2); };
  auto u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  auto f64 = [&](double v) { out.append(reinterpret_cast<const char*>(&v), 8); };
  const std::uint16_t entries = 14;
  const std::uint32_t data = 8 + 2 + 12u * entries + 4;  // after the header and the one IFD
  const std::uint32_t scaleAt = data, tieAt = scaleAt + 24, offsetsAt = tieAt + 48, countsAt = offsetsAt + 4 * tiles;
  out += "II";
  u16(42);
  u32(8);
  u16(entries);
  auto entry = [&](std::uint16_t tag, std::uint16_t type, std::uint32_t count, std::uint32_t value) {
    u16(tag);
    u16(type);
    u32(count);
    u32(value);  // SHORT values sit in the low half (little-endian)
  };
  const std::uint16_t SHORT = 3, LONG = 4, DOUBLE = 12;
  entry(256, LONG, 1, cols);
  entry(257, LONG, 1, rows);
  entry(258, SHORT, 1, 32);   // bits per sample
  entry(259, SHORT, 1, 1);    // no compression
  entry(262, SHORT, 1, 1);    // min-is-black
  entry(277, SHORT, 1, 1);    // one sample per pixel
  entry(284, SHORT, 1, 1);    // chunky
  entry(322, SHORT, 1, tile);
  entry(323, SHORT, 1, tile);
  entry(324, LONG, tiles, offsetsAt);
  entry(325, LONG, tiles, countsAt);
  entry(339, SHORT, 1, 3);    // IEEE floating point
  entry(33550, DOUBLE, 3, scaleAt);
  entry(33922, DOUBLE, 6, tieAt);
  u32(0);  // no next IFD
  for (double v : {1.0, 1.0, 0.0}) f64(v);
  for (double v : {0.0, 0.0, 0.0, 651000.0, 6862000.0, 0.0}) f64(v);
  out.append(size_t(8) * tiles, '\0');  // offsets and byte counts, all 0
  std::ofstream(path, std::ios::binary) << out;
}

TEST_F(RasterIo, AHugeRasterIsReadDecimatedBeforeAnythingIsAllocated) {
  // 20000 x 20000 cells would be 1.6 GB of floats: read at the smallest step under
  // kMaxRasterCells (6144^2): 1/4 (1/3 would be 6667^2 = 44.4M cells). (40000 x 40000, a 296 KB
  // file, reads at 1/7 the same way; four times slower, so not in the suite.)
  const std::string path = file("huge.tif");
  writeSparseGeoTiff(path, 20000, 20000);
  ASSERT_LT(fs::file_size(path), 100u * 1024);
  Diagnostics diag;
  const GeoreferencedHeightfield read = readHeightfield(path, SourceGeoref{}, diag);
  const Heightfield& g = read.field;
  EXPECT_EQ(g.cols, 5000);
  EXPECT_EQ(g.rows, 5000);
  EXPECT_LE(std::uint64_t(g.cols) * g.rows, kMaxRasterCells);
  // Same extent: 20000 one-metre cells.
  EXPECT_NEAR(g.cellX * g.cols, 20000.0, 1e-6);
  EXPECT_NEAR(g.cellY * g.rows, -20000.0, 1e-6);
  EXPECT_DOUBLE_EQ(g.originX, 651000.0);
  EXPECT_EQ(g.z[12345], 0.0f);
  ASSERT_EQ(diag.warnings.size(), 1u);
  const std::string& w = diag.warnings[0];
  EXPECT_NE(w.find(path), std::string::npos) << w;
  EXPECT_NE(w.find("20000 x 20000"), std::string::npos) << w;
  EXPECT_NE(w.find("1/4"), std::string::npos) << w;
}

TEST_F(RasterIo, ARasterUnderTheCapIsReadWhole) {
  const std::string path = file("small.tif");
  writeSparseGeoTiff(path, 600, 500);
  Diagnostics diag;
  const Heightfield g = readHeightfield(path, SourceGeoref{}, diag).field;
  EXPECT_EQ(g.cols, 600);
  EXPECT_EQ(g.rows, 500);
  EXPECT_DOUBLE_EQ(g.cellX, 1.0);
  EXPECT_TRUE(diag.warnings.empty());
}

TEST_F(RasterIo, EmptyOrAllNoDataTerrainIsRefusedNamingTheFile) {
  Heightfield f;
  f.cols = 3;
  f.rows = 2;
  f.z.assign(6, std::numeric_limits<float>::quiet_NaN());
  writeGeoTiff(file("nodata.tif"), f, "");
  Heightfield one;
  one.cols = one.rows = 1;
  one.z = {5.0f};
  writeGeoTiff(file("one.tif"), one, "");
  for (const auto& [name, why] : {std::pair<std::string, std::string>{"nodata.tif", "no-data"}, {"one.tif", "2 x 2"}}) {
    try {
      readHeightfield(file(name));
      ADD_FAILURE() << name << " read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(file(name)), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }
}

TEST_F(RasterIo, AFifoIsRefusedBeforeGdalOpensIt) {
  ASSERT_EQ(::mkfifo(file("dtm.tif").c_str(), 0600), 0);
  try {
    readHeightfield(file("dtm.tif"));
    ADD_FAILURE() << "read a FIFO";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("FIFO"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hv
