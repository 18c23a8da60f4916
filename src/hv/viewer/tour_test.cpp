// Tours and orbits (viewer/tour.h).
#include "hv/viewer/tour.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace hv::viewer {
namespace {

TEST(Tour, TwoOptUntanglesWhatTheNearestNeighbourChainCrosses) {
  // Two parallel streets 10 apart, houses every 6: the nearest-neighbour chain runs down one
  // street and jumps back to the far end of the other; the best open path is a U (one street,
  // across, the other back), 5 * 6 + 10 + 5 * 6 = 70.
  std::vector<glm::dvec3> c;
  for (int i = 0; i < 6; ++i) c.push_back({6.0 * i, 0.0, 0.0});
  for (int i = 0; i < 6; ++i) c.push_back({6.0 * i, 10.0, 0.0});
  std::mt19937 rng(7);
  std::shuffle(c.begin(), c.end(), rng);
  const std::vector<int> nn = streetOrder(c), tour = tourOrder(c);
  ASSERT_EQ(tour.size(), c.size());
  std::vector<int> sorted = tour;
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 0; i < sorted.size(); ++i) EXPECT_EQ(sorted[i], int(i)) << "each photograph once";
  EXPECT_LE(pathLength(c, tour), pathLength(c, nn) + 1e-9);
  EXPECT_NEAR(pathLength(c, tour), 70.0, 1e-9);
}

TEST(Tour, TwoOptShortensTheNearestNeighbourChain) {
  // Six houses where the greedy chain (from (1, 6), the farthest from the centroid) goes
  // (3,3) (4,1) (5,1) (6,3) and back to (2,1): 13.55. The shortest open path from (1, 6), found by
  // trying all 720 orders (outside this test), is (3,3) (2,1) (4,1) (5,1) (6,3): 11.08.
  const std::vector<glm::dvec3> c{{1, 6, 0}, {3, 3, 0}, {4, 1, 0}, {2, 1, 0}, {5, 1, 0}, {6, 3, 0}};
  EXPECT_EQ(streetOrder(c), (std::vector<int>{0, 1, 2, 4, 5, 3}));
  EXPECT_NEAR(pathLength(c, streetOrder(c)), 13.549823185463149, 1e-9);
  EXPECT_EQ(tourOrder(c), (std::vector<int>{0, 1, 3, 2, 4, 5}));
  EXPECT_NEAR(pathLength(c, tourOrder(c)), 11.07768723046357, 1e-9);
}

TEST(Tour, KeysVisitEachPhotographThenStepBack) {
  const Camera a = lookAtCamera("a", {0, 0, 2}, {10, 0, 2}, 400, 300, 300);
  const Camera b = lookAtCamera("b", {20, 0, 2}, {20, 10, 2}, 400, 300, 300);
  TourSettings s;
  s.focus.stepBack = 4.0;
  s.speed = 2.0;
  const std::vector<PathKey> keys = focusContextKeys({a, b}, 800, 600, s);
  ASSERT_EQ(keys.size(), 6u);  // focus, hold, context for each
  for (size_t i = 1; i < keys.size(); ++i) EXPECT_GT(keys[i].time, keys[i - 1].time);
  EXPECT_EQ(keys[0].camera.center, a.center);
  EXPECT_EQ(keys[1].camera.center, a.center);
  EXPECT_NEAR(glm::length(keys[2].camera.center - glm::dvec3(-4, 0, 2)), 0.0, 1e-9);   // a looks along +x
  EXPECT_NEAR(glm::length(keys[5].camera.center - glm::dvec3(20, -4, 2)), 0.0, 1e-9);  // b along +y
  // From a's context (-4, 0, 2) to b (20, 0, 2): 24 units at 2 units/s.
  EXPECT_NEAR(keys[3].time - keys[2].time, 12.0, 1e-9);
  for (const PathKey& k : keys) {
    EXPECT_EQ(k.camera.width, 800);
    EXPECT_EQ(k.camera.height, 600);
  }
  // The photograph still fills the window (scaled by 2) and looks where it looked.
  EXPECT_NEAR(keys[0].camera.focal.x, 600.0, 1e-9);
  EXPECT_NEAR(glm::length(forwardOf(keys[3].camera) - glm::dvec3(0, 1, 0)), 0.0, 1e-12);
  EXPECT_NO_THROW(CameraPath{keys});
  EXPECT_THROW(focusContextKeys({}, 800, 600, s), std::invalid_argument);
}

TEST(Tour, OrbitCirclesThePointLookingAtIt) {
  const glm::dvec3 p(100, 200, 10);
  OrbitSettings s;
  s.radius = 30.0;
  s.elevationDeg = 45.0;
  s.keys = 8;
  s.seconds = 16.0;
  const std::vector<PathKey> keys = orbitKeys(p, {0, 0, 1}, 640, 480, s);
  ASSERT_EQ(keys.size(), 9u);
  for (size_t i = 0; i < keys.size(); ++i) {
    const glm::dvec3 d = keys[i].camera.center - p;
    EXPECT_NEAR(std::hypot(d.x, d.y), 30.0, 1e-9);
    EXPECT_NEAR(d.z, 30.0, 1e-9);  // tan 45 deg * 30
    EXPECT_NEAR(glm::length(keys[i].camera.project(p).pxIdeal - glm::dvec2(320, 240)), 0.0, 1e-9);
    EXPECT_NEAR(keys[i].time, 2.0 * double(i), 1e-12);
  }
  EXPECT_NEAR(glm::length(keys.front().camera.center - keys.back().camera.center), 0.0, 1e-9);
  // A quarter turn later the eye is a quarter round, counter-clockwise seen from above.
  const glm::dvec3 d0 = keys[0].camera.center - p, d2 = keys[2].camera.center - p;
  EXPECT_NEAR(d0.x * d2.y - d0.y * d2.x, 900.0, 1e-6);
  s.radius = 0.0;
  EXPECT_THROW(orbitKeys(p, {0, 0, 1}, 640, 480, s), std::invalid_argument);
}

}  // namespace
}  // namespace hv::viewer
