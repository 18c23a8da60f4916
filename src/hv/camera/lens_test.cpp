// Lens models (hv::LensDistortion) against formulas written out independently here: OpenCV's
// documented distortion, iTowns' fish-eye shader as it runs (in its y-up texture frame), COLMAP's
// equidistant fish-eye; inverses, domains and scaling.
#include "hv/camera/camera.h"

#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv {
namespace {

using Model = LensDistortion::Model;

LensDistortion opencv() {
  LensDistortion d;
  d.center = {320.0, 240.0};
  d.scale = {500.0, 480.0};
  d.c3 = 0.1;
  d.c5 = -0.05;
  d.c7 = 0.01;
  d.p1 = 0.001;
  d.p2 = -0.002;
  return d;
}

LensDistortion fisheye() {
  LensDistortion d;
  d.model = Model::Fisheye;
  d.center = {1030.0, 1010.0};
  d.scale = {700.0, 700.0};
  d.c3 = -0.02;
  d.c5 = 0.003;
  d.c7 = -0.0001;
  d.l1 = 2e-4;
  d.l2 = -3e-4;
  return d;
}

TEST(LensDistortion, OpenCvMatchesItsDocumentedFormula) {
  const LensDistortion d = opencv();
  for (glm::dvec2 p : {glm::dvec2(400.0, 300.0), glm::dvec2(12.0, 460.0), glm::dvec2(630.0, 5.0)}) {
    const double x = (p.x - 320.0) / 500.0, y = (p.y - 240.0) / 480.0;
    const double r2 = x * x + y * y;
    const double radial = 1.0 + 0.1 * r2 - 0.05 * r2 * r2 + 0.01 * r2 * r2 * r2;
    const double xd = x * radial + 2.0 * 0.001 * x * y + -0.002 * (r2 + 2.0 * x * x);
    const double yd = y * radial + 0.001 * (r2 + 2.0 * y * y) + 2.0 * -0.002 * x * y;
    const glm::dvec2 pd = d.distort(p);
    EXPECT_NEAR(pd.x, 320.0 + 500.0 * xd, 1e-9);
    EXPECT_NEAR(pd.y, 240.0 + 480.0 * yd, 1e-9);
  }
}

// iTowns' projective_texturing shader, literally, in its texture frame (y up: pps.y and the point's
// y are flipped to H - y before, and back after).
glm::dvec2 itownsFisheye(glm::dvec2 pYDown, double height, glm::dvec2 ppsYDown, double etats, glm::dvec3 poly,
                         glm::dvec2 l1l2) {
  const glm::dvec2 p(pYDown.x, height - pYDown.y), pps(ppsYDown.x, height - ppsYDown.y);
  const glm::dvec2 AB = (p - pps) / etats;
  const double R = glm::length(AB);
  const double lambda = std::atan(R) / R;
  const glm::dvec2 ab = lambda * AB;
  const double rho2 = glm::dot(ab, ab);
  const double r357 = 1.0 + rho2 * (poly.x + rho2 * (poly.y + rho2 * poly.z));
  const glm::dvec2 out = pps + etats * (r357 * ab + glm::dvec2(glm::dot(l1l2, ab), l1l2.y * ab.x));
  return {out.x, height - out.y};
}

TEST(LensDistortion, FisheyeComputesWhatITownsComputes) {
  const LensDistortion d = fisheye();
  for (glm::dvec2 p : {glm::dvec2(1500.0, 700.0), glm::dvec2(100.0, 1900.0), glm::dvec2(1031.0, 1012.0),
                       glm::dvec2(-900.0, -400.0)}) {
    const glm::dvec2 expected =
        itownsFisheye(p, 2048.0, d.center, 700.0, {d.c3, d.c5, d.c7}, {d.l1, d.l2});
    const glm::dvec2 pd = d.distort(p);
    EXPECT_NEAR(pd.x, expected.x, 1e-9) << p.x << "," << p.y;
    EXPECT_NEAR(pd.y, expected.y, 1e-9) << p.x << "," << p.y;
  }
}

TEST(LensDistortion, FisheyeIsColmapsEquidistantModel) {
  // COLMAP OPENCV_FISHEYE: theta = atan(r), theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6),
  // u_d = u theta_d / r.
  LensDistortion d;
  d.model = Model::Fisheye;
  d.center = {640.0, 360.0};
  d.scale = {400.0, 410.0};
  d.c3 = 0.05;
  d.c5 = -0.01;
  d.c7 = 0.002;
  const glm::dvec2 p(1100.0, 60.0);
  const glm::dvec2 u((p.x - 640.0) / 400.0, (p.y - 360.0) / 410.0);
  const double r = glm::length(u), t = std::atan(r), t2 = t * t;
  const double td = t * (1.0 + 0.05 * t2 - 0.01 * t2 * t2 + 0.002 * t2 * t2 * t2);
  const glm::dvec2 pd = d.distort(p);
  EXPECT_NEAR(pd.x, 640.0 + 400.0 * u.x * td / r, 1e-9);
  EXPECT_NEAR(pd.y, 360.0 + 410.0 * u.y * td / r, 1e-9);
}

TEST(LensDistortion, UndistortInvertsEveryModel) {
  LensDistortion radial;
  radial.center = {320.0, 240.0};
  radial.c3 = -2e-7;
  radial.c5 = 1e-13;
  for (const LensDistortion& d : {opencv(), fisheye(), radial}) {
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j) {
        // A grid over +-0.8 normalised units (about 39 degrees) around the centre.
        const glm::dvec2 x(-0.8 + 0.16 * i, -0.8 + 0.16 * j);
        const glm::dvec2 p = d.center + x * (d.scale.x == 1.0 ? glm::dvec2(400.0) : d.scale);
        const auto back = d.undistort(d.distort(p));
        ASSERT_TRUE(back.has_value()) << int(d.model) << " " << p.x << "," << p.y;
        EXPECT_NEAR(back->x, p.x, 1e-6);
        EXPECT_NEAR(back->y, p.y, 1e-6);
      }
  }
}

