// Cameras as an OGR point layer (docs/formats.md, "Cameras as an OGR point layer"): written to
// GeoPackage and GeoJSON by writeOgrCameras, read back through the catalog's per-feature decoder.
#include "hv/io/native/camera_catalog.h"

#include "hv/io/native/scene_loader.h"
#include "hv/testing/awkward_photos.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

class OgrCamerasTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv-ogr-cameras-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

using testing::expectSamePhoto;

// testing::awkwardPhotos, the last one's image by URL.
std::vector<Photo> awkwardPhotos() {
  std::vector<Photo> photos = testing::awkwardPhotos();
  photos[4].imagePath = "https://example.org/photos/Île de la Cité 4.jpg";
  return photos;
}

TEST_F(OgrCamerasTest, GeoPackageRoundTripIsExact) {
  const std::vector<Photo> photos = awkwardPhotos();
  const std::string gpkg = (dir_ / "cameras.gpkg").string();
  EXPECT_EQ(writeOgrCameras(photos, "EPSG:2154", gpkg, "cameras"), photos.size());
  Diagnostics diag;
  const CatalogCameras back = readOgrCameras(gpkg, "cameras", diag);
  EXPECT_TRUE(diag.errors.empty()) << diag.errors.front();
  EXPECT_EQ(back.crs, "EPSG:2154");
  ASSERT_EQ(back.photos.size(), photos.size());
  for (std::size_t i = 0; i < photos.size(); ++i) expectSamePhoto(photos[i], back.photos[i], 0);
  // Written again: replaced, not appended.
  writeOgrCameras({photos[0], photos[1]}, "EPSG:2154", gpkg, "cameras");
  EXPECT_EQ(readOgrCameras(gpkg, "", diag).photos.size(), 2u);  // the only layer, unnamed
}

TEST_F(OgrCamerasTest, GeoJsonRoundTripIsWithinOneInATrillion) {
  const std::vector<Photo> photos = awkwardPhotos();
  const std::string geojson = (dir_ / "cameras.geojson").string();
  writeOgrCameras(photos, "EPSG:2154", geojson, "cameras");
  Diagnostics diag;
  const CatalogCameras back = readOgrCameras(geojson, "cameras", diag);
  EXPECT_TRUE(diag.errors.empty()) << diag.errors.front();
  EXPECT_EQ(back.crs, "EPSG:2154");
  ASSERT_EQ(back.photos.size(), photos.size());
  for (std::size_t i = 0; i < photos.size(); ++i) expectSamePhoto(photos[i], back.photos[i], 1e-12);
}

