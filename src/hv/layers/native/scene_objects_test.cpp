#include "hv/layers/native/scene_objects.h"

#include "hv/scene/native/raycast.h"
#include "hv/testing/box_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace hv::layers {
namespace {

Mesh box(glm::dvec3 lo, glm::dvec3 hi, std::uint32_t tag) { return hv::testing::taggedBox(lo, hi, tag); }

// Flat ground z = 0 over [-100, 100]^2, up-facing.
Mesh ground() {
  Mesh m;
  m.positions = {{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

class TwoBuildings : public ::testing::Test {
 protected:
  void SetUp() override {
    // Building 0 in front, building 1 behind it and wider, both with their foot 2 m underground
    // (as LOD1 walls are on a slope).
    scene_.terrain = ground();
    scene_.buildings = box({-5, -10, -2}, {5, -5, 8}, 0);
    scene_.buildings.append(box({-12, 5, -2}, {12, 12, 14}, 1));
    camera_ = lookAtCamera("photo", {0.0, -50.0, 10.0}, {0.0, 0.0, 5.0}, 64, 48, 60.0);
    objects_ = collectSceneObjects(scene_, 100.0);
  }
  std::uint32_t building(std::uint32_t tag) const {
    for (std::uint32_t i = 0; i < objects_.objects.size(); ++i)
      if (objects_.objects[i].kind == SceneObject::Kind::Building && objects_.objects[i].tag == tag) return i;
    ADD_FAILURE() << "no building " << tag;
    return 0;
  }
  Scene scene_;
  Camera camera_;
  SceneObjects objects_;
};

TEST_F(TwoBuildings, ObjectsAreBuildingsAndTerrainTiles) {
  // 200 m of terrain in tiles of 100 m: the two triangles' centroids, (33, -33) and (-33, 33), are
  // (133, 67) and (67, 133) from the terrain's lower corner: column 1 row 0, column 0 row 1.
  ASSERT_EQ(objects_.objects.size(), 4u);
  EXPECT_EQ(objects_.objects[0].name, "terrain 1,0");
  EXPECT_EQ(objects_.objects[1].name, "terrain 0,1");
  EXPECT_EQ(objects_.objects[2].name, "building 0");
  EXPECT_EQ(objects_.objects[3].name, "building 1");
  EXPECT_EQ(objects_.objectOfTriangle.size(), 2u + 24u);
  EXPECT_TRUE(objects_.terrainTriangle[1]);
  EXPECT_FALSE(objects_.terrainTriangle[2]);
}

TEST_F(TwoBuildings, RaysKeepFrontFacesAboveGround) {
  const RayCaster caster(objects_.geometry);
  const PixelHits h = castPixelHits(camera_, objects_, caster);
  ASSERT_EQ(h.pixelCount(), 64u * 48u);
  // The ray through pixel (31, 23): building 0's front wall (y = -10), building 1's (y = 5), then
  // the ground beyond; no back faces, nothing underground. Depths from the planes, by hand.
  const std::size_t p = 23 * 64 + 31;
  ASSERT_EQ(h.first[p + 1] - h.first[p], 3u);
  const glm::dvec3 dir = glm::normalize(camera_.rayDirection({31.5, 23.5}));
  const SurfaceHit* hits = &h.hits[h.first[p]];
  EXPECT_EQ(hits[0].object, building(0));
  EXPECT_NEAR(hits[0].depth, (-10.0 - camera_.center.y) / dir.y, 1e-3);
  EXPECT_EQ(hits[1].object, building(1));
  EXPECT_NEAR(hits[1].depth, (5.0 - camera_.center.y) / dir.y, 1e-3);
  EXPECT_EQ(objects_.objects[hits[2].object].kind, SceneObject::Kind::Terrain);
  EXPECT_NEAR(hits[2].depth, (0.0 - camera_.center.z) / dir.z, 1e-3);
  // Once a ray has met the ground, nothing else: the walls' buried feet hide nothing.
  std::size_t groundThenMore = 0, buriedFeet = 0;
  for (std::size_t q = 0; q < h.pixelCount(); ++q)
    for (std::uint32_t i = h.first[q]; i < h.first[q + 1]; ++i) {
      if (objects_.objects[h.hits[i].object].kind == SceneObject::Kind::Terrain && i + 1 < h.first[q + 1])
        ++groundThenMore;
      const glm::dvec3 point = camera_.center + h.hits[i].depth * *pixelRay(camera_, int(q % 64), int(q / 64));
      if (point.z < -1e-6) ++buriedFeet;
    }
  EXPECT_EQ(groundThenMore, 0u);
  EXPECT_EQ(buriedFeet, 0u);
}

TEST_F(TwoBuildings, LayersFollowTheRayCastOrder) {
  const RayCaster caster(objects_.geometry);
  const PixelHits h = castPixelHits(camera_, objects_, caster);
  const VisibilityLayers v = peelVisibilityLayers(h);
  EXPECT_TRUE(v.cycles.empty());
  auto layerOf = [&](std::uint32_t o) {
    for (std::size_t k = 0; k < v.layers.size(); ++k)
      for (std::uint32_t x : v.layers[k].objects)
        if (x == o) return int(k + 1);
    return 0;
  };
  EXPECT_EQ(layerOf(building(0)), 1);
  EXPECT_EQ(layerOf(building(1)), 2);
  // The ground is behind both buildings somewhere: after them.
  EXPECT_EQ(layerOf(0), 3);
  EXPECT_EQ(layerOf(1), 3);
}

TEST(FaceGroups, PlanarConnectedTrianglesOfOneObject) {
  // A box: its six sides, two triangles each (taggedBox: triangles 2k and 2k + 1 are side k).
  const Mesh b = box({0, 0, 0}, {1, 2, 3}, 0);
  const std::vector<std::uint32_t> face = faceGroups(b, std::vector<std::uint32_t>(12, 0));
  EXPECT_EQ(face, (std::vector<std::uint32_t>{0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5}));
  // An L of two boxes of one object, the second's corners repeating the first's: their walls at
  // x = -15 meet along the edge x = -15, y = -14 and are one face; the same two boxes as two
  // objects keep them apart.
  Mesh l = box({-15, -20, 0}, {5, -14, 12}, 1);
  l.append(box({-15, -14, 0}, {-9, 0, 12}, 1));
  const std::vector<std::uint32_t> one(24, 0);
  std::vector<std::uint32_t> two(24, 0);
  std::fill(two.begin() + 12, two.end(), 1u);
  // Side 4 of taggedBox is x = lo.x (corners 0, 4, 6, 2): triangles 8, 9 of each box.
  const std::vector<std::uint32_t> asOne = faceGroups(l, one), asTwo = faceGroups(l, two);
  EXPECT_EQ(asOne[8], asOne[20]);
  EXPECT_EQ(asOne[9], asOne[21]);
  EXPECT_NE(asTwo[8], asTwo[20]);
  EXPECT_EQ(std::set<std::uint32_t>(asTwo.begin(), asTwo.end()).size(), 12u);
  // The tops (z = 12) share no edge (box 0's runs on to x = 5 where box 1's stops at x = -9): 12
  // sides, two of them one face.
  EXPECT_EQ(std::set<std::uint32_t>(asOne.begin(), asOne.end()).size(), 11u);
  // A stick of 3 segments: 4 long sides of 6 triangles and 2 caps.
  const Mesh stick = hv::testing::taggedStick({0, 0, 0}, {10, 0, 2}, 1.0, 0.5, 3, 0);
  const std::vector<std::uint32_t> sf = faceGroups(stick, std::vector<std::uint32_t>(stick.triangles.size(), 0));
  EXPECT_EQ(std::set<std::uint32_t>(sf.begin(), sf.end()).size(), 6u);
  EXPECT_THROW(faceGroups(b, {0, 0}), std::invalid_argument);
}

// The ray through the pixel where `point` projects from `camera`, and its hits.
std::pair<std::uint32_t, std::uint32_t> hitsAt(const PixelHits& h, const Camera& camera, glm::dvec3 point) {
  const glm::dvec2 px = camera.project(point).pxDistorted;
  const std::size_t p = std::size_t(int(px.y)) * std::size_t(h.width) + std::size_t(int(px.x));
  return {h.first[p], h.first[p + 1]};
}

// Along every ray, a hit is never in a layer after a hit behind it, nor in the same layer unless
// both are the same piece: no piece of layer k is hidden by a piece of layer k or deeper.
std::size_t orderViolations(const PixelHits& h, const VisibilityLayers& v) {
  std::size_t bad = 0;
  for (std::size_t p = 0; p < h.pixelCount(); ++p)
    for (std::uint32_t i = h.first[p]; i < h.first[p + 1]; ++i)
      for (std::uint32_t j = i + 1; j < h.first[p + 1]; ++j) {
        if (v.layerOfHit[i] == 0 || v.layerOfHit[i] > v.layerOfHit[j]) ++bad;
        if (v.layerOfHit[i] == v.layerOfHit[j] && !(v.pieceOf(h, h.hits[i]) == v.pieceOf(h, h.hits[j]))) ++bad;
      }
  return bad;
}

TEST(ThreeSticks, ThreeMutuallyOverlappingObjectsAreSplitAndReported) {
  // Three sticks in a ring seen from 60 m above (hv::testing::threeSticks), two segments each: at
  // corner V_(i+1) stick i passes over stick i + 1. Whole, they cannot be ordered; their faces
  // cannot either (stick i's top hides stick i + 1's top); their triangles can: the end segment of
  // each stick hides the start segment of the next, and nothing hides the end segments.
  Scene scene;
  scene.terrain = ground();
  scene.buildings = hv::testing::threeSticks(2);
  const Camera camera = lookAtCamera("photo", {0.0, -3.0, 60.0}, {0.0, 0.0, 0.0}, 128, 128, 240.0);
  const SceneObjects objects = collectSceneObjects(scene, 100.0);
  ASSERT_EQ(objects.objects.size(), 5u);  // two terrain tiles, three sticks
  const RayCaster caster(objects.geometry);
  const PixelHits h = castPixelHits(camera, objects, caster);
  const VisibilityLayers v = peelVisibilityLayers(h);

  EXPECT_TRUE(v.cycles.empty()) << "a cycle was left to the pixel-level break";
  ASSERT_GE(v.splits.size(), 2u);
  EXPECT_EQ(v.splits[0].into, CycleSplit::Into::Faces);
  EXPECT_EQ(v.splits[0].beforeLayer, 1);
  const auto& ring = v.splits[0].objects;
  ASSERT_EQ(ring.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const SceneObject& a = objects.objects[ring[k]];
    const SceneObject& b = objects.objects[ring[(k + 1) % 3]];
    EXPECT_EQ(b.tag, (a.tag + 1) % 3) << a.name << " is not reported hiding " << b.name;
  }
  std::size_t triangleSplits = 0;
  for (std::size_t k = 1; k < v.splits.size(); ++k) {
    EXPECT_EQ(v.splits[k].into, CycleSplit::Into::Triangles);
    triangleSplits += v.splits[k].into == CycleSplit::Into::Triangles;
    for (std::uint32_t o : v.splits[k].objects) EXPECT_EQ(objects.objects[o].kind, SceneObject::Kind::Building);
  }
  EXPECT_GE(triangleSplits, 1u);
  EXPECT_EQ(v.splitObjects.size(), 3u);  // the sticks, not the ground
  for (std::uint32_t o : v.splitObjects) EXPECT_EQ(objects.objects[o].kind, SceneObject::Kind::Building);
  EXPECT_EQ(orderViolations(h, v), 0u);

  // By hand: over corner V1 = 10 (cos 210°, sin 210°) the ray meets stick 0's top at about 6.5 m
  // (its end segment: layer 1), stick 1's top at about 2.5 m (its start segment, hidden by stick
  // 0: layer 2), then the ground: layer 3, as over V2 (stick 2's start): three layers.
  const double pi = 3.14159265358979323846;
  const auto [first, last] = hitsAt(h, camera, {10.0 * std::cos(210 * pi / 180), 10.0 * std::sin(210 * pi / 180), 6.5});
  ASSERT_EQ(last - first, 3u);
  EXPECT_EQ(objects.objects[h.hits[first].object].name, "building 0");
  EXPECT_EQ(objects.objects[h.hits[first + 1].object].name, "building 1");
  EXPECT_EQ(objects.objects[h.hits[first + 2].object].kind, SceneObject::Kind::Terrain);
  EXPECT_EQ(v.layerOfHit[first], 1);
  EXPECT_EQ(v.layerOfHit[first + 1], 2);
  EXPECT_EQ(v.layerOfHit[first + 2], 3);
  EXPECT_EQ(v.layers.size(), 3u);
  // The triangles are the pieces there: each a different one of its stick's.
  EXPECT_EQ(v.pieceOf(h, h.hits[first]).kind, VisibilityLayers::PieceKind::Triangle);
  EXPECT_EQ(v.pieceOf(h, h.hits[first + 1]).kind, VisibilityLayers::PieceKind::Triangle);
  EXPECT_EQ(v.pieceOf(h, h.hits[first + 2]).kind, VisibilityLayers::PieceKind::Object);
}

TEST(ThreeSticks, CrossingTrianglesAreAReportedCycleBrokenAtPixelLevel) {
  // Two single-triangle plates over the same ground triangle (-5, -5), (5, -5), (0, 5), facing up:
  // P (building 0) at z = 5 + x / 2, Q (building 1) at z = 5 - x / 2. They cross along x = 0: P is
  // above where x > 0, Q where x < 0. No split orders them.
  Scene scene;
  scene.terrain = ground();
  scene.buildings.positions = {{-5, -5, 2.5}, {5, -5, 7.5}, {0, 5, 5}, {-5, -5, 7.5}, {5, -5, 2.5}, {0, 5, 5}};
  scene.buildings.triangles = {{0, 1, 2}, {3, 4, 5}};
  scene.buildings.triangleTags = {0, 1};
  const Camera camera = lookAtCamera("photo", {0.0, -3.0, 60.0}, {0.0, 0.0, 0.0}, 128, 128, 240.0);
  const SceneObjects objects = collectSceneObjects(scene, 100.0);
  const RayCaster caster(objects.geometry);
  const PixelHits h = castPixelHits(camera, objects, caster);
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.cycles.size(), 1u);
  std::set<std::string> names;
  for (std::uint32_t o : v.cycles[0]) names.insert(objects.objects[o].name);
  EXPECT_EQ(names, (std::set<std::string>{"building 0", "building 1"}));
  ASSERT_EQ(v.splits.size(), 3u);
  EXPECT_EQ(v.splits[2].into, CycleSplit::Into::Pixels);
  EXPECT_EQ(orderViolations(h, v), 0u);
  // Where x = 2.5: P (z = 6.25) in front, layer 1; Q (3.75) behind it, layer 2. At x = -2.5 the other
  // way round.
  for (const double x : {2.5, -2.5}) {
    const auto [first, last] = hitsAt(h, camera, {x, -2.0, 5.0 + std::abs(x) / 2});
    ASSERT_EQ(last - first, 3u) << "x = " << x;
    EXPECT_EQ(objects.objects[h.hits[first].object].name, x > 0 ? "building 0" : "building 1");
    EXPECT_EQ(v.layerOfHit[first], 1);
    EXPECT_EQ(v.layerOfHit[first + 1], 2);
    EXPECT_EQ(v.layerOfHit[first + 2], 3);
  }
}

}  // namespace
}  // namespace hv::layers
