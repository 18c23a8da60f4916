#include "hv/layers/native/scene_objects.h"

#include "hv/scene/native/raycast.h"
#include "hv/testing/box_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace hv::layers
