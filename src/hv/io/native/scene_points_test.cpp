// scene.json "points": LAS or PLY by extension, CRS override, chunks built at load, a broken
// file reported and left out while the rest of the scene loads.
#include "hv/io/native/las_writer.h"
#include "hv/io/native/ply_points.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/chunks.h"
#include "hv/scene/point_normals.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <cmath>
#include <fstream>
#include <map>
#include <tuple>
#include <thread>

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

// Normals a source lacks are estimated when first asked for, not at load, and are then what the
// estimate at load gave (estimateNormals before organizeChunks, as the loader did).
TEST_F(ScenePoints, NormalsAreEstimatedWhenFirstNeededAsAtLoad) {
  PointCloud relief;
  relief.resize(4000, {.intensity = true});
  for (std::size_t i = 0; i < relief.size(); ++i) {
    const double x = double(i % 80) * 0.5, y = double(i / 80) * 0.5;
    relief.positions[i] = {651000.0 + x, 6862000.0 + y, 38.0 + 2.0 * std::sin(0.3 * x) + 0.05 * y * y};
  }
  writePlyPoints((dir_ / "r.ply").string(), relief);
  PointCloud eager = readPlyPoints((dir_ / "r.ply").string());
  ASSERT_FALSE(eager.fields().normals);
  estimateNormals(eager);
  organizeChunks(eager);
  ASSERT_EQ(eager.normals.size(), relief.size());

  Diagnostics diag;
  const Scene s = loadScene(scene(R"({"points": {"path": "r.ply"}})"), diag);
  EXPECT_TRUE(diag.ok());
  ASSERT_EQ(s.points.positions, eager.positions);  // the same chunk order
  EXPECT_TRUE(s.points.normals.empty()) << "not estimated at load";
  EXPECT_FALSE(s.points.fields().normals);
  EXPECT_TRUE(hasNormals(s.points));
  // Asked from two threads at once: estimated once, the same for both, equal to the eager ones.
  const std::vector<glm::vec3>* got[2] = {nullptr, nullptr};
  std::thread other([&] { got[1] = &pointNormals(s.points); });
  got[0] = &pointNormals(s.points);
  other.join();
  EXPECT_EQ(got[0], got[1]);
  EXPECT_EQ(*got[0], eager.normals);
  int tilted = 0;  // not a flat field: the comparison says something
  for (const glm::vec3& n : eager.normals) tilted += n.z < 0.99f && n != glm::vec3(0.0f);
  EXPECT_GT(tilted, 1000);

  // A subsample carries the whole cloud's estimate; a resolved copy holds it as its own normals.
  const PointCloud sub = subsampleChunks(s.points, 1000);
  ASSERT_EQ(sub.normals.size(), sub.size());
  std::map<std::tuple<double, double, double>, glm::vec3> byPosition;
  for (std::size_t i = 0; i < eager.size(); ++i)
    byPosition[{eager.positions[i].x, eager.positions[i].y, eager.positions[i].z}] = eager.normals[i];
  for (std::size_t i = 0; i < sub.size(); ++i)
    ASSERT_EQ(sub.normals[i], (byPosition[{sub.positions[i].x, sub.positions[i].y, sub.positions[i].z}]));
  PointCloud copy = s.points;
  resolveNormals(copy);
  EXPECT_EQ(copy.normals, eager.normals);
  EXPECT_FALSE(copy.pendingNormals);
  EXPECT_EQ(*got[0], eager.normals) << "the copy's resolution leaves the scene's estimate";

  // "facing": none estimated, none pending; a file's own normals are kept as they are.
  const Scene facing = loadScene(scene(R"({"points": {"path": "r.ply", "normals": "facing"}})"), diag);
  EXPECT_FALSE(hasNormals(facing.points));
  EXPECT_TRUE(pointNormals(facing.points).empty());
}

}  // namespace
}  // namespace hv
