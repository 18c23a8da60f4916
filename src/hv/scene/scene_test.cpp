#include "hv/scene/robust_extent.h"
#include "hv/scene/scene.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>

namespace hv {
namespace {

Photo photoAt(const std::string& id, const glm::dvec3& c) {
  Photo p;
  p.camera.id = id;
  p.camera.width = 64;
  p.camera.height = 48;
  p.camera.center = c;
  return p;
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Median nearest-neighbour distance by brute force: the definition, independent of the kd-tree.
double bruteSpacing(const std::vector<Photo>& photos) {
  std::vector<double> nearest;
  for (size_t i = 0; i < photos.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < photos.size(); ++j)
      if (i != j) best = std::min(best, glm::distance(photos[i].camera.center, photos[j].camera.center));
    nearest.push_back(best);
  }
  std::nth_element(nearest.begin(), nearest.begin() + std::ptrdiff_t(nearest.size() / 2), nearest.end());
  return nearest[nearest.size() / 2] > 0.0 ? nearest[nearest.size() / 2] : 1.0;
}

TEST(SceneCameraSpacing, MatchesTheDefinition) {
  Scene s;
  std::uint64_t state = 12345;
  auto next = [&] {  // a fixed LCG: the same scene everywhere
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 53);
  };
  for (int i = 0; i < 300; ++i)
    s.photos.push_back(photoAt("p" + std::to_string(i), {650000 + 500 * next(), 6860000 + 500 * next(), 40 * next()}));
  s.photos.push_back(photoAt("twin", s.photos[7].camera.center));  // a coincident pair: 0 for both
  EXPECT_DOUBLE_EQ(s.cameraSpacing(), bruteSpacing(s.photos));
  // Mostly coincident (a rig): the median is 0, so the default scale falls back to 1.
  Scene rig;
  for (int i = 0; i < 10; ++i) rig.photos.push_back(photoAt("r" + std::to_string(i), {1, 2, 3}));
  rig.photos.push_back(photoAt("other", {5, 2, 3}));
  EXPECT_EQ(rig.cameraSpacing(), 1.0);
  EXPECT_EQ(bruteSpacing(rig.photos), 1.0);
}

TEST(SceneCameraSpacing, HundredThousandCamerasThenCached) {
  // 100k cameras 2 m apart on a grid (with a 100k-camera column of duplicates this was 84 s per
  // frame: quadratic, and asked for every frame when --sigma is not given). No speed is asserted:
  // a generous bound catches the quadratic case, and the cache is checked against the first call.
  Scene s;
  for (int i = 0; i < 100000; ++i)
    s.photos.push_back(photoAt("c" + std::to_string(i), {2.0 * (i % 317), 2.0 * (i / 317), 10.0}));
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_DOUBLE_EQ(s.cameraSpacing(), 2.0);
  const double first = seconds(t0);
  EXPECT_LT(first, 30.0) << "quadratic in the number of cameras?";
  t0 = std::chrono::steady_clock::now();
  for (int frame = 0; frame < 100; ++frame) EXPECT_DOUBLE_EQ(s.cameraSpacing(), 2.0);
  // 100 frames: the cached value, checked against a hash of the centres, each call a small part of
  // the first one (recomputing would cost 100 first calls).
  EXPECT_LT(seconds(t0), 10.0 * first + 0.5);
  // A camera that moves (an edited scene) is noticed.
  for (Photo& p : s.photos) p.camera.center *= 3.0;
  EXPECT_DOUBLE_EQ(s.cameraSpacing(), 6.0);
  // A copy of the scene gives its own answer after its cameras change.
  Scene copy = s;
  copy.photos.resize(2);
  copy.photos[1].camera.center = copy.photos[0].camera.center + glm::dvec3(0, 0, 0.5);
  EXPECT_DOUBLE_EQ(copy.cameraSpacing(), 0.5);
  EXPECT_DOUBLE_EQ(s.cameraSpacing(), 6.0);
}

TEST(SceneCameraSpacing, CoincidentCamerasStayFast) {
  Scene s;
  s.photos.assign(100000, photoAt("same", {651000, 6862000, 35}));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(s.cameraSpacing(), 1.0);
  EXPECT_LT(seconds(t0), 30.0);  // a guard, not a speed: quadratic, every search visited every equal centre (hours)
}

// A 1 km terrain grid (Lambert-93 sized coordinates) with cameras above it.
Scene city() {
  Scene s;
  for (int y = 0; y <= 50; ++y)
    for (int x = 0; x <= 50; ++x) s.terrain.positions.push_back({650000.0 + 20 * x, 6860000.0 + 20 * y, 35.0});
  for (int i = 0; i < 40; ++i)
    s.photos.push_back(photoAt("street" + std::to_string(i), {650100.0 + 20 * i, 6860500.0, 37.0}));
  s.photos.push_back(photoAt("aerial", {650500.0, 6860500.0, 1500.0}));  // legitimately far above
  return s;
}

TEST(SceneRobustExtent, CleanSceneIsItsBounds) {
  const Scene s = city();
  const RobustExtent r = robustExtent(s);
  EXPECT_TRUE(r.outliers.empty()) << r.outliers.front();
  EXPECT_EQ(r.bounds.lo, s.bounds().lo);
  EXPECT_EQ(r.bounds.hi, s.bounds().hi);
  EXPECT_EQ(r.geometry.hi.z, 35.0);  // geometry alone: the terrain
}

TEST(SceneRobustExtent, AbsurdCoordinatesAreLeftOutAndNamed) {
  Scene s = city();
  const Aabb clean = s.bounds();
  s.terrain.positions[17].z = 1e38;                                     // unflagged no-data
  s.terrain.positions[18].x = -1e9;                                     // a typo
  s.terrain.positions[19].y = std::numeric_limits<double>::infinity();  // an inf vertex
  s.buildings.positions = {{650200, 6860200, 35}, {650210, 6860200, 1e9}};  // a 1e9 m building
  s.mesh.positions = {{650300, 6860300, 40}, {1e15, 1e15, 1e15}};       // a LAS-style offset of 1e15
  s.photos.push_back(photoAt("lost", {1e9, 1e9, 1e9}));
  s.photos.push_back(photoAt("degrees", {2.35, 48.85, 35.0}));  // typed in degrees in a Lambert-93 file
  const RobustExtent r = robustExtent(s);
  // The extent, the origin (its centre) and the depth ranges are those of the clean scene.
  EXPECT_EQ(r.bounds.lo, clean.lo);
  EXPECT_EQ(r.bounds.hi, clean.hi);
  std::string all;
  for (const std::string& o : r.outliers) all += o + "\n";
  EXPECT_NE(all.find("terrain: 3 vertices"), std::string::npos) << all;
  EXPECT_NE(all.find("buildings: 1 vertices"), std::string::npos) << all;
  EXPECT_NE(all.find("mesh: 1 vertices"), std::string::npos) << all;
  EXPECT_NE(all.find("camera 'lost'"), std::string::npos) << all;
  EXPECT_NE(all.find("camera 'degrees'"), std::string::npos) << all;
  EXPECT_NE(all.find("left out of the render origin and the depth range"), std::string::npos) << all;
  EXPECT_EQ(r.outliers.size(), 5u) << all;
  // The plain bounds, for comparison, are what made the origin fly off.
  EXPECT_GT(s.bounds().hi.z, 1e37);
}

TEST(SceneRobustExtent, PointChunksCountWithTheirBoxes) {
  Scene s = city();
  PointChunk near, far;
  near.bounds.extend(glm::dvec3(650000, 6860000, 30));
  near.bounds.extend(glm::dvec3(650100, 6860100, 60));
  far.bounds.extend(glm::dvec3(650000, 6860000, 30));
  far.bounds.extend(glm::dvec3(1e15, 6860100, 60));
  s.points.chunks = {near, far};
  const RobustExtent r = robustExtent(s);
  ASSERT_EQ(r.outliers.size(), 1u);
  EXPECT_NE(r.outliers[0].find("points: 1 chunk"), std::string::npos) << r.outliers[0];
  EXPECT_EQ(r.geometry.hi.z, 60.0);
  EXPECT_LT(r.bounds.hi.x, 1e7);
}

TEST(SceneRobustExtent, EmptySceneHasNoExtent) {
  const RobustExtent r = robustExtent(Scene{});
  EXPECT_TRUE(r.bounds.empty());
  EXPECT_TRUE(r.outliers.empty());
}

}  // namespace
}  // namespace hv
