// The pose mode's session (hv/pose/pose_session.h), driven as the viewer drives it: a click on the
// photograph, then a click in the 3D view turned into a world point by an Embree ray cast through
// the view's camera (here the photograph's true camera, so the same pixel shows the same point).
#include "hv/pose/pose_session.h"

#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::pose {
namespace {

double angleDegrees(const glm::dmat3& a, const glm::dmat3& b) {
  const glm::dmat3 d = a * glm::transpose(b);
  return std::acos(std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0, -1.0, 1.0)) * 180.0 / M_PI;
}

// A ground square and two boxes, in a projected CRS's range of coordinates.
Mesh city() {
  const glm::dvec3 o(651000.0, 6862000.0, 40.0);
  Mesh m;
  auto quad = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d) {
    const unsigned base = unsigned(m.positions.size());
    for (const glm::dvec3& p : {a, b, c, d}) m.positions.push_back(o + p);
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  };
  quad({-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0});
  auto box = [&](glm::dvec3 lo, glm::dvec3 hi) {
    quad({lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z});  // south face
    quad({hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {hi.x, lo.y, hi.z});  // east
    quad({lo.x, hi.y, lo.z}, {lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z});  // west
    quad({lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z});  // roof
  };
  box({-20, 10, 0}, {-5, 25, 18});
  box({5, 5, 0}, {22, 20, 12});
  return m;
}

Camera truth() {
  const glm::dvec3 o(651000.0, 6862000.0, 40.0);
  Camera c = lookAtCamera("p1", o + glm::dvec3(6.0, -48.0, 9.0), o + glm::dvec3(0.0, 10.0, 5.0), 1200, 900, 1100.0);
  c.principal = {604.0, 447.0};
  return c;
}

// The photograph's camera as the scene has it: 6 m and 5 degrees wrong.
Camera wrong(const Camera& t) {
  Camera w = t;
  w.center += glm::dvec3(4.0, -3.0, 3.0);
  const double a = 5.0 * M_PI / 180.0;
  const glm::dmat3 rz(glm::dvec3(std::cos(a), std::sin(a), 0), glm::dvec3(-std::sin(a), std::cos(a), 0),
                      glm::dvec3(0, 0, 1));
  w.camFromWorld = t.camFromWorld * rz;
  return w;
}

// A click in the 3D view at `px` of `view`, as the viewer makes it.
std::optional<glm::dvec3> pick(const RayCaster& caster, const Camera& view, glm::dvec2 px) {
  const WorldRay r = rayThroughPixel(view, px);
  if (!r.valid) return std::nullopt;
  const auto hit = caster.intersect(r.origin, r.direction);
  if (!hit) return std::nullopt;
  return hit->position;
}

TEST(PoseSession, FourClickedPairsRecoverTheCamera) {
  const Mesh m = city();
  const RayCaster caster(m);
  const Camera t = truth();
  PoseSession s(wrong(t));
  EXPECT_EQ(s.pairsNeeded(), 4);
  const glm::dvec2 clicks[] = {{150.5, 700.5}, {1050.5, 760.5}, {400.5, 380.5}, {820.5, 420.5}, {600.5, 850.5}};
  int n = 0;
  for (const glm::dvec2 px : clicks) {
    EXPECT_EQ(s.step(), PoseSession::Step::Photo);
    ASSERT_TRUE(s.clickPhoto(px));
    EXPECT_EQ(s.step(), PoseSession::Step::Scene);
    ASSERT_TRUE(s.clickScene(pick(caster, t, px))) << s.message();
    ++n;
    EXPECT_EQ(s.solution().has_value(), n >= 4) << s.message();
  }
  ASSERT_TRUE(s.solution()) << s.message();
  const Camera& c = s.solution()->camera;
  EXPECT_LT(glm::distance(c.center, t.center), 0.1);
  EXPECT_LT(angleDegrees(c.camFromWorld, t.camFromWorld), 0.1);
  EXPECT_EQ(c.focal, t.focal);  // the intrinsics kept
  for (const ResidualLine& l : s.residualLines()) EXPECT_LT(l.pixels, 0.05);
}

TEST(PoseSession, SolvingTheFocalNeedsSixPairs) {
  const Mesh m = city();
  const RayCaster caster(m);
  const Camera t = truth();
  Camera start = wrong(t);
  start.focal *= 0.85;
  PoseSession s(start, true);
  EXPECT_EQ(s.pairsNeeded(), 6);
  const glm::dvec2 clicks[] = {{150.5, 700.5}, {1050.5, 760.5}, {400.5, 380.5}, {820.5, 420.5},
                               {600.5, 850.5}, {300.5, 250.5},  {980.5, 520.5}, {700.5, 600.5}};
  int n = 0;
  for (const glm::dvec2 px : clicks) {
    s.clickPhoto(px);
    ASSERT_TRUE(s.clickScene(pick(caster, t, px)));
    ++n;
    if (n == 5) EXPECT_FALSE(s.solution());
  }
  ASSERT_TRUE(s.solution()) << s.message();
  EXPECT_LT(glm::distance(s.solution()->camera.center, t.center), 0.1);
  EXPECT_LT(angleDegrees(s.solution()->camera.camFromWorld, t.camFromWorld), 0.1);
  EXPECT_NEAR(s.solution()->camera.focal.x / t.focal.x, 1.0, 0.005);
}

