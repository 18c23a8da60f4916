#include "hv/camera/camera.h"

#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv {
namespace {

// A camera at (10, 20, 30) looking along world +y, with camera x = world +x and camera y (down) =
// world -z: R rows are the camera axes expressed in the world frame.
Camera lookingNorth() {
  Camera c;
  c.id = "north";
  c.width = 640;
  c.height = 480;
  c.center = {10.0, 20.0, 30.0};
  const double r[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
  c.camFromWorld = mat3FromRowMajor(r);
  c.focal = {500.0, 400.0};
  c.principal = {320.5, 240.5};
  return c;
}

TEST(Camera, ProjectsAgainstHandComputedValues) {
  const Camera c = lookingNorth();
  // P - C = (2, 10, 1): camera (x, y, z) = (2, -1, 10); pixel = (500*2/10 + 320.5, 400*-1/10 + 240.5).
  const Projection p = c.project({12.0, 30.0, 31.0});
  EXPECT_TRUE(p.inFront);
  EXPECT_TRUE(p.inImage);
  EXPECT_NEAR(p.depth, 10.0, 1e-12);
  EXPECT_NEAR(p.pxIdeal.x, 420.5, 1e-12);
  EXPECT_NEAR(p.pxIdeal.y, 200.5, 1e-12);
  // Behind the camera.
  EXPECT_FALSE(c.project({10.0, 10.0, 30.0}).inFront);
  // In front but outside the image: x = 500 * 10 / 10 + 320.5 = 820.5 > 640.
  EXPECT_FALSE(c.project({20.0, 30.0, 30.0}).inImage);
}

TEST(Camera, SkewEntersXOnly) {
  Camera c = lookingNorth();
  c.skew = 5.0;
  const Projection p = c.project({12.0, 30.0, 31.0});  // camera (2, -1, 10)
  EXPECT_NEAR(p.pxIdeal.x, 420.5 + 5.0 * -1.0 / 10.0, 1e-12);
  EXPECT_NEAR(p.pxIdeal.y, 200.5, 1e-12);
}

TEST(Camera, RayThroughPixelRoundTrips) {
  Camera c = lookingNorth();
  c.skew = 3.0;
  for (glm::dvec2 px : {glm::dvec2(0.5, 0.5), glm::dvec2(639.5, 10.25), glm::dvec2(320.5, 479.0)}) {
    const glm::dvec3 dir = c.rayDirection(px);
    const glm::dvec3 P = c.center + 7.5 * dir;
    const Projection p = c.project(P);
    EXPECT_NEAR(p.depth, 7.5, 1e-9);
    EXPECT_NEAR(p.pxIdeal.x, px.x, 1e-9);
    EXPECT_NEAR(p.pxIdeal.y, px.y, 1e-9);
  }
}

TEST(LensDistortion, ForwardMatchesPolynomial) {
  LensDistortion d;
  d.center = {100.0, 50.0};
  d.c3 = 1e-6;
  d.c5 = -2e-12;
  d.c7 = 3e-18;
  // r = (30, 40), |r|^2 = 2500: factor = 1e-6*2500 - 2e-12*2500^2 + 3e-18*2500^3
  const double r2 = 2500.0;
  const double factor = 1e-6 * r2 - 2e-12 * r2 * r2 + 3e-18 * r2 * r2 * r2;
  const glm::dvec2 pd = d.distort({130.0, 90.0});
  EXPECT_NEAR(pd.x, 130.0 + 30.0 * factor, 1e-12);
  EXPECT_NEAR(pd.y, 90.0 + 40.0 * factor, 1e-12);
  EXPECT_EQ(d.distort(d.center), d.center);
}

TEST(LensDistortion, DomainAndInverse) {
  LensDistortion d;
  d.center = {320.0, 240.0};
  d.c3 = -2e-7;  // barrel; monotonic while 1 + 3 c3 r^2 > 0, i.e. r < ~1290
  d.r2max = 600.0 * 600.0;
  EXPECT_TRUE(d.inDomain({320.0 + 599.0, 240.0}));
  EXPECT_FALSE(d.inDomain({320.0 + 601.0, 240.0}));
  for (glm::dvec2 p : {glm::dvec2(0.0, 0.0), glm::dvec2(640.0, 480.0), glm::dvec2(321.0, 100.0)}) {
    const glm::dvec2 pd = d.distort(p);
    const auto back = d.undistort(pd);
    ASSERT_TRUE(back.has_value());
    EXPECT_NEAR(back->x, p.x, 1e-7);
    EXPECT_NEAR(back->y, p.y, 1e-7);
  }
  // Outside the domain: no inverse.
  EXPECT_FALSE(d.undistort(d.distort({320.0 + 650.0, 240.0})).has_value());
}

TEST(Camera, DistortedProjectionUsesDistortedPixel) {
  Camera c = lookingNorth();
  LensDistortion d;
  d.center = {320.5, 240.5};
  d.c3 = 1e-6;
  c.distortion = d;
  const Projection p = c.project({12.0, 30.0, 31.0});  // ideal (420.5, 200.5), r = (100, -40)
  const double f = 1e-6 * (100.0 * 100.0 + 40.0 * 40.0);
  EXPECT_NEAR(p.pxDistorted.x, 420.5 + 100.0 * f, 1e-9);
  EXPECT_NEAR(p.pxDistorted.y, 200.5 - 40.0 * f, 1e-9);
}

TEST(Camera, ScaledKeepsNormalisedProjection) {
  Camera c = lookingNorth();
  LensDistortion d;
  d.center = {300.0, 200.0};
  d.c3 = 1e-6;
  d.c5 = 1e-12;
  c.distortion = d;
  const Camera half = c.scaled(0.5, 320, 240);
  const glm::dvec3 P(13.0, 31.0, 29.0);
  const Projection a = c.project(P), b = half.project(P);
  EXPECT_NEAR(b.pxDistorted.x, 0.5 * a.pxDistorted.x, 1e-9);
  EXPECT_NEAR(b.pxDistorted.y, 0.5 * a.pxDistorted.y, 1e-9);
}

TEST(ValidateCamera, RejectsBadFieldsNamingThem) {
  auto expectError = [](Camera c, const std::string& field) {
    try {
      validateCamera(c);
      FAIL() << "accepted a camera with a bad " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("north"), std::string::npos) << e.what();
    }
  };
  Camera c = lookingNorth();
  c.focal.x = 0.0;
  expectError(c, "focal");
  c = lookingNorth();
  c.focal.y = -3.0;
  expectError(c, "focal");
  c = lookingNorth();
  c.center.y = std::nan("");
  expectError(c, "center");
  c = lookingNorth();
  c.camFromWorld[0][0] = 1.01;  // defect 0.0201 > 1e-5
  expectError(c, "rotation");
  c = lookingNorth();
  c.camFromWorld[1] = -c.camFromWorld[1];  // a reflection is orthonormal but not a rotation
  expectError(c, "rotation");
  c = lookingNorth();
  c.width = 0;
  expectError(c, "width");
}

TEST(ValidateCamera, ReorthonormalisesSmallDefects) {
  Camera c = lookingNorth();
  c.camFromWorld[0][0] += 3e-6;  // |R R^T - I| ~ 6e-6 < 1e-5
  validateCamera(c);
  const glm::dmat3 rrt = c.camFromWorld * glm::transpose(c.camFromWorld);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(rrt[i][j], i == j ? 1.0 : 0.0, 1e-14);
  EXPECT_NEAR(c.camFromWorld[0][0], 1.0, 1e-5);
}

}  // namespace
}  // namespace hv
