#include "hv/io/native/points_tiles.h"

#include "hv/io/native/scene_loader.h"
#include "hv/io/tiles3d.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

class PointTiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv-point-tiles-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& bytes) {
    fs::create_directories((dir_ / name).parent_path());
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
  }
  // A tile of n points at `at`.
  void tile(const std::string& name, int n, glm::dvec3 at) {
    PointCloud c;
    c.resize(std::size_t(n), PointFields{});
    for (int i = 0; i < n; ++i) c.positions[std::size_t(i)] = at + glm::dvec3(i * 0.1, 0, 0);
    write(name, writePnts(c));
  }
  // A REPLACE tree: the root (1 point, error 50, sphere of 1000 m at the origin), A (2 points,
  // error 5, 10 m at the origin) over A1 (3 points), B (4 points, error 5, 10 m at x = 5 km) over
  // B1 (5 points).
  std::string replaceTree() {
    write("tree/tileset.json", R"({"asset":{"version":"1.0"},"geometricError":100,"root":{
      "boundingVolume":{"sphere":[0,0,0,1000]},"geometricError":50,"refine":"REPLACE","content":{"uri":"root.pnts"},
      "children":[
        {"boundingVolume":{"sphere":[0,0,0,10]},"geometricError":5,"content":{"uri":"a.pnts"},
         "children":[{"boundingVolume":{"sphere":[0,0,0,1]},"geometricError":0,"content":{"uri":"a1.pnts"}}]},
        {"boundingVolume":{"sphere":[5000,0,0,10]},"geometricError":5,"content":{"uri":"b.pnts"},
         "children":[{"boundingVolume":{"sphere":[5000,0,0,1]},"geometricError":0,"content":{"uri":"sub/b1.pnts"}}]}]}})");
    tile("tree/root.pnts", 1, {0, 0, 0});
    tile("tree/a.pnts", 2, {0, 0, 0});
    tile("tree/a1.pnts", 3, {0, 0, 0});
    tile("tree/b.pnts", 4, {5000, 0, 0});
    tile("tree/sub/b1.pnts", 5, {5000, 0, 0});
    return (dir_ / "tree/tileset.json").string();
  }
  fs::path dir_;
};

Camera cameraAt(glm::dvec3 c) {
  Camera cam;
  cam.center = c;
  cam.focal = {1000.0, 1000.0};
  return cam;
}

TEST_F(PointTiles, TilesChosenByScreenSpaceErrorFromTheCameras) {
  PointTilesetRequest r;
  r.url = replaceTree();
  const std::vector<Camera> cams{cameraAt({0, 0, 100})};
  // From 100 m above A: the root's error 50 x 1000 / ~0 m and A's 5 x 1000 / 90 m = 56 px exceed 2
  // px, B's 5 x 1000 / 4991 m = 1.0 px does not: A1 (3 points) and B (4).
  Diagnostics diag;
  PointTilesetInfo info;
  PointCloud c = loadPointTileset(r, cams, diag, &info);
  EXPECT_TRUE(diag.errors.empty());
  EXPECT_EQ(c.size(), 7u);
  EXPECT_EQ(c.crs, "EPSG:4978");
  EXPECT_EQ(info.tilesInTileset, 5u);
  EXPECT_EQ(info.tilesRead, 4u);  // root, A, B, A1
  EXPECT_EQ(info.tilesKept, 2u);
  EXPECT_FALSE(info.budgetLimited);
  // Under 1 px, B is refined too: A1 + B1.
  r.tolerancePx = 0.5;
  EXPECT_EQ(loadPointTileset(r, cams, diag).size(), 8u);
  // A budget of 6 points: A + B (6) replace the root; neither refinement fits after.
  r.budget = 6;
  c = loadPointTileset(r, cams, diag, &info);
  EXPECT_EQ(c.size(), 6u);
  EXPECT_TRUE(info.budgetLimited);
  EXPECT_EQ(diag.warnings.size(), 1u);
  // Without cameras: refined by geometric error, every leaf.
  r.budget = kPointTilesBudget;
  EXPECT_EQ(loadPointTileset(r, {}, diag).size(), 8u);
}

