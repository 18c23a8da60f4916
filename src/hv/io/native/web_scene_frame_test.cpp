// A service scene read by the page without an export (hv/io/web_scene_frame.h) against the native
// loader on the same data: the DTM as a GeoTIFF read by GDAL natively, as the ESRI ASCII grid a WCS
// answers in the page; the same terrain mesh, origin, up and terrain rectangle, and those against
// values worked out here from the grid itself.
#include "hv/io/web_scene_frame.h"
#include "hv/io/native/raster.h"
#include "hv/io/native/scene_loader.h"
#include "hv/io/web_scene.h"
#include "hv/scene/scene_frame.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

// A 61 x 47 grid of 2 m cells in Lambert-93 with a float32 relief (no-data in one corner).
Heightfield relief() {
  Heightfield f;
  f.cols = 61;
  f.rows = 47;
  f.originX = 651003.0;
  f.originY = 6862117.0;
  f.cellX = 2.0;
  f.cellY = -2.0;
  f.z.resize(std::size_t(f.cols) * f.rows);
  for (int j = 0; j < f.rows; ++j)
    for (int i = 0; i < f.cols; ++i)
      f.z[std::size_t(j) * f.cols + i] =
          float(31.25 + 0.37 * i - 0.11 * j + 1.7 * std::sin(0.3 * i) * std::cos(0.2 * j));
  f.z[0] = std::nanf("");
  return f;
}

// The grid as MapServer's WCS writes it (GDAL's AAIGrid, 9 significant digits: float32 exactly).
std::string aaiGrid(const Heightfield& f) {
  std::ostringstream s;
  char v[32];
  s << "ncols " << f.cols << "\nnrows " << f.rows << "\n";
  std::snprintf(v, sizeof v, "%.17g", f.originX);
  s << "xllcorner " << v << "\n";
  std::snprintf(v, sizeof v, "%.17g", f.originY + f.rows * f.cellY);
  s << "yllcorner " << v << "\ncellsize " << f.cellX << "\nNODATA_value -9999\n";
  for (int j = 0; j < f.rows; ++j) {
    for (int i = 0; i < f.cols; ++i) {
      const float z = f.at(i, j);
      if (std::isnan(z))
        s << " -9999";
      else {
        std::snprintf(v, sizeof v, " %.9g", double(z));
        s << v;
      }
    }
    s << "\n";
  }
  return s.str();
}

class WebSceneFrame : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_web_scene_frame_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream((dir_ / name).string(), std::ios::binary) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

TEST_F(WebSceneFrame, GridTerrainOriginAndExtentMatchTheNativeLoader) {
  const Heightfield f = relief();
  writeGeoTiff((dir_ / "dtm.tif").string(), f, "EPSG:2154");
  write("cameras.json", R"({"cameras": []})");
  const std::string scenePath = write("scene.json", R"({"crs": "EPSG:2154", "terrain": {"path": "dtm.tif"}})");
  write("dtm.asc", aaiGrid(f));
  const std::string manifest =
      write("scene_web.json", R"({"format": "histoview-web", "version": 1, "crs": "EPSG:2154", "meshes": [],
                                   "terrain": {"grid": "dtm.asc"}, "cameras": "cameras.json"})");
  Diagnostics nd, wd;
  const Scene native = loadScene(scenePath, nd);
  WebSceneOptions options;
  options.checkImageFiles = false;
  const Scene web = readWebScene(manifest, options, wd);
  ASSERT_TRUE(nd.ok()) << nd.errors.front();
  ASSERT_TRUE(wd.ok()) << wd.errors.front();

  // The same mesh, vertex for vertex (float32 heights both ways).
  ASSERT_EQ(web.terrain.positions.size(), native.terrain.positions.size());
  ASSERT_EQ(web.terrain.triangles, native.terrain.triangles);
  for (std::size_t i = 0; i < web.terrain.positions.size(); ++i)
    ASSERT_EQ(web.terrain.positions[i], native.terrain.positions[i]) << "vertex " << i;
  // Two triangles per cell whose four samples have data (one corner sample missing: one cell less).
  EXPECT_EQ(web.terrain.triangles.size(), std::size_t(2 * ((f.cols - 1) * (f.rows - 1) - 1)));

  // The frame: from the grid's samples here (cell centres; z over the samples with data).
  float zlo = 1e9f, zhi = -1e9f;
  for (float z : f.z)
    if (!std::isnan(z)) zlo = std::min(zlo, z), zhi = std::max(zhi, z);
  const double x0 = f.originX + 0.5 * f.cellX, x1 = f.originX + (f.cols - 0.5) * f.cellX;
  const double y1 = f.originY + 0.5 * f.cellY, y0 = f.originY + (f.rows - 0.5) * f.cellY;
  const glm::dvec3 origin = glm::round(glm::dvec3((x0 + x1) / 2, (y0 + y1) / 2, (double(zlo) + double(zhi)) / 2));
  EXPECT_EQ(native.origin, origin);
  EXPECT_EQ(web.origin, origin);
  EXPECT_EQ(web.up, glm::dvec3(0, 0, 1));
  EXPECT_EQ(native.up, glm::dvec3(0, 0, 1));
  const Aabb extent = terrainExtent(web);
  EXPECT_EQ(terrainExtent(native).lo, extent.lo);
  EXPECT_EQ(terrainExtent(native).hi, extent.hi);
  EXPECT_EQ(extent.lo.x, x0);
  EXPECT_EQ(extent.hi.x, x1);
  EXPECT_EQ(extent.lo.y, y0);
  EXPECT_EQ(extent.hi.y, y1);
  const nlohmann::json frame = webSceneFrameJson(web);
  EXPECT_EQ(frame["terrainExtent"], nlohmann::json({x0, y0, x1, y1}));
  EXPECT_EQ(frame["origin"], nlohmann::json({origin.x, origin.y, origin.z}));
}

