#include "hv/io/geojson_cameras.h"

#include <gtest/gtest.h>

namespace hv {
namespace {

// A camera looking down -z from (x, 20, 30), 640 x 480, focal 500: the rest as `extra` says.
std::string feature(const std::string& fid, const std::string& id, const std::string& extra,
                    const std::string& geometry = R"({"type": "Point", "coordinates": [10.5, 20, 30]})") {
  return R"({"type": "Feature", "id": ")" + fid + R"(", "geometry": )" + geometry + R"(, "properties": {"id": ")" + id +
         R"(", "width": 640, "height": 480, "focal_x": 500, "focal_y": 500, "principal_x": 320, "principal_y": 240,
         "skew": 0, "cam_from_world": [1, 0, 0, 0, -1, 0, 0, 0, -1])" +
         extra + "}}";
}

TEST(GeoJsonCameras, CamerasPropertiesAndNextLink) {
  const std::string text = R"({"type": "FeatureCollection", "features": [)" +
                           feature("cameras.1", "a", R"(, "image": "photos/a.jpg", "date": "1910")") + "," +
                           feature("cameras.2", "b", R"(, "image": "http://h/iiif?IIIF=b.tif/info.json",
                                   "distortion_model": "polynomial",
                                   "distortion": "{320,240,500,500,0.1,0,0,0,0,0,0,4}",
                                   "colour_gain": [2, 1, 1], "colour_offset": "[0.5, 0, 0]")") +
                           R"(], "links": [{"rel": "next", "href": "http://h/items?offset=2"}]})";
  Diagnostics diag;
  const GeoJsonCameraPage page = parseGeoJsonCameras(text, "http://h/wfs?p=0", diag);
  EXPECT_TRUE(diag.errors.empty()) << diag.errors.front();
  EXPECT_EQ(page.features, 2u);
  EXPECT_EQ(page.next, "http://h/items?offset=2");
  ASSERT_EQ(page.photos.size(), 2u);
  const Photo& a = page.photos[0];
  EXPECT_EQ(a.camera.id, "a");
  EXPECT_EQ(a.camera.center, glm::dvec3(10.5, 20, 30));
  EXPECT_EQ(a.camera.width, 640);
  EXPECT_EQ(a.camera.focal, glm::dvec2(500, 500));
  EXPECT_EQ(a.camera.camFromWorld[1][1], -1.0);
  EXPECT_EQ(a.imagePath, "photos/a.jpg");
  EXPECT_EQ(a.date, "1910");
  const Photo& b = page.photos[1];
  EXPECT_EQ(b.imagePath, "http://h/iiif?IIIF=b.tif/info.json");
  ASSERT_TRUE(b.camera.distortion.has_value());
  EXPECT_EQ(b.camera.distortion->c3, 0.1);
  EXPECT_EQ(b.camera.distortion->r2max, 4.0);
  EXPECT_EQ(b.colour.gain, glm::dvec3(2, 1, 1));
  EXPECT_EQ(b.colour.offset, glm::dvec3(0.5, 0, 0));
}

// MapServer's WFS writes a NULL text field as "": no mask, no lens distortion.
TEST(GeoJsonCameras, EmptyTextIsNoValueAsMapServerWritesNull) {
  const std::string text = R"({"type": "FeatureCollection", "features": [)" +
                           feature("cameras.1", "p1", R"(, "image": "images/p1.png", "mask": "",
                                   "distortion_model": "", "distortion": "", "date": "")") +
                           "]}";
  Diagnostics diag;
  const GeoJsonCameraPage page = parseGeoJsonCameras(text, "http://h/wfs", diag);
  EXPECT_TRUE(diag.errors.empty());
  ASSERT_EQ(page.photos.size(), 1u);
  EXPECT_EQ(page.photos[0].maskPath, "");
  EXPECT_FALSE(page.photos[0].camera.distortion.has_value());
  EXPECT_EQ(page.photos[0].date, "");
}

TEST(GeoJsonCameras, BrokenFeaturesAreNamedWithTheUrlAndLeftOut) {
  const std::string text =
      R"({"type": "FeatureCollection", "features": [)" +
      feature("c1", "flat", "", R"({"type": "Point", "coordinates": [1, 2]})") + "," +
      feature("c2", "line", "", R"({"type": "LineString", "coordinates": [[1, 2, 3], [4, 5, 6]]})") + "," +
      feature("c3", "big", R"(, "width": 640.5)") + "," +
      feature("c4", "rot", R"(, "cam_from_world": [1, 0, "x", 0, 1, 0, 0, 0, 1])") + "," +
      feature("c5", "bent", R"(, "cam_from_world": [1, 1, 0, 0, 1, 0, 0, 0, 1])") + "," +
      R"(42, {"type": "Feature", "properties": {"width": 1}}, )" + feature("c8", "ok", "") + "]}";
  Diagnostics diag;
  const GeoJsonCameraPage page = parseGeoJsonCameras(text, "http://h/wfs", diag);
  EXPECT_EQ(page.features, 8u);
  ASSERT_EQ(page.photos.size(), 1u);
  EXPECT_EQ(page.photos[0].camera.id, "ok");
  ASSERT_EQ(diag.errors.size(), 7u);
  EXPECT_EQ(diag.errors[0],
            "http://h/wfs: feature c1 (camera 'flat'): centre: expected a 3D point (x, y, z), got a 2D "
            "one (camera skipped)");
  EXPECT_EQ(diag.errors[1],
            "http://h/wfs: feature c2 (camera 'line'): centre: expected a point geometry (camera skipped)");
  EXPECT_EQ(diag.errors[2],
            "http://h/wfs: feature c3 (camera 'big'): width: expected a positive whole number of pixels "
            "(camera skipped)");
  EXPECT_EQ(diag.errors[3],
            "http://h/wfs: feature c4 (camera 'rot'): cam_from_world: expected a list of numbers, got a "
            "field of type array holding a string (camera skipped)");
  EXPECT_NE(diag.errors[4].find("http://h/wfs: feature c5 (camera 'bent'): "), std::string::npos) << diag.errors[4];
  EXPECT_EQ(diag.errors[5],
            "http://h/wfs: feature 5 (camera ''): expected a GeoJSON Feature (\"type\": \"Feature\") "
            "(camera skipped)");
  EXPECT_EQ(diag.errors[6],
            "http://h/wfs: feature 6 (camera ''): id: missing (expected the camera's name) "
            "(camera skipped)");
}

TEST(GeoJsonCameras, NotJsonOrNotAFeatureCollectionThrowsNamingTheUrl) {
  Diagnostics diag;
  for (const char* text : {"", "{\"type\": \"Feature", "<html>502</html>", "[]", R"({"type": "FeatureCollection"})"}) {
    try {
      parseGeoJsonCameras(text, "http://h/wfs?REQUEST=GetFeature", diag);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("http://h/wfs?REQUEST=GetFeature: ", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace hv