TEST(PoseSession, ClicksOutOfOrderSkyAndRemoval) {
  const Mesh m = city();
  const RayCaster caster(m);
  const Camera t = truth();
  PoseSession s(wrong(t));
  EXPECT_FALSE(s.clickScene(glm::dvec3(0.0)));  // no photograph pixel yet
  EXPECT_NE(s.message().find("photograph first"), std::string::npos);
  EXPECT_FALSE(s.clickPhoto({-3.0, 10.0}));
  EXPECT_FALSE(s.clickPhoto({10.0, 901.0}));
  EXPECT_EQ(s.step(), PoseSession::Step::Photo);
  // Above the horizon: the sky, no pair; the pixel stays pending.
  ASSERT_TRUE(s.clickPhoto({600.5, 20.5}));
  EXPECT_FALSE(s.clickScene(pick(caster, t, {600.5, 20.5})));
  EXPECT_NE(s.message().find("sky"), std::string::npos);
  EXPECT_EQ(s.step(), PoseSession::Step::Scene);
  s.cancel();
  EXPECT_EQ(s.step(), PoseSession::Step::Photo);
  // A wrong pair among five: with four right ones the solution holds it an outlier; removed, the
  // solution is the same camera and every residual small.
  const glm::dvec2 clicks[] = {{150.5, 700.5}, {1050.5, 760.5}, {400.5, 380.5}, {820.5, 420.5}, {600.5, 850.5}};
  for (const glm::dvec2 px : clicks) {
    s.clickPhoto(px);
    ASSERT_TRUE(s.clickScene(pick(caster, t, px)));
  }
  s.clickPhoto({300.5, 600.5});
  ASSERT_TRUE(s.clickScene(pick(caster, t, {900.5, 650.5})));  // the wrong point
  ASSERT_EQ(s.pairs().size(), 6u);
  ASSERT_TRUE(s.solution()) << s.message();
  EXPECT_FALSE(s.solution()->inliers[5]);
  const int before = s.solutionVersion();
  EXPECT_FALSE(s.removePair(6));
  ASSERT_TRUE(s.removePair(5));
  EXPECT_GT(s.solutionVersion(), before);
  ASSERT_EQ(s.pairs().size(), 5u);
  EXPECT_LT(glm::distance(s.solution()->camera.center, t.center), 0.1);
  // Down to three: no solution, and it says how many more.
  s.removePair(0), s.removePair(0);
  EXPECT_FALSE(s.solution());
  EXPECT_NE(s.message().find("1 more"), std::string::npos) << s.message();
}

TEST(PoseSession, DraggingAMisplacedPointFixesIt) {
  const Mesh m = city();
  const RayCaster caster(m);
  const Camera t = truth();
  PoseSession s(wrong(t));
  const glm::dvec2 clicks[] = {{150.5, 700.5}, {1050.5, 760.5}, {400.5, 380.5}, {820.5, 420.5}};
  for (const glm::dvec2 px : clicks) {
    s.clickPhoto(px);
    ASSERT_TRUE(s.clickScene(pick(caster, t, px)));
  }
  ASSERT_TRUE(s.solution());
  // Pair 3's photograph pixel 25 px off its point: the four pairs no longer agree.
  ASSERT_TRUE(s.movePair(2, clicks[2] + glm::dvec2(25.0, -10.0)));
  const bool off =
      !s.solution() || glm::distance(s.solution()->camera.center, t.center) > 0.5 || s.residualLines()[2].pixels > 5.0;
  EXPECT_TRUE(off) << s.message();
  // Dragged back onto it: the camera again, the world point unchanged.
  const glm::dvec3 world = s.pairs()[2].world;
  const int before = s.solutionVersion();
  ASSERT_TRUE(s.movePair(2, clicks[2]));
  EXPECT_GT(s.solutionVersion(), before);
  EXPECT_EQ(s.pairs()[2].world, world);
  ASSERT_TRUE(s.solution()) << s.message();
  EXPECT_LT(glm::distance(s.solution()->camera.center, t.center), 0.1);
  // Nowhere to move to: refused and said.
  EXPECT_FALSE(s.movePair(4, {10.0, 10.0}));
  EXPECT_NE(s.message().find("no pair 5"), std::string::npos) << s.message();
  EXPECT_FALSE(s.movePair(0, {1300.0, 10.0}));
  EXPECT_NE(s.message().find("cannot leave"), std::string::npos) << s.message();
  EXPECT_EQ(s.pairs()[0].pixel, clicks[0]);
}

TEST(PoseSession, RayThroughAPixelMeetsWhatItShows) {
  const Camera t = truth();
  const glm::dvec3 X = t.center + glm::dvec3(3.0, 30.0, -4.0);
  const Projection p = t.project(X);
  const WorldRay r = rayThroughPixel(t, p.pxDistorted);
  ASSERT_TRUE(r.valid);
  const glm::dvec3 toX = glm::normalize(X - t.center);
  EXPECT_NEAR(glm::dot(glm::normalize(r.direction), toX), 1.0, 1e-12);
  EXPECT_EQ(r.origin, t.center);
}

TEST(PoseSaving, NeverOverwritesSilently) {
  const std::vector<std::string> inputs = {"/data/city/scene.json", "/data/city/cameras.json"};
  EXPECT_EQ(checkSavePath("", inputs, false, false), "give the cameras.json to write");
  EXPECT_NE(checkSavePath("/data/city/./cameras.json", inputs, true, true).find("input"), std::string::npos);
  EXPECT_NE(checkSavePath("/tmp/posed.json", inputs, true, false).find("exists"), std::string::npos);
  EXPECT_EQ(checkSavePath("/tmp/posed.json", inputs, true, true), "");
  EXPECT_EQ(checkSavePath("/tmp/new.json", inputs, false, false), "");
}

}  // namespace
}  // namespace hv::pose
