// The web manifest's camera layer (hv/io/web_scene.h, "cameras": {"geojson": [...], "urls": [...]}):
// the GeoJSON pages the page fetched from a WFS, read with the URLs named in messages, relative
// image paths resolved against the manifest's folder, URLs kept, a malformed page left out alone.
#include "hv/io/web_scene.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

TEST(WebSceneCameras, LayerPagesWithUrlsInMessagesAndAMalformedPageLeftOut) {
  const fs::path dir = fs::temp_directory_path() / ("hv-web-cameras-" + std::to_string(::getpid()));
  fs::create_directories(dir / "services");
  auto feature = [](const std::string& id, const std::string& image, const std::string& extra) {
    return R"({"type": "Feature", "id": "cameras.)" + id +
           R"(", "geometry": {"type": "Point", "coordinates": [1, 2, 3]}, "properties": {"id": ")" + id +
           R"(", "image": ")" + image + R"(", "width": 64, "height": 48, "focal_x": 50, "focal_y": 50,
           "principal_x": 32, "principal_y": 24, "skew": 0, "cam_from_world": [1, 0, 0, 0, -1, 0, 0, 0, -1])" +
           extra + "}}";
  };
  std::ofstream(dir / "services" / "cameras-0.json")
      << R"({"type": "FeatureCollection", "features": [)" << feature("a", "web/images/a.jpg", "") << ","
      << feature("b", "http://h/iiif?IIIF=b.tif/info.json", R"(, "mask": "masks/b.png")") << "," << feature("c", "", "")
      << "," << feature("d", "x.jpg", R"(, "focal_x": "wide")") << "]}";
  std::ofstream(dir / "services" / "cameras-1.json") << R"({"type": "FeatureCollection", "features": [{"type": "Fe)";
  const std::string pageUrl = "http://h/mapserv?map=city&REQUEST=GetFeature&TYPENAMES=ms%3Acameras&STARTINDEX=0";
  std::ofstream(dir / "scene_web.json") << R"({"format": "histoview-web", "version": 1, "origin": [0, 0, 0],
    "meshes": [], "cameras": {"geojson": ["services/cameras-0.json", "services/cameras-1.json"],
    "urls": [")" << pageUrl << R"(", "http://h/page-1"]}})";
  Diagnostics diag;
  WebSceneOptions options;
  options.checkImageFiles = false;
  const Scene s = readWebScene((dir / "scene_web.json").string(), options, diag);
  ASSERT_EQ(s.photos.size(), 2u);
  EXPECT_EQ(s.photos[0].imagePath, (dir / "web" / "images" / "a.jpg").string());
  EXPECT_EQ(s.photos[1].imagePath, "http://h/iiif?IIIF=b.tif/info.json");
  EXPECT_EQ(s.photos[1].maskPath, (dir / "masks" / "b.png").string());
  ASSERT_EQ(diag.errors.size(), 3u);
  EXPECT_EQ(diag.errors[0], pageUrl +
                                ": feature cameras.d (camera 'd'): focal_x: expected a number, got \"wide\" "
                                "(camera skipped)");
  EXPECT_EQ(diag.errors[1], pageUrl +
                                ": camera 'c': image: missing (expected the photograph's path or URL; camera "
                                "skipped)");
  EXPECT_EQ(diag.errors[2].rfind("http://h/page-1: not valid JSON: ", 0), 0u) << diag.errors[2];
  std::error_code ec;
  fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace hv
