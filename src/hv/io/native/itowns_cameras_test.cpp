#include "hv/io/native/itowns_cameras.h"

#include "hv/io/cameras_json.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

namespace hv {
namespace {

// A camera read from iTowns' own files equals the native conversion in paris-stereopolis/ (made
// independently and checked against iTowns' code, data README): sampled points project to the
// same distorted pixels within 0.01 px.
TEST(ITownsCameras, MatchTheNativeConversionOfStereopolis) {
  const std::string dir = testing::dataset("paris-stereopolis");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no paris-stereopolis/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  Diagnostics diag;
  const ITownsSource src{dir + "/itowns/panoramicsMetaDataParis.geojson", dir + "/itowns/cameraCalibration.json",
                         dir + "/itowns/image_url_patterns.json", dir};
  const auto itowns = readITownsCameras(src, diag);
  EXPECT_TRUE(diag.ok());
  ASSERT_EQ(itowns.size(), 30u);  // 6 panoramas x cameras 300-304
  const auto native = readCameraFile(dir + "/cameras.json", CameraFileOptions{}, diag);
  ASSERT_EQ(native.size(), 30u);
  std::map<std::string, const Photo*> byId;
  for (const auto& p : itowns) byId[p.camera.id] = &p;
  double worst = 0.0;
  int points = 0;
  for (const auto& n : native) {
    ASSERT_TRUE(byId.count(n.camera.id)) << n.camera.id;
    const Camera& a = n.camera;
    const Camera& b = byId[n.camera.id]->camera;
    EXPECT_EQ(std::filesystem::path(byId[n.camera.id]->imagePath).lexically_normal(),
              std::filesystem::path(n.imagePath).lexically_normal());
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i)
        for (double z : {2.0, 10.0, 60.0}) {
          const glm::dvec2 pd(200.0 + 412.0 * i, 200.0 + 412.0 * j);
          const auto ideal = a.undistort(pd);
          ASSERT_TRUE(ideal.has_value());
          const glm::dvec3 P = a.center + z * a.rayDirection(*ideal);
          const Projection pb = b.project(P);
          ASSERT_TRUE(pb.inFront);
          worst = std::max(worst, glm::length(pb.pxDistorted - pd));
          ++points;
        }
  }
  std::cout << "iTowns vs native: " << points << " points, worst " << worst << " px\n";
  EXPECT_LE(worst, 0.01);
}

TEST(ITownsCameras, MalformedFilesNameFileEntryAndField) {
  const auto dir = std::filesystem::temp_directory_path() / ("hv-itowns-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "calib.json") << R"([
    {"id": 1, "rotation": [1,0,0, 0,1,0, 0,0,1], "position": [0,0,0],
     "projection": [100,0,50, 0,100,40, 0,0,1], "size": [100, 80]},
    {"id": 2, "rotation": [1,0,0, 0,1,0], "position": [0,0,0],
     "projection": [100,0,50, 0,100,40, 0,0,1], "size": [100, 80]}])";
  std::ofstream(dir / "poses.geojson") << R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651000, 6862000, 40]},
     "properties": {"id": 7, "roll": 0, "pitch": 0, "heading": 90}},
    {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651001, 6862000, 40]},
     "properties": {"id": 8, "roll": "x", "pitch": 0, "heading": 0}}]})";
  Diagnostics diag;
  const auto photos = readITownsCameras(
      {(dir / "poses.geojson").string(), (dir / "calib.json").string(), "img/{panoId}-{cameraId}.jpg"}, diag, false);
  ASSERT_EQ(photos.size(), 1u);  // pano 7 with camera 1
  EXPECT_EQ(photos[0].camera.id, "7-1");
  // With an identity R_cal the camera axes are the panorama's, and camera z is the panorama's up,
  // which a heading (a rotation about the vertical) leaves vertical.
  EXPECT_NEAR(glm::transpose(photos[0].camera.camFromWorld)[2].z, 1.0, 1e-12);
  ASSERT_EQ(diag.errors.size(), 2u);
  EXPECT_NE(diag.errors[0].find("calib.json"), std::string::npos);
  EXPECT_NE(diag.errors[0].find("rotation"), std::string::npos);
  EXPECT_NE(diag.errors[1].find("panorama 8"), std::string::npos);
  EXPECT_NE(diag.errors[1].find("roll"), std::string::npos);
  EXPECT_THROW(readITownsCameras({(dir / "missing.geojson").string(), (dir / "calib.json").string(), "x"}, diag),
               InputError);
  std::filesystem::remove_all(dir);
}

TEST(ITownsCameras, DuplicatesAndAbsurdSizesAreNamedAndTheRestLoads) {
  const auto dir = std::filesystem::temp_directory_path() / ("hv-itowns-dup-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string cam = R"("rotation": [1,0,0, 0,1,0, 0,0,1], "position": [0,0,0],
     "projection": [100,0,50, 0,100,40, 0,0,1])";
  std::ofstream(dir / "calib.json") << "[{\"id\": 1, " << cam << R"(, "size": [100, 80]},
    {"id": 1, )" << cam << R"(, "size": [100, 80]},
    {"id": 2, )" << cam << R"(, "size": [1e9, 80]},
    {"id": 3, )" << cam << R"(, "size": [100, NaN]}])";
  std::ofstream(dir / "poses.geojson") << R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651000, 6862000, 40]},
     "properties": {"id": 7, "roll": 0, "pitch": 0, "heading": 90}},
    {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651001, 6862000, 40]},
     "properties": {"id": 7, "roll": 0, "pitch": 0, "heading": 0}},
    {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651002, 6862000, 40]},
     "properties": {"id": 9, "roll": 0, "pitch": 0, "heading": 0}}]})";
  Diagnostics diag;
  // One image name for every panorama: the second panorama's camera would be the first's again.
  const auto photos = readITownsCameras(
      {(dir / "poses.geojson").string(), (dir / "calib.json").string(), "img/{cameraId}.jpg"}, diag, false);
  ASSERT_EQ(photos.size(), 1u);
  EXPECT_EQ(photos[0].camera.id, "1");
  std::string all;
  for (const std::string& e : diag.errors) all += e + "\n";
  ASSERT_EQ(diag.errors.size(), 5u) << all;
  EXPECT_NE(diag.errors[0].find("duplicate"), std::string::npos) << all;  // rig camera 1 twice
  EXPECT_NE(diag.errors[1].find("size"), std::string::npos) << all;       // 1e9
  EXPECT_NE(diag.errors[1].find("65536"), std::string::npos) << all;
  EXPECT_NE(diag.errors[2].find("size"), std::string::npos) << all;       // NaN, this camera only
  EXPECT_NE(diag.errors[3].find("panorama 7"), std::string::npos) << all;  // feature 7 twice
  EXPECT_NE(diag.errors[3].find("duplicate"), std::string::npos) << all;
  EXPECT_NE(diag.errors[4].find("panorama 9"), std::string::npos) << all;  // img/1.jpg again
  EXPECT_NE(diag.errors[4].find("duplicate"), std::string::npos) << all;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hv
