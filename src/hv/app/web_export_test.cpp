// web-export writes the demo city as a web scene; the portable reader (hv/io/web_scene.h) reads
// it back to the same geometry and cameras as the native scene loader.
#include "hv/app/web_export_command.h"
#include "hv/demo/demo_city.h"
#include "hv/image/image.h"
#include "hv/io/scene_loader.h"
#include "hv/io/web_scene.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace hv::app {
namespace {

namespace fs = std::filesystem;

TEST(WebExport, DemoCityRoundTrip) {
  const fs::path dir = fs::temp_directory_path() / ("hv_web_export_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  demo::DemoOptions small;
  small.buildings = 8;
  small.photos = 6;
  small.views = 2;
  small.samplesPerAxis = 1;
  const demo::DemoSummary city = demo::generate(small, (dir / "city").string());

  WebExportOptions o;
  o.scenePath = city.scenePath;
  o.out = (dir / "web").string();
  o.viewsPath = city.viewsPath;
  o.pageDir = (dir / "no-page").string();  // the page is not under test here
  o.wasmDir = (dir / "no-wasm").string();
  ASSERT_EQ(runWebExport(o), 0);

  Diagnostics nativeDiag, webDiag;
  const Scene native = loadScene(city.scenePath, nativeDiag);
  const Scene web = readWebScene((dir / "web" / kWebSceneManifest).string(), {}, webDiag);
  EXPECT_TRUE(webDiag.ok()) << (webDiag.errors.empty() ? "" : webDiag.errors[0]);
  EXPECT_EQ(web.crs, native.crs);
  EXPECT_EQ(web.origin, native.origin);
  EXPECT_EQ(web.up, native.up);
  EXPECT_EQ(web.terrain.triangles, native.terrain.triangles);
  EXPECT_EQ(web.buildings.triangles, native.buildings.triangles);
  EXPECT_EQ(web.buildings.triangleTags, native.buildings.triangleTags);
  EXPECT_EQ(web.buildingValidity, native.buildingValidity);
  ASSERT_FALSE(web.terrain.empty());
  ASSERT_FALSE(web.buildings.empty());
  // Positions are float32 relative to the origin: the demo city spans a few hundred metres, so
  // the round trip is exact to well under a millimetre.
  // The export carries no point cloud (yet): compare with the native scene's geometry and cameras.
  Scene withoutPoints = native;
  withoutPoints.points = PointCloud{};
  const Aabb a = withoutPoints.bounds(), b = web.bounds();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a.lo[i], b.lo[i], 1e-4);
    EXPECT_NEAR(a.hi[i], b.hi[i], 1e-4);
  }
  for (size_t i = 0; i < native.terrain.positions.size(); ++i)
    ASSERT_LT(glm::distance(native.terrain.positions[i], web.terrain.positions[i]), 1e-4);

  ASSERT_EQ(web.photos.size(), native.photos.size());
  for (size_t i = 0; i < web.photos.size(); ++i) {
    const Camera &n = native.photos[i].camera, &w = web.photos[i].camera;
    EXPECT_EQ(w.id, n.id);
    EXPECT_EQ(w.width, n.width);
    EXPECT_EQ(w.height, n.height);
    EXPECT_LT(glm::distance(w.center, n.center), 1e-9);
    EXPECT_EQ(w.focal, n.focal);
    EXPECT_EQ(w.principal, n.principal);
    EXPECT_EQ(w.distortion.has_value(), n.distortion.has_value());
    EXPECT_EQ(web.photos[i].date, native.photos[i].date);
    EXPECT_EQ(web.photos[i].maskPath.empty(), native.photos[i].maskPath.empty());
    // Every photograph is a JPEG the browser build's decoder reads, at the photograph's size.
    const Image8 img = readImage(web.photos[i].imagePath);
    EXPECT_EQ(img.width, n.width);
    EXPECT_EQ(img.height, n.height);
    EXPECT_EQ(fs::path(web.photos[i].imagePath).extension(), ".jpg");
  }
  EXPECT_TRUE(fs::exists(dir / "web" / "views.json"));
  fs::remove_all(dir);
}

TEST(WebScene, RejectsBrokenFiles) {
  const fs::path dir = fs::temp_directory_path() / ("hv_web_scene_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "scene_web.json") << R"({"format": "histoview-web", "version": 1, "origin": [0, 0, 0],
    "meshes": [{"name": "terrain", "path": "terrain.bin", "vertices": 3, "triangles": 1}], "cameras": "cameras.json"})";
  std::ofstream(dir / "terrain.bin") << "short";
  std::ofstream(dir / "cameras.json") << R"({"cameras": []})";
  Diagnostics diag;
  const Scene s = readWebScene((dir / "scene_web.json").string(), {}, diag);
  EXPECT_TRUE(s.terrain.empty());
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("terrain.bin"), std::string::npos) << diag.errors[0];

  std::ofstream(dir / "bad.json") << R"({"format": "something else"})";
  EXPECT_THROW(readWebScene((dir / "bad.json").string(), {}, diag), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hv::app
