// The browser's GeoJSON camera reader (hv/io/geojson_cameras.h) against the native one
// (readOgrCameras, through OGR's GeoJSON driver) on the same layers: the same cameras, bit for
// bit, and the same broken features left out for the same reasons.
#include "hv/io/geojson_cameras.h"
#include "hv/io/native/camera_catalog.h"
#include "hv/testing/awkward_photos.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class GeoJsonCamerasMatchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv-geojson-cameras-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

// A layer as `histoview cameras export --ogr` writes it (doubles with 17 digits, arrays as text):
// awkward doubles, every lens model, dates, a mask, a colour correction, a name in another script.
TEST_F(GeoJsonCamerasMatchTest, ExportedLayerGivesTheNativeReadersCameras) {
  std::vector<Photo> photos;
  for (int i = 0; i < 4; ++i) {
    const double t = 0.1 + 0.7 * i;
    Photo p;
    p.camera = lookAtCamera("cam" + std::to_string(i),
                            glm::dvec3(651234.123456789 + i / 3.0, 6861234.98765432 - i / 7.0, 35.3 + 1.0 / 3.0),
                            glm::dvec3(651250.0 + std::sin(t), 6861240.0 + std::cos(t), 30.1), 1000 + i, 700 + i,
                            812.3456789012345 + i / 9.0);
    p.camera.principal += glm::dvec2(1.0 / 3.0, -2.0 / 7.0);
    p.camera.skew = 1e-9 / 3.0;
    p.imagePath = "photos/cam" + std::to_string(i) + ".jpg";
    photos.push_back(p);
  }
  LensDistortion radial;
  radial.center = {501.0 / 3.0, 349.9};
  radial.c3 = 1.2345678901234e-8, radial.c5 = -3.3e-15 / 7.0, radial.r2max = 1234567.891;
  photos[0].camera.distortion = radial;
  LensDistortion fisheye;
  fisheye.model = LensDistortion::Model::Fisheye;
  fisheye.center = {512.25, 384.75};
  fisheye.scale = {600.0 / 7.0, 600.0 / 7.0};
  fisheye.c3 = -0.01 / 3.0, fisheye.l1 = 1e-5 / 3.0, fisheye.r2max = 3.7;
  photos[1].camera.distortion = fisheye;
  photos[0].date = "1905";
  photos[1].date = "1905-06-01T10:30:00+01:00";
  photos[1].maskPath = "masks/cam1.png";
  photos[2].colour.gain = {1.1 / 3.0, 0.9, 1.0 + 1e-15};
  photos[2].colour.offset = {-0.01 / 7.0, 0.0, 0.02};
  photos[3].camera.id = "Île de la Cité, n° 4 — 照片";
  photos[3].imagePath = "http://127.0.0.1:8080/iiif?IIIF=cam3.tif/info.json";
  const fs::path file = dir_ / "cameras.geojson";
  writeOgrCameras(photos, "EPSG:2154", file.string(), "cameras");

  Diagnostics nativeDiag, webDiag;
  const CatalogCameras native = readOgrCameras(file.string(), "cameras", nativeDiag);
  const GeoJsonCameraPage web = parseGeoJsonCameras(slurp(file), "http://host/cameras-page-0", webDiag);
  EXPECT_TRUE(nativeDiag.errors.empty());
  EXPECT_TRUE(webDiag.errors.empty()) << webDiag.errors.front();
  EXPECT_EQ(web.features, photos.size());
  ASSERT_EQ(native.photos.size(), photos.size());
  ASSERT_EQ(web.photos.size(), photos.size());
  for (std::size_t i = 0; i < photos.size(); ++i) testing::expectSamePhoto(native.photos[i], web.photos[i]);
}

// Arrays as JSON arrays and as PostgreSQL text, numbers as text, broken features: the same cameras
// kept, the same features left out for the same field and reason.
TEST_F(GeoJsonCamerasMatchTest, BrokenFeaturesAreLeftOutForTheSameReasons) {
  auto feature = [](int fid, const std::string& id, const std::string& geometry, const std::string& extra) {
    return R"({"type": "Feature", "id": )" + std::to_string(fid) + R"(, "geometry": )" + geometry +
           R"(, "properties": {"id": ")" + id + R"(", "image": "photos/)" + id +
           R"(.jpg", "width": 640, "height": 480, "focal_y": "500.5", "principal_x": 320.25,
      "principal_y": 240.75, "skew": 0, "colour_gain": "{1.5, 1, 1}", "colour_offset": [0.25, 0, 0])" +
           extra + "}}";
  };
  const std::string point = R"({"type": "Point", "coordinates": [10.5, 20.25, 30.125]})";
  const std::string rot = R"(, "cam_from_world": [1, 0, 0, 0, -1, 0, 0, 0, -1])";
  const std::string text =
      R"({"type": "FeatureCollection", "features": [)" +
      feature(1, "good", point, rot + R"(, "focal_x": 500.5, "date": "1910-05")") + ",\n" +
      feature(2, "short", point, R"(, "cam_from_world": "[1, 0, 0, 0, -1, 0, 0, 0]", "focal_x": 1)") + ",\n" +
      feature(3, "nofocal", point, rot) + ",\n" +
      feature(4, "flat", R"({"type": "Point", "coordinates": [1, 2]})", rot + R"(, "focal_x": 1)") + ",\n" +
      feature(5, "word", point, rot + R"(, "focal_x": "wide")") + ",\n" +
      feature(6, "lens", point, rot + R"(, "focal_x": 1, "distortion_model": "zoom")") + ",\n" +
      feature(7, "when", point, rot + R"(, "focal_x": 1, "date": "spring")") + ",\n" +
      feature(8, "alsogood", point, R"(, "cam_from_world": "{1,0,0,0,-1,0,0,0,-1}", "focal_x": 600)") + "]}\n";
  const fs::path file = dir_ / "published.geojson";
  std::ofstream(file) << text;
  Diagnostics nativeDiag, webDiag;
  const CatalogCameras native = readOgrCameras(file.string(), "", nativeDiag);
  const GeoJsonCameraPage web = parseGeoJsonCameras(text, "http://host/wfs?page=0", webDiag);
  ASSERT_EQ(native.photos.size(), 2u);
  ASSERT_EQ(web.photos.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) testing::expectSamePhoto(native.photos[i], web.photos[i]);
  EXPECT_EQ(web.photos[0].camera.center, glm::dvec3(10.5, 20.25, 30.125));
  EXPECT_EQ(web.photos[1].camera.id, "alsogood");
  ASSERT_EQ(nativeDiag.errors.size(), 6u);
  ASSERT_EQ(webDiag.errors.size(), 6u);
  // The same message after the place: "fid N (...)" natively, "feature N (...)" here.
  const std::string nativeAt = file.string() + ": layer published: fid ", webAt = "http://host/wfs?page=0: feature ";
  for (std::size_t i = 0; i < 6; ++i) {
    ASSERT_EQ(nativeDiag.errors[i].rfind(nativeAt, 0), 0u) << nativeDiag.errors[i];
    ASSERT_EQ(webDiag.errors[i].rfind(webAt, 0), 0u) << webDiag.errors[i];
    EXPECT_EQ(nativeDiag.errors[i].substr(nativeAt.size()), webDiag.errors[i].substr(webAt.size()));
  }
  EXPECT_EQ(webDiag.errors[1], webAt + "3 (camera 'nofocal'): focal_x: missing (expected a number) (camera skipped)");
  EXPECT_EQ(webDiag.errors[3], webAt + "5 (camera 'word'): focal_x: expected a number, got \"wide\" (camera skipped)");
}

}  // namespace
}  // namespace hv
