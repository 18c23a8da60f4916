#include "hv/viewer/navigation.h"

#include "hv/scene/native/lod1.h"
#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace hv::viewer {
namespace {

// A terrain z = slope * x over [-60, 60]^2 (a 2 m grid), optionally with a box building.
Mesh slopedGround(double slope) {
  Mesh m;
  const int n = 61;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -60.0 + 2.0 * i, y = -60.0 + 2.0 * j;
      m.positions.push_back({x, y, slope * x});
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const auto a = std::uint32_t(j * n + i), b = a + 1, c = a + std::uint32_t(n), d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  return m;
}

Mesh box(double x0, double x1, double y0, double y1, double z0, double z1) {
  Footprint f;
  f.id = "b";
  f.rings = {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
  return extrudeLod1(f, z0, z1);
}

Camera lookingAlongX(glm::dvec3 eye) {
  return lookAtCamera("start", eye, eye + glm::dvec3(1, 0, 0), 320, 240, 250);
}

NavigationInput forwardFor(double dt) {
  NavigationInput in;
  in.move = {0, 1, 0};
  in.dt = dt;
  return in;
}

TEST(Navigation, HeadingRoundTripsAndRotationHasNoRoll) {
  const UpFrame f = upFrame({0, 0, 1});
  const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, -0.8, 0.2));
  const Heading h = headingOf(d, f);
  const glm::dvec3 back = forwardOf(h, f);
  EXPECT_NEAR(glm::length(back - d), 0.0, 1e-12);
  const glm::dmat3 r = camFromWorldLooking(d, f.up);
  EXPECT_NEAR(glm::length(r * d - glm::dvec3(0, 0, 1)), 0.0, 1e-12);
  // Camera x (right) is horizontal: no roll; camera y (down) points below the horizon.
  const glm::dmat3 w = glm::transpose(r);
  EXPECT_NEAR(glm::dot(w[0], f.up), 0.0, 1e-12);
  EXPECT_LT(glm::dot(w[1], f.up), 0.0);
  EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
}

TEST(Navigation, FlightMovesAlongTheViewAtTheSetSpeed) {
  Navigator nav({0, 0, 1});
  nav.settings().speed = 3.0;
  nav.setCamera(lookingAlongX({0, 0, 10}));
  EXPECT_TRUE(nav.update(forwardFor(0.5)));
  EXPECT_NEAR(glm::length(nav.camera().center - glm::dvec3(1.5, 0, 10)), 0.0, 1e-12);
  NavigationInput up;
  up.move = {0, 0, 1};
  up.dt = 1.0;
  up.fast = true;  // x fastFactor
  nav.update(up);
  EXPECT_NEAR(nav.camera().center.z, 10.0 + 3.0 * nav.settings().fastFactor, 1e-12);
  NavigationInput still;
  still.dt = 0.1;
  EXPECT_FALSE(nav.update(still));
}

TEST(Navigation, GivenRotationIsKeptUntilTheUserLooksAround) {
  Navigator nav({0, 0, 1});
  Camera c = lookingAlongX({0, 0, 10});
  // A rolled camera (a tilted photograph): 10 degrees about its own axis.
  const double a = 10.0 * M_PI / 180.0;
  const glm::dmat3 roll = glm::transpose(glm::dmat3({std::cos(a), std::sin(a), 0}, {-std::sin(a), std::cos(a), 0}, {0, 0, 1}));
  c.camFromWorld = roll * c.camFromWorld;
  nav.setCamera(c);
  nav.update(forwardFor(0.2));
  EXPECT_EQ(nav.camera().camFromWorld, c.camFromWorld);
  NavigationInput look;
  look.lookPixels = {100, 0};  // to the right
  look.dt = 0.016;
  nav.update(look);
  const glm::dvec3 f = forwardOf(nav.camera());
  EXPECT_LT(f.y, 0.0) << "turning right from +x looks towards -y (z up)";
  EXPECT_NEAR(glm::transpose(nav.camera().camFromWorld)[0].z, 0.0, 1e-12) << "no roll once rebuilt";
  look.lookPixels = {0, -1e6};  // far up: clamped
  nav.update(look);
  EXPECT_NEAR(headingOf(forwardOf(nav.camera()), nav.frame()).pitch, nav.settings().maxPitch, 1e-9);
}

TEST(Navigation, WalkingKeepsTheEyeAtItsHeightAboveTheGround) {
  const double slope = 0.1;
  const Mesh ground = slopedGround(slope);
  const RayCaster caster(ground);
  Navigator nav({0, 0, 1}, &caster);
  nav.settings().speed = 2.0;
  nav.setMode(Mode::Walk);
  nav.setCamera(lookingAlongX({-30, 0, 20}));  // starts high: drops onto the ground
  for (int i = 0; i < 60 * 20; ++i) {
    nav.update(forwardFor(1.0 / 60.0));
    if (i < 60) continue;  // one second to settle from the drop
    const glm::dvec3 e = nav.camera().center;
    // The eye follows a rising ramp with a lag of speed * slope * time constant (exponential
    // smoothing of a ramp): 2 * 0.1 * 0.12 = 0.024 here; 0.03 leaves room for discretisation.
    EXPECT_NEAR(e.z - slope * e.x, nav.settings().eyeHeight, 0.03) << "at x = " << e.x;
    EXPECT_NEAR(e.y, 0.0, 1e-9) << "walking straight on";
  }
  EXPECT_NEAR(nav.camera().center.x, -30.0 + 2.0 * 20.0, 1e-6);
}

