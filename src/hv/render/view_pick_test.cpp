// Picking from the view depth (render/view_pick.h) against values worked out by hand and against
// the camera's own projection.
#include "hv/render/view_pick.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::render {
namespace {

// Identity rotation (looking along +z, y down), centre (1, 2, 3), f = 100, principal (50, 50).
Camera simpleCamera() {
  Camera c;
  c.width = 100;
  c.height = 100;
  c.center = {1.0, 2.0, 3.0};
  c.focal = {100.0, 100.0};
  c.principal = {50.0, 50.0};
  return c;
}

TEST(ViewPick, TexelOfAPixelAndItsCentre) {
  Camera c = simpleCamera();
  c.width = 640;
  c.height = 480;
  PinholeFrustum rect;
  rect.pxMin = {0.0, 0.0};
  rect.pxMax = {640.0, 480.0};
  // A target of half the view's size: texel = floor(px / 2), its centre at 2 (texel + 0.5).
  const auto t = viewDepthTexel(c, rect, {320, 240}, {101.3, 50.7});
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->texel, glm::ivec2(50, 25));
  EXPECT_DOUBLE_EQ(t->pxIdeal.x, 101.0);
  EXPECT_DOUBLE_EQ(t->pxIdeal.y, 51.0);
  // A rectangle wider than the view (a distorted view's): offsets by pxMin.
  rect.pxMin = {-64.0, -48.0};
  rect.pxMax = {704.0, 528.0};
  const auto u = viewDepthTexel(c, rect, {768, 576}, {0.2, 479.9});
  ASSERT_TRUE(u.has_value());
  EXPECT_EQ(u->texel, glm::ivec2(64, 527));
  EXPECT_DOUBLE_EQ(u->pxIdeal.x, 0.5);
  EXPECT_DOUBLE_EQ(u->pxIdeal.y, 479.5);
}

TEST(ViewPick, OutsideTheViewIsNothing) {
  const Camera c = simpleCamera();
  PinholeFrustum rect;
  rect.pxMax = {100.0, 100.0};
  EXPECT_FALSE(viewDepthTexel(c, rect, {100, 100}, {-0.1, 10.0}));
  EXPECT_FALSE(viewDepthTexel(c, rect, {100, 100}, {10.0, 100.0}));
  EXPECT_FALSE(viewDepthTexel(c, rect, {0, 100}, {10.0, 10.0}));
}

TEST(ViewPick, DistortedPixelFindsTheTexelOfItsIdealPixel) {
  Camera c = simpleCamera();
  LensDistortion d;
  d.center = {50.0, 50.0};
  d.c3 = 2e-5;  // pixels^-2: 5 % at the corners
  c.distortion = d;
  const PinholeFrustum rect = idealRectCoveringImage(c);
  const glm::ivec2 size(200, 200);
  const glm::dvec2 px(90.0, 12.0);
  const auto t = viewDepthTexel(c, rect, size, px);
  ASSERT_TRUE(t.has_value());
  // The texel's centre is within half a texel of the pixel's ideal position, and distorts back to
  // within a texel of the pixel.
  const glm::dvec2 texelPx = (rect.pxMax - rect.pxMin) / glm::dvec2(size);
  const glm::dvec2 ideal = *c.undistort(px);
  EXPECT_LE(std::abs(t->pxIdeal.x - ideal.x), 0.5 * texelPx.x + 1e-9);
  EXPECT_LE(std::abs(t->pxIdeal.y - ideal.y), 0.5 * texelPx.y + 1e-9);
  EXPECT_GT(glm::length(ideal - px), 1.0);  // the test means something: the distortion moves it
}

TEST(ViewPick, WorldPointByHand) {
  const Camera c = simpleCamera();
  // Pixel (150, 50), z = 2: camera point (2 (150 - 50) / 100, 0, 2) = (2, 0, 2), world (3, 2, 5).
  // Stored between near 1 and far 5: (2 - 1) / 4.
  const auto p = worldFromViewDepth(c, {150.0, 50.0}, 0.25, 1.0, 5.0);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->x, 3.0, 1e-12);
  EXPECT_NEAR(p->y, 2.0, 1e-12);
  EXPECT_NEAR(p->z, 5.0, 1e-12);
}

TEST(ViewPick, WorldPointProjectsBackToItsPixelAndDepth) {
  const Camera c = lookAtCamera("v", {652000.0, 6862000.0, 60.0}, {652100.0, 6862040.0, 35.0}, 800, 600, 700.0);
  const glm::dvec3 world(652080.0, 6862020.0, 31.0);
  const Projection pr = c.project(world);
  ASSERT_TRUE(pr.inFront);
  const double near = 0.5, far = 900.0;
  const auto p = worldFromViewDepth(c, pr.pxIdeal, (pr.depth - near) / (far - near), near, far);
  ASSERT_TRUE(p.has_value());
  EXPECT_LT(glm::distance(*p, world), 1e-6);  // metres; the CRS's 10^6 costs the last digits
}

TEST(ViewPick, ClearedOrInvalidDepthIsNothing) {
  const Camera c = simpleCamera();
  EXPECT_FALSE(worldFromViewDepth(c, {50.0, 50.0}, 1.0, 1.0, 5.0));
  EXPECT_FALSE(worldFromViewDepth(c, {50.0, 50.0}, -0.1, 1.0, 5.0));
  EXPECT_FALSE(worldFromViewDepth(c, {50.0, 50.0}, std::nan(""), 1.0, 5.0));
  EXPECT_FALSE(worldFromViewDepth(c, {50.0, 50.0}, 0.5, 5.0, 5.0));
}

}  // namespace
}  // namespace hv::render