TEST_F(PointTiles, AMissingTileIsNamedAndTheRestLoads) {
  PointTilesetRequest r;
  r.url = replaceTree();
  r.tolerancePx = 0.5;
  fs::remove(dir_ / "tree/sub/b1.pnts");
  Diagnostics diag;
  PointTilesetInfo info;
  const PointCloud c = loadPointTileset(r, {cameraAt({0, 0, 100})}, diag, &info);
  EXPECT_EQ(c.size(), 3u);  // A1; B was replaced by its (missing) child
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("tree/sub/b1.pnts"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[0].find("(tile root.children[1].children[0] left out)"), std::string::npos) << diag.errors[0];
  EXPECT_EQ(info.tilesFailed, 1u);
  // A broken tile likewise, with the field.
  write("tree/sub/b1.pnts", "pnts");
  Diagnostics again;
  loadPointTileset(r, {cameraAt({0, 0, 100})}, again);
  ASSERT_EQ(again.errors.size(), 1u);
  EXPECT_NE(again.errors[0].find("b1.pnts: header: expected 28 bytes"), std::string::npos) << again.errors[0];
}

TEST_F(PointTiles, ExternalTilesetsAreReadWhereTheTraversalReachesThem) {
  write("ext/tileset.json", R"({"asset":{"version":"1.0"},"geometricError":10,"root":{
    "boundingVolume":{"sphere":[0,0,0,10]},"geometricError":10,"refine":"ADD",
    "transform":[1,0,0,0, 0,1,0,0, 0,0,1,0, 100,0,0,1],
    "children":[{"boundingVolume":{"sphere":[0,0,0,10]},"geometricError":0,"content":{"uri":"more/tileset.json"}}]}})");
  write("ext/more/tileset.json", R"({"asset":{"version":"1.0"},"geometricError":1,"root":{
    "boundingVolume":{"sphere":[0,0,0,10]},"geometricError":0,"content":{"uri":"p.pnts"}}})");
  tile("ext/more/p.pnts", 2, {1, 2, 3});
  PointTilesetRequest r;
  r.url = (dir_ / "ext/tileset.json").string();
  Diagnostics diag;
  PointTilesetInfo info;
  const PointCloud c = loadPointTileset(r, {}, diag, &info);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c.positions[0].x, 101.0, 1e-3);  // the outer tileset's transform carried on
  EXPECT_NEAR(c.positions[0].y, 2.0, 1e-3);
  EXPECT_EQ(info.tilesInTileset, 3u);
}

TEST_F(PointTiles, SceneJsonTilesetEntry) {
  PointCloud cloud;
  cloud.resize(500, PointFields{});
  for (std::size_t i = 0; i < cloud.size(); ++i)
    cloud.positions[i] = glm::dvec3(double(i % 25), double(i / 25), 0.5 * double(i % 7));
  glm::dmat4 t(1.0);
  t[3] = glm::dvec4(1000, 2000, 30, 1);
  for (const PointTilesFile& f : writePointTiles(cloud, t, PointTilesOptions{60, 16}).files)
    write("t/" + f.name, f.bytes);
  write("scene.json", R"({"points": {"tileset": "t/tileset.json", "tolerance": 0, "normals": "facing"}})");
  Diagnostics diag;
  const Scene scene = loadScene((dir_ / "scene.json").string(), diag);
  EXPECT_TRUE(diag.errors.empty());
  ASSERT_EQ(scene.points.size(), 500u);
  const Aabb b = scene.points.bounds();
  EXPECT_NEAR(b.lo.x, 1000.0, 1e-3);
  EXPECT_NEAR(b.hi.y, 2019.0, 1e-3);
  EXPECT_NEAR(b.hi.z, 33.0, 1e-3);
  EXPECT_FALSE(scene.points.chunks.empty());

  write("both.json", R"({"points": {"tileset": "t/tileset.json", "path": "x.las"}})");
  write("tolerance.json", R"({"points": {"path": "x.las", "tolerance": 1}})");
  write("negative.json", R"({"points": {"tileset": "t/tileset.json", "tolerance": -1}})");
  write("missing.json", R"({"points": {"path": "none/tileset.json"}})");
  for (const auto& [file, want] : std::vector<std::pair<std::string, std::string>>{
           {"both.json", "points: expected either a path (a point file) or a tileset (3D Tiles), not both"},
           {"tolerance.json", "points.tolerance: only with a 3D Tiles tileset"},
           {"negative.json", "points.tolerance: expected a screen-space error in pixels"},
           {"missing.json", "none/tileset.json"}}) {
    Diagnostics d;
    const Scene s = loadScene((dir_ / file).string(), d);
    ASSERT_EQ(d.errors.size(), 1u) << file;
    EXPECT_NE(d.errors[0].find(want), std::string::npos) << d.errors[0];
    EXPECT_NE(d.errors[0].find("(points left out)"), std::string::npos) << d.errors[0];
    EXPECT_TRUE(s.points.empty());
  }
}

}  // namespace
}  // namespace hv
