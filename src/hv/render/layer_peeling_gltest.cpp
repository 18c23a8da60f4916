// Visibility layers peeled on the GPU (render/layer_peeling.h) against the CPU reference: rays
// cast with Embree through every pixel (hv/layers/native/scene_objects.h) and peeled on the hit
// lists (hv/layers/visibility_layers.h), on small scenes of boxes on the ground: a building behind
// another, a courtyard, an L-shape hiding itself, a shed in a courtyard and three sticks in a ring
// (cycles: the GPU stops there and the CPU finishes from its layers, splitting objects into faces
// and triangles).
#include "hv/render/layer_peeling.h"

#include "hv/layers/native/scene_objects.h"
#include "hv/layers/object_layers.h"
#include "hv/layers/visibility_layers.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/scene/native/raycast.h"
#include "hv/testing/box_mesh.h"

#include <gtest/gtest.h>

#include <string>

namespace hv::render {
namespace {

Mesh box(glm::dvec3 lo, glm::dvec3 hi, std::uint32_t tag) { return hv::testing::taggedBox(lo, hi, tag); }

// Flat ground z = 0 over [-100, 100]^2, up-facing, in 16 x 16 quads (tiles of 50 m: 4 x 4 objects).
Mesh ground() {
  Mesh m;
  const int n = 16;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.push_back({-100.0 + 200.0 * i / n, -100.0 + 200.0 * j / n, 0.0});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const unsigned a = unsigned(j * (n + 1) + i), b = a + 1, c = a + unsigned(n + 1) + 1, d = a + unsigned(n + 1);
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  return m;
}

// A building around a courtyard of [-8, 8]^2 inside [-12, 12]^2, `height` high, its feet 1 m under
// the ground, in four boxes with one tag.
Mesh courtyard(double height, std::uint32_t tag) {
  Mesh m = box({-12, -12, -1}, {12, -8, height}, tag);
  m.append(box({-12, 8, -1}, {12, 12, height}, tag));
  m.append(box({-12, -8, -1}, {-8, 8, height}, tag));
  m.append(box({8, -8, -1}, {12, 8, height}, tag));
  return m;
}

struct Compared {
  std::vector<std::uint16_t> cpu, gpu;
  layers::SceneObjects objects;
  layers::VisibilityLayers cpuLayers;
  layers::PixelHits hits;
  GpuObjectLayers gpuLayers;
  std::uint16_t layerOfBuilding(const std::vector<std::uint16_t>& of, std::uint32_t tag) const {
    for (std::uint32_t i = 0; i < objects.objects.size(); ++i)
      if (objects.objects[i].kind == layers::SceneObject::Kind::Building && objects.objects[i].tag == tag) return of[i];
    ADD_FAILURE() << "no building " << tag;
    return 0;
  }
};

Compared peelBoth(const Mesh& buildings, const Camera& camera) {
  testing::glContext();
  Scene scene;
  scene.terrain = ground();
  scene.buildings = buildings;
  Compared c;
  c.objects = layers::collectSceneObjects(scene, 50.0);
  const RayCaster caster(c.objects.geometry);
  c.hits = layers::castPixelHits(camera, c.objects, caster);
  c.cpuLayers = layers::peelVisibilityLayers(c.hits);
  c.cpu.assign(c.objects.objects.size(), 0);
  for (std::size_t k = 0; k < c.cpuLayers.layers.size(); ++k)
    for (std::uint32_t o : c.cpuLayers.layers[k].objects) c.cpu[o] = std::uint16_t(k + 1);
  c.gpuLayers = peelObjectLayersGl(camera, c.objects.geometry, c.objects.objectOfTriangle, c.objects.terrainTriangle,
                                   c.objects.objects.size());
  c.gpu = c.gpuLayers.layerOfObject;
  return c;
}

void expectSameLayers(const Compared& c) {
  ASSERT_EQ(c.cpu.size(), c.gpu.size());
  for (std::size_t o = 0; o < c.cpu.size(); ++o)
    EXPECT_EQ(c.gpu[o], c.cpu[o]) << c.objects.objects[o].name << ": GPU layer " << c.gpu[o] << ", CPU layer "
                                  << c.cpu[o];
}

TEST(GpuLayerPeeling, BuildingBehindAnother) {
  // Building 0 in front, building 1 behind it and wider, both with their feet 2 m underground
  // (as LOD1 walls are on a slope): the buried feet hide nothing.
  Mesh b = box({-5, -10, -2}, {5, -5, 8}, 0);
  b.append(box({-12, 5, -2}, {12, 12, 14}, 1));
  const Compared c = peelBoth(b, lookAtCamera("photo", {0.0, -50.0, 10.0}, {0.0, 0.0, 5.0}, 96, 72, 60.0));
  EXPECT_TRUE(c.cpuLayers.cycles.empty());
  EXPECT_FALSE(c.gpuLayers.stoppedAtCycle);
  EXPECT_EQ(c.layerOfBuilding(c.gpu, 0), 1);
  EXPECT_EQ(c.layerOfBuilding(c.gpu, 1), 2);
  EXPECT_GE(c.gpuLayers.objectsSeen, 4u);  // two buildings and terrain tiles
  EXPECT_EQ(c.gpuLayers.layers, int(c.cpuLayers.layers.size()));
  expectSameLayers(c);
}

TEST(GpuLayerPeeling, CourtyardDoesNotHideItself) {
  // Seen from above at an angle: the front wall hides the foot of the far wall and the courtyard's
  // ground; the building is one object, in layer 1, the ground behind it after.
  const Compared c =
      peelBoth(courtyard(10.0, 3), lookAtCamera("photo", {0.0, -45.0, 30.0}, {0.0, 0.0, 0.0}, 96, 72, 60.0));
  EXPECT_TRUE(c.cpuLayers.cycles.empty());
  EXPECT_EQ(c.layerOfBuilding(c.gpu, 3), 1);
  EXPECT_EQ(c.gpuLayers.layers, int(c.cpuLayers.layers.size()));
  expectSameLayers(c);
}

TEST(GpuLayerPeeling, LShapeHidingItselfInFrontOfABuilding) {
  // An L-shaped building (two boxes, one tag) whose near wing hides part of its far wing, in front
  // of building 2: the L is in layer 1 whole, building 2 in layer 2.
  Mesh b = box({-15, -20, -1}, {5, -14, 12}, 1);
  b.append(box({-15, -14, -1}, {-9, 0, 12}, 1));
  b.append(box({-20, 10, -1}, {20, 16, 20}, 2));
  const Compared c = peelBoth(b, lookAtCamera("photo", {20.0, -60.0, 8.0}, {-5.0, 0.0, 6.0}, 96, 72, 60.0));
  EXPECT_TRUE(c.cpuLayers.cycles.empty());
  EXPECT_EQ(c.layerOfBuilding(c.gpu, 1), 1);
  EXPECT_EQ(c.layerOfBuilding(c.gpu, 2), 2);
  expectSameLayers(c);
}

TEST(GpuLayerPeeling, ShedInACourtyardStopsAtTheCycleAndTheCpuFinishes) {
  // A shed in the courtyard, taller than the courtyard's walls: the front wall hides the shed's
  // foot, the shed hides part of the far wall. Neither can be taken whole: the GPU stops there.
  Mesh b = courtyard(6.0, 3);
  b.append(box({-3, -3, -1}, {3, 3, 12}, 4));
  const Compared c = peelBoth(b, lookAtCamera("photo", {0.0, -45.0, 15.0}, {0.0, 0.0, 4.0}, 96, 72, 60.0));
  // The CPU splits the two into faces (the front wall's outer face hides the shed, the shed's
  // front hides the far wall's inner face: faces can be ordered), nothing at pixel level.
  ASSERT_EQ(c.cpuLayers.splits.size(), 1u);
  EXPECT_EQ(c.cpuLayers.splits[0].into, layers::CycleSplit::Into::Faces);
  EXPECT_EQ(c.cpuLayers.splits[0].objects.size(), 2u);
  EXPECT_TRUE(c.cpuLayers.cycles.empty());
  EXPECT_TRUE(c.gpuLayers.stoppedAtCycle);
  // The objects before the cycle are the CPU's; the CPU then finishes to the same layers.
  const layers::VisibilityLayers finished = layers::completeVisibilityLayers(c.hits, c.gpu);
  EXPECT_EQ(finished.layerOfHit, c.cpuLayers.layerOfHit);
  EXPECT_EQ(finished.cycles, c.cpuLayers.cycles);
  ASSERT_EQ(finished.splits.size(), c.cpuLayers.splits.size());
  EXPECT_EQ(finished.splits[0].objects, c.cpuLayers.splits[0].objects);
}

TEST(GpuLayerPeeling, ThreeSticksStopTheGpuAndTheCpuSplitsThemAlike) {
  // Three sticks overlapping in a ring (hv::testing::threeSticks) over the ground, seen from above:
  // no object can be peeled whole (the ground is under all three), so the GPU stops at once; the
  // CPU splits the sticks into faces, then triangles, and from the GPU's (empty) layers finishes to
  // exactly its own layers.
  const Compared c =
      peelBoth(hv::testing::threeSticks(2), lookAtCamera("photo", {0.0, -3.0, 60.0}, {0.0, 0.0, 0.0}, 96, 96, 180.0));
  EXPECT_TRUE(c.gpuLayers.stoppedAtCycle);
  EXPECT_EQ(c.gpuLayers.layers, 0);
  ASSERT_GE(c.cpuLayers.splits.size(), 2u);
  EXPECT_EQ(c.cpuLayers.splits[0].into, layers::CycleSplit::Into::Faces);
  EXPECT_EQ(c.cpuLayers.splits[0].objects.size(), 3u);
  EXPECT_TRUE(c.cpuLayers.cycles.empty());
  const layers::VisibilityLayers finished = layers::completeVisibilityLayers(c.hits, c.gpu);
  EXPECT_EQ(finished.layerOfHit, c.cpuLayers.layerOfHit);
  ASSERT_EQ(finished.splits.size(), c.cpuLayers.splits.size());
  for (std::size_t k = 0; k < finished.splits.size(); ++k) {
    EXPECT_EQ(finished.splits[k].into, c.cpuLayers.splits[k].into);
    EXPECT_EQ(finished.splits[k].objects, c.cpuLayers.splits[k].objects);
  }
  EXPECT_EQ(finished.splitFaces, c.cpuLayers.splitFaces);
}

TEST(GpuLayerPeeling, MismatchedArraysAreRefused) {
  testing::glContext();
  const Mesh b = box({0, 0, 0}, {1, 1, 1}, 0);
  const Camera cam = lookAtCamera("photo", {0.0, -10.0, 1.0}, {0.0, 0.0, 0.5}, 8, 8, 60.0);
  EXPECT_THROW(peelObjectLayersGl(cam, b, std::vector<std::uint32_t>(3, 0), std::vector<bool>(12, false), 1),
               std::invalid_argument);
  EXPECT_THROW(peelObjectLayersGl(cam, b, std::vector<std::uint32_t>(12, 5), std::vector<bool>(12, false), 1),
               std::invalid_argument);
}

}  // namespace
}  // namespace hv::render
