#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace hv {
namespace {

// A unit cube at projected (Lambert-93-like) coordinates, where float has only ~0.5 m resolution:
// the caster must shift it to keep centimetre precision.
const glm::dvec3 kCorner(651000.0, 6862000.0, 40.0);

// Vertex i sits at corner + (bit0, bit1, bit2) of i. Faces are wound counter-clockwise seen from
// outside (normals worked out by hand with (v1 - v0) x (v2 - v0)); triangle indices:
// 0-1 bottom (-z), 2-3 top (+z), 4-5 x=0 (-x), 6-7 x=1 (+x), 8-9 y=0 (-y), 10-11 y=1 (+y).
Mesh unitCube(bool flipWinding = false) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back(kCorner + glm::dvec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 4, 6}, {0, 6, 2},
                 {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3}};
  if (flipWinding)
    for (auto& t : m.triangles) std::swap(t.y, t.z);
  return m;
}

// Centimetre precision is the requirement; the hit is refined in double, so a tenth of a
// millimetre is asked for to catch a regression to plain float arithmetic (~0.5 m here).
constexpr double kTol = 1e-4;

TEST(RayCaster, HitsSideFaceFromOutside) {
  const RayCaster caster(unitCube());
  const glm::dvec3 origin = kCorner + glm::dvec3(-10.0, 0.25, 0.75);
  const auto hit = caster.intersect(origin, glm::dvec3(3.0, 0.0, 0.0));  // not normalised on purpose
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 10.0, kTol);
  EXPECT_NEAR(hit->position.x, kCorner.x, kTol);
  EXPECT_NEAR(hit->position.y, kCorner.y + 0.25, kTol);
  EXPECT_NEAR(hit->position.z, kCorner.z + 0.75, kTol);
  EXPECT_EQ(hit->triangle, 4u);  // (0, 4, 6) covers y <= z on the x=0 face
  EXPECT_NEAR(hit->normal.x, -1.0, 1e-12);
  EXPECT_NEAR(hit->normal.y, 0.0, 1e-12);
  EXPECT_NEAR(hit->normal.z, 0.0, 1e-12);
  // (y, z) = (1-u-v)(0,0) + u(0,1) + v(1,1) = (v, u+v) = (0.25, 0.75)
  EXPECT_NEAR(hit->barycentric.x, 0.5, 1e-4);
  EXPECT_NEAR(hit->barycentric.y, 0.25, 1e-4);
}

TEST(RayCaster, HitsRoofFromAbove) {
  const RayCaster caster(unitCube());
  const glm::dvec3 origin = kCorner + glm::dvec3(0.25, 0.75, 100.0);
  const auto hit = caster.intersect(origin, glm::dvec3(0.0, 0.0, -5.0));
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 99.0, kTol);
  EXPECT_NEAR(hit->position.z, kCorner.z + 1.0, kTol);
  EXPECT_EQ(hit->triangle, 3u);  // (4, 7, 6) covers y >= x on the roof
  EXPECT_NEAR(hit->normal.z, 1.0, 1e-12);
  // (x, y) = u(1,1) + v(0,1) = (u, u+v) = (0.25, 0.75)
  EXPECT_NEAR(hit->barycentric.x, 0.25, 1e-4);
  EXPECT_NEAR(hit->barycentric.y, 0.5, 1e-4);
}

TEST(RayCaster, ObliqueRayKeepsCentimetrePrecision) {
  const RayCaster caster(unitCube());
  // Aim at the point (0.3, 0.6, 1) of the roof from 50 m away along (1, 2, -2)/3.
  const glm::dvec3 target = kCorner + glm::dvec3(0.3, 0.6, 1.0);
  const glm::dvec3 dir = glm::dvec3(1.0, 2.0, -2.0) / 3.0;
  const auto hit = caster.intersect(target - 50.0 * dir, dir);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 50.0, kTol);
  EXPECT_NEAR(hit->position.x, target.x, kTol);
  EXPECT_NEAR(hit->position.y, target.y, kTol);
  EXPECT_NEAR(hit->position.z, target.z, kTol);
  EXPECT_NEAR(hit->normal.z, 1.0, 1e-12);
}

TEST(RayCaster, NormalFollowsMeshWindingNotRayDirection) {
  const RayCaster inverted(unitCube(/*flipWinding=*/true));
  const auto hit = inverted.intersect(kCorner + glm::dvec3(0.25, 0.75, 100.0), glm::dvec3(0.0, 0.0, -1.0));
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->normal.z, -1.0, 1e-12);
  // From inside the (outward) cube the ray meets the roof's back side: the normal still points out.
  const RayCaster cube(unitCube());
  const auto inside = cube.intersect(kCorner + glm::dvec3(0.5, 0.5, 0.5), glm::dvec3(0.0, 0.0, 1.0));
  ASSERT_TRUE(inside.has_value());
  EXPECT_NEAR(inside->t, 0.5, kTol);
  EXPECT_NEAR(inside->normal.z, 1.0, 1e-12);
}

