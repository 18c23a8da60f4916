// scene.json "points": LAS or PLY by extension, CRS override, chunks built at load, a broken
// file reported and left out while the rest of the scene loads.
#include "hv/io/native/las_writer.h"
#include "hv/io/native/ply_points.h"
#include "hv/io/native/scene_loader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

class ScenePoints : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv-scene-points-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    cloud_.crs = "EPSG:2154";
    cloud_.resize(1000, {.intensity = true, .classification = true});
    for (std::size_t i = 0; i < cloud_.size(); ++i) {
      cloud_.positions[i] = {651000.0 + double(i % 40), 6862000.0 + double(i / 40), 38.0};
      cloud_.classification[i] = i % 3 ? 2 : 6;
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string scene(const std::string& json) {
    std::ofstream(dir_ / "scene.json") << json;
    return (dir_ / "scene.json").string();
  }
  fs::path dir_;
  PointCloud cloud_;
};

TEST_F(ScenePoints, LasAndPlyLoadIntoChunks) {
  writeLas((dir_ / "p.las").string(), cloud_);
  writePlyPoints((dir_ / "p.ply").string(), cloud_);
  for (const char* file : {"p.las", "p.ply"}) {
    SCOPED_TRACE(file);
    Diagnostics diag;
    const Scene s = loadScene(scene(std::string(R"({"points": {"path": ")") + file + "\"}}"), diag);
    EXPECT_TRUE(diag.ok());
    EXPECT_TRUE(diag.warnings.empty());
    ASSERT_EQ(s.points.size(), cloud_.size());
    EXPECT_EQ(s.points.crs, "EPSG:2154");
    EXPECT_FALSE(s.points.chunks.empty());
    EXPECT_EQ(s.points.classHistogram()[6], 334u);
    EXPECT_NEAR(s.bounds().lo.x, 651000.0, 1e-3);  // the points count in the scene's bounds
    EXPECT_EQ(s.origin, glm::round(s.bounds().center()));
  }
  Diagnostics diag;
  const Scene s = loadScene(scene(R"({"points": {"path": "p.las", "crs": "EPSG:27561"}})"), diag);
  EXPECT_EQ(s.points.crs, "EPSG:27561");
}

TEST_F(ScenePoints, BrokenSourcesAreReportedAndLeftOut) {
  std::ofstream(dir_ / "bad.las") << "LASF but not really";
  std::ofstream(dir_ / "x.xyz") << "1 2 3\n";
  for (const char* json : {R"({"points": {"path": "bad.las"}})", R"({"points": {"path": "x.xyz"}})",
                           R"({"points": {"path": "missing.ply"}})", R"({"points": {"path": "bad.las", "crs": 3}})",
                           R"({"points": "bad.las"})"}) {
    SCOPED_TRACE(json);
    Diagnostics diag;
    const Scene s = loadScene(scene(json), diag);
    EXPECT_TRUE(s.points.empty());
    ASSERT_EQ(diag.errors.size(), 1u);
    EXPECT_NE(diag.errors[0].find("points left out"), std::string::npos) << diag.errors[0];
  }
}

}  // namespace
}  // namespace hv
