// Cameras as an OGR point layer (docs/formats.md, "Cameras as an OGR point layer"): written to
// GeoPackage and GeoJSON by writeOgrCameras, read back through the catalog's per-feature decoder.
#include "hv/io/native/camera_catalog.h"

#include "hv/io/native/scene_loader.h"

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

// `b` equals `a` to `rel` relative (0: bit for bit).
void expectNear(double a, double b, double rel, const char* what) {
  if (rel == 0)
    EXPECT_EQ(a, b) << what;
  else
    EXPECT_LE(std::abs(a - b), rel * std::max(std::abs(a), 1e-300)) << what << ": " << a << " vs " << b;
}

void expectSamePhoto(const Photo& a, const Photo& b, double rel) {
  const Camera &x = a.camera, &y = b.camera;
  SCOPED_TRACE("camera '" + x.id + "'");
  EXPECT_EQ(x.id, y.id);
  EXPECT_EQ(x.width, y.width);
  EXPECT_EQ(x.height, y.height);
  for (int i = 0; i < 3; ++i) expectNear(x.center[i], y.center[i], rel, "centre");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) expectNear(x.camFromWorld[i][j], y.camFromWorld[i][j], rel, "cam_from_world");
  for (int i = 0; i < 2; ++i) expectNear(x.focal[i], y.focal[i], rel, "focal");
  for (int i = 0; i < 2; ++i) expectNear(x.principal[i], y.principal[i], rel, "principal");
  expectNear(x.skew, y.skew, rel, "skew");
  ASSERT_EQ(x.distortion.has_value(), y.distortion.has_value());
  if (x.distortion) {
    const LensDistortion &d = *x.distortion, &e = *y.distortion;
    EXPECT_EQ(d.model, e.model);
    const double u[] = {d.center.x, d.center.y, d.scale.x, d.scale.y, d.c3, d.c5,
                        d.c7,       d.p1,       d.p2,      d.l1,      d.l2, d.r2max};
    const double v[] = {e.center.x, e.center.y, e.scale.x, e.scale.y, e.c3, e.c5,
                        e.c7,       e.p1,       e.p2,      e.l1,      e.l2, e.r2max};
    for (int i = 0; i < 12; ++i) expectNear(u[i], v[i], rel, "distortion");
  }
  EXPECT_EQ(a.imagePath, b.imagePath);
  EXPECT_EQ(a.maskPath, b.maskPath);
  EXPECT_EQ(a.date, b.date);
  for (int i = 0; i < 3; ++i) expectNear(a.colour.gain[i], b.colour.gain[i], rel, "colour_gain");
  for (int i = 0; i < 3; ++i) expectNear(a.colour.offset[i], b.colour.offset[i], rel, "colour_offset");
}

// Awkward doubles everywhere (none short in decimal), every lens model, dates, a mask, a colour
// correction, a name in another script.
std::vector<Photo> awkwardPhotos() {
  std::vector<Photo> photos;
  for (int i = 0; i < 5; ++i) {
    const double t = 0.1 + 0.7 * i;
    const std::string id = "cam" + std::to_string(i);
    Camera c = lookAtCamera(id, glm::dvec3(651234.123456789 + i / 3.0, 6861234.98765432 - i / 7.0, 35.3 + 1.0 / 3.0),
                            glm::dvec3(651250.0 + std::sin(t), 6861240.0 + std::cos(t), 30.1), 1000 + i, 700 + i,
                            812.3456789012345 + i / 9.0);
    c.focal.y = c.focal.x * (1.0 + 1e-7);
    c.principal += glm::dvec2(1.0 / 3.0, -2.0 / 7.0);
    c.skew = 1e-9 / 3.0;
    Photo p;
    p.camera = c;
    p.imagePath = "/photos/" + id + ".jpg";
    photos.push_back(p);
  }
  LensDistortion radial;
  radial.center = {501.0 / 3.0, 349.9};
  radial.c3 = 1.2345678901234e-8, radial.c5 = -3.3e-15 / 7.0, radial.c7 = 2e-22 / 3.0, radial.r2max = 1234567.891;
  photos[0].camera.distortion = radial;
  LensDistortion opencv;
  opencv.center = photos[1].camera.principal;
  opencv.scale = photos[1].camera.focal;
  opencv.c3 = 0.1 / 3.0, opencv.c5 = -0.02, opencv.c7 = 1e-3 / 7.0, opencv.p1 = 1e-4 / 3.0, opencv.p2 = -2e-4 / 9.0;
  photos[1].camera.distortion = opencv;
  LensDistortion fisheye;
  fisheye.model = LensDistortion::Model::Fisheye;
  fisheye.center = {512.25, 384.75};
  fisheye.scale = {600.0 / 7.0, 600.0 / 7.0};
  fisheye.c3 = -0.01 / 3.0, fisheye.l1 = 1e-5 / 3.0, fisheye.l2 = -2e-5 / 7.0, fisheye.r2max = 3.7;
  photos[2].camera.distortion = fisheye;
  photos[0].date = "1905";
  photos[1].date = "1905-06";
  photos[2].date = "1905-06-01T10:30:00+01:00";
  photos[1].maskPath = "/photos/masks/cam1.png";
  photos[3].colour.gain = {1.1 / 3.0, 0.9, 1.0 + 1e-15};
  photos[3].colour.offset = {-0.01 / 7.0, 0.0, 0.02};
  photos[4].camera.id = "Île de la Cité, n° 4 — 照片";
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
