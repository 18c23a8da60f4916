#include "hv/layers/sub_image.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::layers {
namespace {

// World coordinates of a projected CRS (millions of metres), the render origin near the camera.
const glm::dvec3 kOrigin(651000.0, 6862000.0, 40.0);

Camera makeCamera() {
  Camera cam = lookAtCamera("photo", kOrigin + glm::dvec3(3.0, -40.0, 5.0), kOrigin + glm::dvec3(10.0, 20.0, 8.0), 640,
                            480, 520.0);
  cam.focal = {520.0, 540.0};
  cam.principal = {331.5, 228.25};  // off-centre: the whole frustum is already sheared
  cam.skew = 0.8;
  return cam;
}

// Points in front of the camera whose photograph pixels fall inside the window.
std::vector<glm::dvec3> pointsInWindow(const Camera& cam, const SubImageWindow& w) {
  std::vector<glm::dvec3> pts;
  for (int i = 0; i <= 6; ++i)
    for (int j = 0; j <= 6; ++j) {
      const glm::dvec2 pd = w.pxMin + glm::dvec2(i / 6.0, j / 6.0) * w.size();
      const auto ideal = cam.undistort(pd);
      if (!ideal) continue;
      const double depth = 7.0 + 9.0 * ((i * 7 + j) % 5);
      pts.push_back(cam.center + depth * cam.rayDirection(*ideal));
    }
  return pts;
}

// The photograph pixel through the sub-image texture, compared with the whole photograph's
// (Camera::project: K R (P - C), then the lens model; independent of the clip matrices).
void expectSamePixels(const Camera& cam, const SubImageWindow& w) {
  const PinholeFrustum f = subImageFrustum(cam, w, 0.5, 500.0);
  const glm::dmat4 clip = clipFromRender(cam, f, kOrigin);
  const auto pts = pointsInWindow(cam, w);
  ASSERT_GT(pts.size(), 40u);
  for (const glm::dvec3& p : pts) {
    const Projection whole = cam.project(p);
    ASSERT_TRUE(whole.inFront);
    const auto uv = subImageUv(cam, f, w, clip, p - kOrigin);
    ASSERT_TRUE(uv.has_value());
    const glm::dvec2 px = w.pxMin + *uv * w.size();
    // 1e-6 px: the chain is a handful of double operations on pixel-sized numbers.
    EXPECT_NEAR(px.x, whole.pxDistorted.x, 1e-6);
    EXPECT_NEAR(px.y, whole.pxDistorted.y, 1e-6);
    // The sheared frustum holds the point: its texture covers what the window shows.
    const glm::dvec4 c = clip * glm::dvec4(p - kOrigin, 1.0);
    EXPECT_LE(std::abs(c.x / c.w), 1.0 + 1e-9);
    EXPECT_LE(std::abs(c.y / c.w), 1.0 + 1e-9);
  }
}

TEST(SubImageFrustum, PinholeWindowIsTheFrustum) {
  const Camera cam = makeCamera();
  const SubImageWindow w{{123.25, 77.5}, {300.0, 260.0}};
  const PinholeFrustum f = subImageFrustum(cam, w, 0.5, 500.0);
  EXPECT_EQ(f.pxMin, w.pxMin);
  EXPECT_EQ(f.pxMax, w.pxMax);
  expectSamePixels(cam, w);
  // The window's top-left corner is NDC (-1, -1), its bottom-right (1, 1).
  const glm::dmat4 clip = clipFromRender(cam, f, kOrigin);
  for (const auto& [px, ndc] : {std::pair{w.pxMin, glm::dvec2(-1.0)}, std::pair{w.pxMax, glm::dvec2(1.0)}}) {
    const glm::dvec4 c = clip * glm::dvec4(cam.center + 12.0 * cam.rayDirection(px) - kOrigin, 1.0);
    EXPECT_NEAR(c.x / c.w, ndc.x, 1e-9);
    EXPECT_NEAR(c.y / c.w, ndc.y, 1e-9);
  }
}

TEST(SubImageFrustum, MatchesThePapersGlFrustum) {
  Camera cam = makeCamera();
  cam.skew = 0.0;  // glFrustum has no skew
  const FrustumBounds whole{-cam.principal.x / cam.focal.x, (cam.width - cam.principal.x) / cam.focal.x,
                            -cam.principal.y / cam.focal.y, (cam.height - cam.principal.y) / cam.focal.y};
  const SubImageWindow w{{64.0, 200.0}, {192.0, 456.0}};
  const FrustumBounds s = shearedFrustumBounds(whole, cam.width, cam.height, w);
  const PinholeFrustum f = subImageFrustum(cam, w, 1.0, 100.0);
  EXPECT_NEAR((f.pxMin.x - cam.principal.x) / cam.focal.x, s.xmin, 1e-12);
  EXPECT_NEAR((f.pxMax.x - cam.principal.x) / cam.focal.x, s.xmax, 1e-12);
  EXPECT_NEAR((f.pxMin.y - cam.principal.y) / cam.focal.y, s.ymin, 1e-12);
  EXPECT_NEAR((f.pxMax.y - cam.principal.y) / cam.focal.y, s.ymax, 1e-12);
}

TEST(SubImageFrustum, RadialDistortion) {
  Camera cam = makeCamera();
  LensDistortion d;
  d.center = {325.0, 236.0};
  d.c3 = -2.5e-7;  // barrel: -4 % at 400 px from the centre
  d.c5 = 1e-13;
  cam.distortion = d;
  expectSamePixels(cam, {{10.0, 12.0}, {250.0, 190.0}});  // a corner, where distortion is strongest
  expectSamePixels(cam, {{300.0, 200.0}, {380.5, 300.0}});
}

TEST(SubImageFrustum, Fisheye) {
  Camera cam = makeCamera();
  LensDistortion d;
  d.model = LensDistortion::Model::Fisheye;
  d.center = cam.principal;
  d.scale = cam.focal;
  cam.distortion = d;
  expectSamePixels(cam, {{20.0, 30.0}, {200.0, 170.0}});
}

}  // namespace
}  // namespace hv::layers