// Without a CRS and without a declared up, both take the axis the cameras agree on (an SfM frame
// whose up is -z: the cameras' image up along world -z).
TEST_F(WebSceneFrame, UpFromTheCamerasAsTheNativeLoader) {
  const unsigned char png[] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
                               0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00,
                               0x00, 0x90, 0x77, 0x53, 0xde, 0x00, 0x00, 0x00, 0x0c, 0x49, 0x44, 0x41, 0x54, 0x08,
                               0xd7, 0x63, 0xf8, 0xcf, 0xc0, 0x00, 0x00, 0x03, 0x01, 0x01, 0x00, 0x18, 0xdd, 0x8d,
                               0xb0, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  std::ofstream((dir_ / "img.png").string(), std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof png);
  const char* rotations[] = {"0,1,0, 0,0,1, 1,0,0", "-1,0,0, 0,0,1, 0,1,0", "0,-1,0, 0,0,1, -1,0,0"};
  std::ostringstream cams;
  cams << R"({"cameras": [)";
  for (int i = 0; i < 3; ++i)
    cams << (i ? "," : "") << R"({"id": "c)" << i << R"(", "image": "img.png", "width": 64, "height": 48, "center": [)"
         << 10 * i + 3 << R"(, 7, 2], "rotation": [)" << rotations[i]
         << R"(], "focal": [50, 50], "principal": [32, 24]})";
  cams << "]}";
  write("cameras.json", cams.str());
  const std::string scenePath = write("scene.json", R"({"cameras": {"path": "cameras.json"}})");
  const std::string manifest =
      write("scene_web.json", R"({"format": "histoview-web", "version": 1, "meshes": [], "cameras": "cameras.json"})");
  Diagnostics nd, wd;
  const Scene native = loadScene(scenePath, nd);
  const Scene web = readWebScene(manifest, WebSceneOptions{}, wd);
  EXPECT_NEAR(web.up.z, -1.0, 1e-9);
  EXPECT_EQ(web.up, native.up);
  EXPECT_EQ(web.origin, native.origin);
  EXPECT_EQ(web.origin, glm::dvec3(13, 7, 2));  // the centre of the three camera centres
}

// Bad input: a manifest without an origin may not hold data stored relative to it; a terrain
// grid that cannot be read is named and left out, the rest read.
TEST_F(WebSceneFrame, BadInputIsNamed) {
  write("cameras.json", R"({"cameras": []})");
  const std::string relative = write("a.json", R"({"format": "histoview-web", "version": 1, "cameras": "cameras.json",
      "meshes": [{"name": "terrain", "path": "t.bin", "vertices": 0, "triangles": 0}]})");
  Diagnostics diag;
  try {
    readWebScene(relative, WebSceneOptions{}, diag);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.json: origin: missing"), std::string::npos) << e.what();
  }
  write("bad.asc", "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n");
  const std::string badGrid = write("b.json", R"({"format": "histoview-web", "version": 1, "cameras": "cameras.json",
      "terrain": {"grid": "bad.asc"}})");
  Diagnostics d2;
  const Scene s = readWebScene(badGrid, WebSceneOptions{}, d2);
  ASSERT_EQ(d2.errors.size(), 1u);
  EXPECT_NE(d2.errors[0].find("b.json: terrain: "), std::string::npos) << d2.errors[0];
  EXPECT_NE(d2.errors[0].find("bad.asc"), std::string::npos) << d2.errors[0];
  EXPECT_NE(d2.errors[0].find("(terrain left out)"), std::string::npos) << d2.errors[0];
  EXPECT_TRUE(s.terrain.empty());
  const std::string noGrid = write("c.json", R"({"format": "histoview-web", "version": 1, "cameras": "cameras.json",
      "terrain": {"path": "dtm.asc"}})");
  Diagnostics d3;
  readWebScene(noGrid, WebSceneOptions{}, d3);
  ASSERT_EQ(d3.errors.size(), 1u);
  EXPECT_NE(d3.errors[0].find("c.json: terrain: expected {\"grid\""), std::string::npos) << d3.errors[0];
}

// Above kTerrainTilesAboveCells the grid becomes a quadtree, as natively; its rectangle is the
// grid's sample extent.
TEST(TerrainFromGrid, LargeGridBecomesTiles) {
  Heightfield f;
  f.cols = 1100;
  f.rows = 1000;
  f.originX = 1000.0;
  f.originY = 5000.0;
  f.z.assign(std::size_t(f.cols) * f.rows, 12.5f);
  Scene scene;
  terrainFromGrid(scene, f, "big.asc");
  ASSERT_TRUE(scene.terrainTiles);
  EXPECT_TRUE(scene.terrain.empty());
  const Aabb e = terrainExtent(scene);
  EXPECT_EQ(e.lo.x, 1000.5);
  EXPECT_EQ(e.hi.x, 1000.0 + 1099.5);
  EXPECT_EQ(e.hi.y, 4999.5);
  EXPECT_EQ(e.lo.y, 5000.0 - 999.5);
  f.z.assign(f.z.size(), std::nanf(""));
  Scene none;
  EXPECT_THROW(terrainFromGrid(none, f, "big.asc"), InputError);
}

}  // namespace
}  // namespace hv
