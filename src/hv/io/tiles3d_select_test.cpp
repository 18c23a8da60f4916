#include "hv/io/tiles3d_select.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace hv {
namespace {

// A root with content and two children with content, ADD refinement, boxes along x.
const char* kTileset = R"({"asset": {"version": "1.0"}, "geometricError": 100,
  "root": {"boundingVolume": {"box": [0, 0, 0, 100, 0, 0, 0, 100, 0, 0, 0, 10]}, "geometricError": 10, "refine": "ADD",
           "content": {"uri": "r.pnts"},
           "children": [
             {"boundingVolume": {"box": [-50, 0, 0, 50, 0, 0, 0, 100, 0, 0, 0, 10]}, "geometricError": 0, "content": {"uri": "r0.pnts"}},
             {"boundingVolume": {"box": [50, 0, 0, 50, 0, 0, 0, 100, 0, 0, 0, 10]}, "geometricError": 0, "content": {"uri": "r1.pnts"}}]}})";

PointCloud cloudOf(std::size_t n, double x) {
  PointCloud c;
  c.positions.assign(n, glm::dvec3(x, 0.0, 0.0));
  return c;
}

// Runs a selection to its end, every tile arriving with `n` points except those in `fail`.
std::vector<std::string> runAll(PointTileSelection& s, std::size_t n, const std::vector<std::string>& fail = {}) {
  std::vector<std::string> asked;
  for (std::vector<int> batch = s.next(); !batch.empty(); batch = s.next())
    for (int t : batch) {
      const std::string& url = s.tileset().tiles[std::size_t(t)].content;
      asked.push_back(url.substr(url.rfind('/') + 1));
      if (std::find(fail.begin(), fail.end(), asked.back()) != fail.end())
        s.failed(t, url + ": points tile: HTTP 404");
      else
        s.arrived(t, cloudOf(n, double(t)));
    }
  return asked;
}

Camera cameraAt(const glm::dvec3& c) {
  Camera cam;
  cam.center = c;
  cam.focal = {1000.0, 1000.0};
  return cam;
}

TEST(PointTileSelection, WithoutCamerasReadsEveryTileByGeometricError) {
  PointTileSelection s(parseTileset(kTileset, "http://h/t/tileset.json"), {}, nullptr, 2.0, 1000);
  const std::vector<std::string> asked = runAll(s, 10);
  EXPECT_EQ(asked, (std::vector<std::string>{"r.pnts", "r0.pnts", "r1.pnts"}));
  EXPECT_EQ(s.tilesKept(), 3u);
  EXPECT_EQ(s.points().size(), 30u);
  EXPECT_FALSE(s.budgetLimited());
}

TEST(PointTileSelection, RefinesOnlyWhereTheScreenSpaceErrorExceedsTheTolerance) {
  // Near: 10 m of error at ~100 m seen at 1000 px focal is ~100 px: refined.
  PointTileSelection near(parseTileset(kTileset, "tileset.json"), {cameraAt({0, 0, 200})}, nullptr, 2.0, 1000);
  EXPECT_EQ(runAll(near, 10).size(), 3u);
  // Far (100 km): 0.1 px, not refined.
  PointTileSelection far(parseTileset(kTileset, "tileset.json"), {cameraAt({0, 0, 1e5})}, nullptr, 2.0, 1000);
  EXPECT_EQ(runAll(far, 10), std::vector<std::string>{"r.pnts"});
  // The map into the scene frame places the tiles: moved 100 km away, the near camera is far.
  PointTileSelection moved(parseTileset(kTileset, "tileset.json"), {cameraAt({0, 0, 200})},
                           [](const glm::dvec3& p) { return p + glm::dvec3(1e5, 0, 0); }, 2.0, 1000);
  EXPECT_EQ(runAll(moved, 10).size(), 1u);
}

TEST(PointTileSelection, StopsAtTheBudget) {
  PointTileSelection s(parseTileset(kTileset, "tileset.json"), {}, nullptr, 2.0, 25);
  runAll(s, 10);
  EXPECT_TRUE(s.budgetLimited());
  EXPECT_EQ(s.points().size(), 10u);  // the root only: its children would make 30
}

TEST(PointTileSelection, NamesAFailedTileAndKeepsTheOthers) {
  PointTileSelection s(parseTileset(kTileset, "http://h/t/tileset.json"), {}, nullptr, 2.0, 1000);
  runAll(s, 10, {"r1.pnts"});
  ASSERT_EQ(s.errors().size(), 1u);
  EXPECT_EQ(s.errors()[0], "http://h/t/r1.pnts: points tile: HTTP 404 (tile root.children[1] left out)");
  EXPECT_EQ(s.points().size(), 20u);
  EXPECT_EQ(s.tilesKept(), 2u);
}

}  // namespace
}  // namespace hv