TEST(Navigation, WalkingIsFrameRateIndependent) {
  const Mesh ground = slopedGround(0.05);
  const RayCaster caster(ground);
  glm::dvec3 ends[2];
  const double dts[2] = {1.0 / 20.0, 1.0 / 120.0};
  for (int k = 0; k < 2; ++k) {
    Navigator nav({0, 0, 1}, &caster);
    nav.setMode(Mode::Walk);
    nav.setCamera(lookingAlongX({0, 0, 1.6}));
    const int steps = int(std::lround(2.0 / dts[k]));
    for (int i = 0; i < steps; ++i) nav.update(forwardFor(dts[k]));
    ends[k] = nav.camera().center;
  }
  EXPECT_NEAR(ends[0].x, ends[1].x, 1e-9);
  EXPECT_NEAR(ends[0].z, ends[1].z, 0.02);  // the ramp lag differs by a fraction of a step
}

TEST(Navigation, WalkingClimbsAKerbButStopsAtAWall) {
  Mesh geometry = slopedGround(0.0);
  geometry.append(box(5, 8, -20, 20, 0, 0.15));   // a kerb: lower than maxStep
  geometry.append(box(12, 20, -20, 20, 0, 10));   // a wall
  const RayCaster caster(geometry);
  Navigator nav({0, 0, 1}, &caster);
  nav.setMode(Mode::Walk);
  nav.setCamera(lookingAlongX({0, 0, 1.6}));
  bool onKerb = false;
  for (int i = 0; i < 60 * 6; ++i) {
    nav.update(forwardFor(1.0 / 60.0));
    const glm::dvec3 e = nav.camera().center;
    if (e.x > 6.0 && e.x < 7.0) {
      onKerb = true;
      EXPECT_NEAR(e.z, 0.15 + 1.6, 0.1);
    }
  }
  EXPECT_TRUE(onKerb);
  EXPECT_NEAR(nav.camera().center.x, 12.0 - nav.settings().bodyRadius, 1e-6);
  EXPECT_NEAR(nav.camera().center.z, 1.6, 1e-3);
}

TEST(Navigation, PhotoInWindowLetterboxesThePhotograph) {
  Camera photo = lookAtCamera("p", {0, 0, 2}, {10, 3, 2}, 400, 300, 350);
  photo.principal = {190, 155};
  const Camera v = photoInWindow(photo, 800, 400);  // wider window: scale 400/300, bars left and right
  const double s = 400.0 / 300.0;
  const glm::dvec3 p(10, 1, 3);
  const glm::dvec2 inPhoto = photo.project(p).pxIdeal;
  const glm::dvec2 inView = v.project(p).pxIdeal;
  EXPECT_NEAR(glm::length(inView - (inPhoto * s + glm::dvec2((800 - 400 * s) / 2, 0))), 0.0, 1e-9);
  EXPECT_EQ(v.width, 800);
  EXPECT_FALSE(v.distortion.has_value());
}

TEST(Navigation, FocusThenContextStepsBackAlongThePhotographsAxis) {
  const Camera from = lookAtCamera("here", {-20, -20, 30}, {0, 0, 0}, 320, 240, 250);
  const Camera photo = lookAtCamera("p", {5, 0, 2}, {15, 4, 3}, 400, 300, 350);
  FocusContextSettings s;
  s.stepBack = 8.0;
  const FocusContextPath path(from, photo, s);
  EXPECT_NEAR(glm::length(path.at(0.0).center - from.center), 0.0, 1e-12);
  const Camera focus = path.at(s.travelSeconds + 0.5 * s.holdSeconds);
  EXPECT_NEAR(glm::length(focus.center - photo.center), 0.0, 1e-12);
  EXPECT_EQ(focus.camFromWorld, photo.camFromWorld);
  const Camera end = path.at(path.duration() + 1.0);
  const glm::dvec3 axis = forwardOf(photo);
  EXPECT_NEAR(glm::length(end.center - (photo.center - 8.0 * axis)), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(forwardOf(end) - axis), 0.0, 1e-9);
  EXPECT_NEAR(end.focal.x, focus.focal.x * s.zoomOut, 1e-9);
  // Context: the photograph's centre ray still lands on the window centre, and the photo's
  // field of view shrinks in the window (it sits inside its surroundings).
  const glm::dvec3 target = photo.center + 30.0 * axis;
  EXPECT_NEAR(glm::length(end.project(target).pxIdeal - glm::dvec2(160, 120)), 0.0, 1e-6);
  // The path is continuous: no jump between consecutive 1/60 s samples.
  double maxJump = 0.0;
  for (double t = 0.0; t < path.duration(); t += 1.0 / 60.0)
    maxJump = std::max(maxJump, glm::length(path.at(t + 1.0 / 60.0).center - path.at(t).center));
  EXPECT_LT(maxJump, 1.0);
}