// Arrays as GeoJSON arrays (list fields) and as PostgreSQL text; a broken feature is named with
// the source, the layer, its id, the camera and the field, and left out; the others load.
TEST_F(OgrCamerasTest, ListAndTextArraysLoadAndBrokenFeaturesAreNamedAndLeftOut) {
  const fs::path file = dir_ / "published.geojson";
  auto feature = [](int fid, const std::string& id, const std::string& rot, const std::string& extra) {
    return R"({"type": "Feature", "id": )" + std::to_string(fid) +
           R"(, "geometry": {"type": "Point", "coordinates": [10.5, 20.25, 30.125]}, "properties": {"id": ")" + id +
           R"(", "image": "photos/)" + id + R"(.jpg", "width": 640, "height": 480, "focal_y": 500.5,
      "principal_x": 320.25, "principal_y": 240.75, "skew": 0, "cam_from_world": )" +
           rot + R"(, "colour_gain": "{1.5, 1, 1}", "colour_offset": "{0.25,0,0}")" + extra + "}}";
  };
  const std::string rot = "[1, 0, 0, 0, -1, 0, 0, 0, -1]";
  std::ofstream(file) << R"({"type": "FeatureCollection",
    "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2154"}}, "features": [)"
                      << feature(1, "good", rot, R"(, "focal_x": 500.5)") << ",\n"
                      << feature(2, "short", "[1, 0, 0, 0, -1, 0, 0, 0]", R"(, "focal_x": 500.5)") << ",\n"
                      << feature(3, "nofocal", rot, "") << ",\n"
                      << feature(4, "alsogood", rot, R"(, "focal_x": 600)") << "]}\n";
  Diagnostics diag;
  const CatalogCameras got = readOgrCameras(file.string(), "", diag);
  ASSERT_EQ(got.photos.size(), 2u);
  EXPECT_EQ(got.crs, "EPSG:2154");
  EXPECT_EQ(got.photos[0].camera.id, "good");
  EXPECT_EQ(got.photos[1].camera.id, "alsogood");
  EXPECT_EQ(got.photos[0].camera.center, glm::dvec3(10.5, 20.25, 30.125));
  EXPECT_EQ(got.photos[0].camera.focal, glm::dvec2(500.5, 500.5));
  EXPECT_EQ(got.photos[0].camera.camFromWorld[1][1], -1.0);
  EXPECT_EQ(got.photos[0].colour.gain, glm::dvec3(1.5, 1, 1));
  EXPECT_EQ(got.photos[0].colour.offset, glm::dvec3(0.25, 0, 0));
  EXPECT_EQ(got.photos[0].imagePath, "photos/good.jpg");  // as the layer has it
  ASSERT_EQ(diag.errors.size(), 2u);
  const std::string at = file.string() + ": layer published: ";
  EXPECT_EQ(diag.errors[0], at + "fid 2 (camera 'short'): cam_from_world: expected 9 numbers (row-major), got 8 "
                                 "(camera skipped)");
  EXPECT_EQ(diag.errors[1], at + "fid 3 (camera 'nofocal'): focal_x: missing (expected a number) (camera skipped)");

  // Through scene.json: relative image paths resolve against its folder, URLs stay.
  std::ofstream(dir_ / "scene.json") << R"({"cameras": {"path": "published.geojson", "format": "ogr",
                                           "layer": "published"}})";
  Diagnostics sceneDiag;
  const Scene scene = loadScene((dir_ / "scene.json").string(), sceneDiag);
  ASSERT_EQ(scene.photos.size(), 2u);
  EXPECT_EQ(scene.photos[0].imagePath, (dir_ / "photos" / "good.jpg").lexically_normal().string());
  // A layer the source has not: named, with the ones it has.
  std::ofstream(dir_ / "wrong.json") << R"({"cameras": {"path": "published.geojson", "format": "ogr",
                                           "layer": "nope"}})";
  Diagnostics wrongDiag;
  EXPECT_TRUE(loadScene((dir_ / "wrong.json").string(), wrongDiag).photos.empty());
  ASSERT_FALSE(wrongDiag.errors.empty());
  EXPECT_NE(wrongDiag.errors.front().find("no layer \"nope\" (it has: published)"), std::string::npos)
      << wrongDiag.errors.front();
}

TEST_F(OgrCamerasTest, NoCrsStaysNoneAndOtherFileKindsAreRefusedByName) {
  const std::vector<Photo> photos = awkwardPhotos();
  const std::string gpkg = (dir_ / "local.gpkg").string();
  writeOgrCameras(photos, "", gpkg, "local");
  Diagnostics diag;
  EXPECT_EQ(readOgrCameras(gpkg, "local", diag).crs, "");
  const std::string csv = (dir_ / "cameras.csv").string();
  try {
    writeOgrCameras(photos, "", csv, "cameras");
    FAIL() << "a .csv was written";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), csv + ": expected a .gpkg (GeoPackage) or .geojson file name");
  }
  EXPECT_THROW(readOgrCameras((dir_ / "none.gpkg").string(), "", diag), InputError);
}

TEST(NumberListTest, PostgresAndJsonFormsAndNothingElse) {
  EXPECT_EQ(parseNumberList("{1,2.5,-3e-2}"), (std::vector<double>{1, 2.5, -0.03}));
  EXPECT_EQ(parseNumberList(" [ 1 , +2 ] "), (std::vector<double>{1, 2}));
  EXPECT_EQ(parseNumberList("[]"), std::vector<double>{});
  EXPECT_EQ(parseNumberList("{0.1}")->front(), 0.1);
  for (const char* bad : {"", "1,2", "[1,2}", "{1,,2}", "[1,2,]", "[nan]", "[1e999]", "[a]", "[1 2]", "{"})
    EXPECT_FALSE(parseNumberList(bad).has_value()) << bad;
  EXPECT_EQ(parseNumber(" 650000.25 "), 650000.25);
  EXPECT_FALSE(parseNumber("12px").has_value());
  EXPECT_FALSE(parseNumber("inf").has_value());
}

}  // namespace
}  // namespace hv