TEST(RayCaster, RespectsRayInterval) {
  const RayCaster caster(unitCube());
  const glm::dvec3 origin = kCorner + glm::dvec3(0.5, 0.5, 10.0);
  const glm::dvec3 down(0.0, 0.0, -1.0);
  EXPECT_FALSE(caster.intersect(origin, down, 0.0, 8.0).has_value());  // roof at t = 9
  const auto beyondRoof = caster.intersect(origin, down, 9.5);
  ASSERT_TRUE(beyondRoof.has_value());
  EXPECT_NEAR(beyondRoof->t, 10.0, kTol);  // the floor
  EXPECT_EQ(beyondRoof->triangle / 2, 0u);
  EXPECT_FALSE(caster.intersect(origin, glm::dvec3(0.0, 0.0, 1.0)).has_value());
  EXPECT_FALSE(caster.intersect(kCorner + glm::dvec3(2.0, 0.5, 10.0), down).has_value());
}

TEST(RayCaster, Occluded) {
  const RayCaster caster(unitCube());
  const glm::dvec3 origin = kCorner + glm::dvec3(0.5, 0.5, 10.0);
  const glm::dvec3 down(0.0, 0.0, -2.0);
  EXPECT_TRUE(caster.occluded(origin, down, 0.0, 20.0));
  EXPECT_TRUE(caster.occluded(origin, down, 8.9, 9.1));
  EXPECT_FALSE(caster.occluded(origin, down, 0.0, 8.9));   // stops 10 cm above the roof
  EXPECT_FALSE(caster.occluded(origin, -down, 0.0, 1e6));  // looking up
  EXPECT_FALSE(caster.occluded(kCorner + glm::dvec3(1.05, 0.5, 10.0), down, 0.0, 1e3));  // 5 cm beside
}

TEST(RayCaster, OccludedAgreesWithIntersectOverTerrain) {
  // A 20 x 20 grid of 2 m cells at projected coordinates with a gentle slope, and rays from 1.6 m
  // above it (a pedestrian camera) towards points 0.8 m above it: none may be blocked, while the
  // same rays continued 50 m past the target end up in the ground, as intersect() agrees.
  Mesh ground;
  const int n = 21;
  auto groundZ = [](double x, double y) { return 40.0 + 0.02 * x + 0.01 * y; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      ground.positions.push_back(kCorner + glm::dvec3(2.0 * i, 2.0 * j, groundZ(2.0 * i, 2.0 * j) - 40.0));
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const std::uint32_t a = std::uint32_t(j * n + i), b = a + 1, c = a + n, d = a + n + 1;
      ground.triangles.push_back({a, b, d});
      ground.triangles.push_back({a, d, c});
    }
  const RayCaster caster(ground);
  for (int k = 0; k < 50; ++k) {
    const glm::dvec2 from(3.0 + (k * 13) % 30, 5.0 + (k * 7) % 30),
        to(36.0 - (k * 11) % 30, 2.5 + (k * 17) % 33);
    const glm::dvec3 eye = kCorner + glm::dvec3(from, groundZ(from.x, from.y) - 40.0 + 1.6);
    const glm::dvec3 target = kCorner + glm::dvec3(to, groundZ(to.x, to.y) - 40.0 + 0.8);
    const glm::dvec3 dir = target - eye;
    const double len = glm::length(dir);
    EXPECT_FALSE(caster.occluded(eye, dir, 0.0, len)) << k;
    EXPECT_FALSE(caster.intersect(eye, dir, 0.0, len).has_value()) << k;
    const auto far = caster.intersect(eye, dir, 0.0, len + 1e3);
    EXPECT_EQ(caster.occluded(eye, dir, 0.0, len + 1e3), far.has_value()) << k;
    if (far)
      EXPECT_NEAR(far->position.z - kCorner.z,
                  groundZ(far->position.x - kCorner.x, far->position.y - kCorner.y) - 40.0, kTol);
  }
}

TEST(RayCaster, EmptyMeshNeverHits) {
  const RayCaster caster(Mesh{});
  EXPECT_FALSE(caster.intersect(glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0)).has_value());
  EXPECT_FALSE(caster.occluded(glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0), 0.0, 1e9));
}

TEST(RayCaster, ConcurrentQueriesAgree) {
  const RayCaster caster(unitCube());
  std::atomic<int> wrong{0};
  std::vector<std::thread> threads;
  for (int k = 0; k < 4; ++k)
    threads.emplace_back([&, k] {
      for (int i = 0; i < 2000; ++i) {
        const double x = 0.05 + 0.9 * ((i * 7 + k) % 100) / 100.0;
        const auto hit = caster.intersect(kCorner + glm::dvec3(x, 0.5, 5.0), glm::dvec3(0.0, 0.0, -1.0));
        if (!hit || std::abs(hit->t - 4.0) > kTol) ++wrong;
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(wrong.load(), 0);
}

}  // namespace
}  // namespace hv