TEST(Navigation, StepBackStopsInFrontOfAWallBehindTheCamera) {
  const Mesh wall = box(-10, -6, -20, 20, 0, 20);  // 6 m behind a camera at x = 0 looking +x
  const RayCaster caster(wall);
  const Camera photo = lookingAlongX({0, 0, 2});
  FocusContextSettings s;
  s.stepBack = 15.0;
  const FocusContextPath path(photo, photo, s, &caster);
  EXPECT_NEAR(path.context().center.x, -6.0 + s.clearance, 1e-6);
}

TEST(Navigation, StreetOrderFollowsTheStreet) {
  // Cameras along a bent street, shuffled.
  std::vector<glm::dvec3> c;
  for (int i = 0; i < 12; ++i) c.push_back({6.0 * i, i < 6 ? 0.0 : 4.0 * (i - 5), 2.0});
  std::vector<int> truth(c.size());
  for (size_t i = 0; i < c.size(); ++i) truth[i] = int(i);
  std::mt19937 rng(3);
  std::shuffle(truth.begin(), truth.end(), rng);
  std::vector<glm::dvec3> shuffled;
  for (int i : truth) shuffled.push_back(c[size_t(i)]);
  const std::vector<int> order = streetOrder(shuffled);
  ASSERT_EQ(order.size(), c.size());
  std::vector<int> along;
  for (int i : order) along.push_back(truth[size_t(i)]);
  if (along.front() != 0) std::reverse(along.begin(), along.end());
  for (size_t i = 0; i < along.size(); ++i) EXPECT_EQ(along[i], int(i));

  EXPECT_EQ(stepAlong(order, order[3], 1), order[4]);
  EXPECT_EQ(stepAlong(order, order[3], -1), order[2]);
  EXPECT_EQ(stepAlong(order, order.back(), 1), order.back()) << "clamped at the end of the street";
  EXPECT_EQ(stepAlong(order, -1, 1), order.front());
  EXPECT_EQ(nearestCentre(shuffled, {0.5, 0.2, 2}), int(std::find(truth.begin(), truth.end(), 0) - truth.begin()));
}

}  // namespace
}  // namespace hv::viewer

namespace hv::viewer {
namespace {

TEST(Navigation, ScaleDefaultsCrossTheSurfaceDistanceInTwoSeconds) {
  const ScaleDefaults d = scaleDefaults(12.0);
  EXPECT_EQ(d.speed, 6.0);
  EXPECT_EQ(d.stepBack, 12.0);
  EXPECT_EQ(d.orbitRadius, 24.0);
  EXPECT_EQ(scaleDefaults(std::nan("")).speed, ScaleDefaults{}.speed);
}

TEST(Navigation, FocusOnAnUpsideDownRigCameraKeepsTheHorizonLevel) {
  // A rig camera stored upside down (Stereopolis camera 302): rolled 180 degrees about its axis.
  Camera photo = lookAtCamera("302", {0, 0, 2}, {10, 0, 2}, 400, 300, 300);
  photo.camFromWorld = glm::dmat3(-1, 0, 0, 0, -1, 0, 0, 0, 1) * photo.camFromWorld;
  EXPECT_NEAR(std::abs(rollOf(photo, {0, 0, 1})), std::numbers::pi, 1e-12);
  const Camera from = lookAtCamera("here", {-20, -20, 30}, {0, 0, 0}, 400, 300, 250);
  FocusContextSettings s;
  const FocusContextPath path(from, photo, s);
  for (const Camera* c : {&path.focus(), &path.context()}) {
    EXPECT_NEAR(rollOf(*c, {0, 0, 1}), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(forwardOf(*c) - forwardOf(photo)), 0.0, 1e-12) << "still looks where it looked";
    // Up in the world is up in the image.
    EXPECT_LT(c->project({10, 0, 5}).pxIdeal.y, c->project({10, 0, -1}).pxIdeal.y);
  }
  // A small roll is kept: the photograph then fills the window exactly.
  Camera tilted = lookAtCamera("p", {0, 0, 2}, {10, 0, 2}, 400, 300, 300);
  const double a = 5.0 * std::numbers::pi / 180.0;
  tilted.camFromWorld =
      glm::dmat3(std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a), 0, 0, 0, 1) * tilted.camFromWorld;
  EXPECT_NEAR(std::abs(rollOf(tilted, {0, 0, 1})), a, 1e-12);
  EXPECT_EQ(FocusContextPath(from, tilted, s).focus().camFromWorld, tilted.camFromWorld);
  // And the setting turns the levelling off.
  s.levelHorizon = false;
  EXPECT_EQ(FocusContextPath(from, photo, s).focus().camFromWorld, photo.camFromWorld);
}

}  // namespace
}  // namespace hv::viewer