TEST(LensDistortion, ScalingPixelsScalesTheMapping) {
  for (const LensDistortion& d : {opencv(), fisheye()}) {
    const LensDistortion half = d.scaled(0.5);
    for (glm::dvec2 p : {glm::dvec2(400.0, 300.0), glm::dvec2(20.0, 900.0)}) {
      const glm::dvec2 a = half.distort(0.5 * p), b = 0.5 * d.distort(p);
      EXPECT_NEAR(a.x, b.x, 1e-9);
      EXPECT_NEAR(a.y, b.y, 1e-9);
    }
  }
}

TEST(LensDistortion, FitDomainStopsAtTheTurningPoint) {
  // Pixel polynomial, barrel: d/dr [r (1 + c3 r^2)] = 1 + 3 c3 r^2 = 0 at r = 1 / sqrt(3 |c3|).
  LensDistortion d;
  d.center = {320.0, 240.0};
  d.c3 = -1e-6;
  EXPECT_FALSE(d.fitDomain().empty());
  const double turn = 1.0 / std::sqrt(3e-6);
  EXPECT_NEAR(std::sqrt(d.r2max), 0.999 * turn, 1e-6 * turn);
  // Two roots: 1 + 3 c3 s + 5 c5 s^2 with s = r^2, c3 = -1e-6, c5 = 1e-13: the smaller one.
  LensDistortion e;
  e.c3 = -1e-6;
  e.c5 = 1e-13;
  e.fitDomain();
  const double a = 5e-13, b = -3e-6, s = (-b - std::sqrt(b * b - 4 * a)) / (2 * a);
  EXPECT_NEAR(std::sqrt(e.r2max), 0.999 * std::sqrt(s), 1e-3);
  // Pincushion: increasing everywhere, the domain is left alone.
  LensDistortion f;
  f.c3 = 1e-6;
  f.c5 = 1e-12;
  f.r2max = 1000.0 * 1000.0;
  EXPECT_TRUE(f.fitDomain().empty());
  EXPECT_EQ(f.r2max, 1e6);
}

TEST(LensDistortion, FisheyeDomainIsClippedToWhatAPinholeCovers) {
  LensDistortion d;
  d.model = Model::Fisheye;
  d.scale = {500.0, 500.0};
  const std::string msg = d.fitDomain();
  EXPECT_NE(msg.find("clipped"), std::string::npos) << msg;
  EXPECT_NEAR(std::atan(std::sqrt(d.r2max)), kFisheyeMaxAngleDeg * M_PI / 180.0, 1e-9);
  // A profile theta (1 - 0.5 theta^2) turns at theta = sqrt(2/3), before 75 degrees.
  LensDistortion e = d;
  e.r2max = 1e30;
  e.c3 = -0.5;
  e.fitDomain();
  EXPECT_NEAR(std::atan(std::sqrt(e.r2max)), 0.999 * std::sqrt(2.0 / 3.0), 1e-9);
}

TEST(LensDistortion, FitLensDomainWarnsOnlyWhenThePhotographIsCut) {
  Camera c;
  c.id = "c";
  c.width = 640;
  c.height = 480;
  c.focal = {500.0, 500.0};
  c.principal = {320.0, 240.0};
  LensDistortion d;
  d.center = c.principal;
  d.c3 = -1e-7;  // turns at r = 1826 px, beyond the corners (400 px)
  c.distortion = d;
  Diagnostics quiet;
  fitLensDomain(c, "cams.json", quiet);
  EXPECT_TRUE(quiet.warnings.empty());
  d.c3 = -4e-6;  // turns at r = 289 px, inside the image
  c.distortion = d;
  Diagnostics diag;
  fitLensDomain(c, "cams.json", diag);
  ASSERT_EQ(diag.warnings.size(), 1u);
  EXPECT_NE(diag.warnings[0].find("cams.json: camera 'c': distortion"), std::string::npos) << diag.warnings[0];
}

}  // namespace
}  // namespace hv
