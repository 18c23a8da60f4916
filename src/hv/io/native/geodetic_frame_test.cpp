// GeoPose of cameras in projected CRSs (hv/io/native/georef.h geodeticFrameAt, hv/pose/geopose.h):
// positions and orientations against values known without PROJ — the projections' own origins,
// and Lambert-93's meridian convergence n (λ − λ0).
#include "hv/io/native/georef.h"
#include "hv/pose/geopose.h"

#include <gtest/gtest.h>

#include <proj.h>

#include <cmath>

namespace hv {
namespace {

constexpr double kDeg = M_PI / 180.0;

glm::dvec4 geoPoseQuaternion(const Camera& c, const GeodeticFrame& f) {
  return pose::quaternionOf(pose::enuFromCameraObject(c.camFromWorld, f.enuFromWorld));
}

void expectQuaternion(glm::dvec4 q, glm::dvec4 e, double tol) {
  if (e.w < 0.0) e = -e;
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(q[i], e[i], tol) << "component " << i;
}

TEST(GeodeticFrame, Lambert93OriginLookingEast) {
  // Lambert-93's false origin (700000, 6600000) is lon 3°, lat 46.5° (its central meridian and
  // latitude of origin); grid north is true north on the central meridian.
  Diagnostics diag;
  const glm::dvec3 c(700000.0, 6600000.0, 52.0);
  const GeodeticFrame f = geodeticFrameAt("EPSG:2154", c, diag);
  EXPECT_NEAR(f.latDeg, 46.5, 1e-9);
  EXPECT_NEAR(f.lonDeg, 3.0, 1e-9);
  EXPECT_NEAR(f.heightM, 52.0, 1e-6);  // a 2D CRS: z passes through
  EXPECT_TRUE(f.heightIsZ);
  // A level camera looking east (+x): yaw −90°.
  const Camera cam = lookAtCamera("e", c, c + glm::dvec3(10.0, 0.0, 0.0), 640, 480, 500.0);
  expectQuaternion(geoPoseQuaternion(cam, f), {0, 0, -std::sin(45 * kDeg), std::cos(45 * kDeg)}, 1e-7);
}

TEST(GeodeticFrame, Lambert93EastOfTheCentralMeridian) {
  // At lon 5°, grid north points east of true north by the meridian convergence
  // γ = n (λ − λ0), n = 0.7256077650 for Lambert-93 (IGN's constant of the projection): a camera
  // looking along grid north has a true azimuth of +γ, a GeoPose yaw of −γ.
  PJ_CONTEXT* ctx = proj_context_create();
  PJ* op = proj_create_crs_to_crs(ctx, "EPSG:4326", "EPSG:2154", nullptr);
  ASSERT_TRUE(op);
  const PJ_COORD xy = proj_trans(op, PJ_FWD, proj_coord(46.5, 5.0, 0.0, 0.0));  // EPSG:4326: lat, lon
  proj_destroy(op);
  proj_context_destroy(ctx);
  Diagnostics diag;
  const glm::dvec3 c(xy.xy.x, xy.xy.y, 35.0);
  const GeodeticFrame f = geodeticFrameAt("EPSG:2154", c, diag);
  EXPECT_NEAR(f.latDeg, 46.5, 1e-8);
  EXPECT_NEAR(f.lonDeg, 5.0, 1e-8);
  const double gamma = 0.7256077650 * 2.0 * kDeg;
  const glm::dmat3 worldFromEnu = glm::transpose(f.enuFromWorld);
  EXPECT_NEAR(glm::distance(worldFromEnu[1], glm::dvec3(-std::sin(gamma), std::cos(gamma), 0.0)), 0.0, 1e-7)
      << "true north in the grid";
  const Camera cam = lookAtCamera("n", c, c + glm::dvec3(0.0, 10.0, 0.0), 640, 480, 500.0);
  expectQuaternion(geoPoseQuaternion(cam, f), {0, 0, std::sin(-gamma / 2), std::cos(-gamma / 2)}, 1e-7);
}

TEST(GeodeticFrame, UtmOnTheEquatorLookingNorthAndDown) {
  // UTM 31N's (500000, 0) is lon 3° (its central meridian), lat 0.
  Diagnostics diag;
  const glm::dvec3 c(500000.0, 0.0, 100.0);
  const GeodeticFrame f = geodeticFrameAt("EPSG:32631", c, diag);
  EXPECT_NEAR(f.latDeg, 0.0, 1e-9);
  EXPECT_NEAR(f.lonDeg, 3.0, 1e-9);
  EXPECT_NEAR(f.heightM, 100.0, 1e-6);
  // North, 10° down: pitch −10° about the object's x (east).
  const Camera cam =
      lookAtCamera("d", c, c + glm::dvec3(0.0, std::cos(10 * kDeg), -std::sin(10 * kDeg)), 640, 480, 500.0);
  expectQuaternion(geoPoseQuaternion(cam, f), {std::sin(-5 * kDeg), 0, 0, std::cos(-5 * kDeg)}, 1e-7);
}

TEST(GeodeticFrame, RefusesASceneWithoutCrs) {
  Diagnostics diag;
  try {
    geodeticFrameAt("", glm::dvec3(0.0), diag);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no CRS"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hv
