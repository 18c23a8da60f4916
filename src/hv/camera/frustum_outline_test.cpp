#include "hv/camera/frustum_outline.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv {
namespace {

// At (10, 20, 30) looking along world +y: camera x = world +x, camera y (down) = world -z.
Camera lookingNorth() {
  Camera c;
  c.id = "north";
  c.width = 640;
  c.height = 480;
  c.center = {10.0, 20.0, 30.0};
  const double r[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
  c.camFromWorld = mat3FromRowMajor(r);
  c.focal = {500.0, 400.0};
  c.principal = {320.0, 240.0};
  return c;
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(FrustumOutline, PinholeCornersAgainstHandValues) {
  const Camera c = lookingNorth();
  const FrustumOutline f = frustumOutline(c, 2.0, 1);
  ASSERT_EQ(f.border.size(), 4u);
  expectNear(f.apex, c.center, 0.0);
  // Corner (0, 0): camera direction ((0 - 320) / 500, (0 - 240) / 400, 1) = (-0.64, -0.6, 1), i.e.
  // world (-0.64, 1, 0.6); times the depth 2 from the centre.
  expectNear(f.border[size_t(f.corners[0])], {8.72, 22.0, 31.2}, 1e-12);
  expectNear(f.border[size_t(f.corners[1])], {11.28, 22.0, 31.2}, 1e-12);  // (W, 0): (+0.64, -0.6)
  expectNear(f.border[size_t(f.corners[2])], {11.28, 22.0, 28.8}, 1e-12);  // (W, H): (+0.64, +0.6)
  expectNear(f.border[size_t(f.corners[3])], {8.72, 22.0, 28.8}, 1e-12);   // (0, H): (-0.64, +0.6)

  // Lines: 4 border segments closing the loop, then 4 edges from the apex.
  const std::vector<glm::dvec3> lines = frustumLineSegments(f);
  ASSERT_EQ(lines.size(), 16u);
  expectNear(lines[6], f.border[3], 0.0);
  expectNear(lines[7], f.border[0], 0.0);
  for (int e = 0; e < 4; ++e) {
    expectNear(lines[size_t(8 + 2 * e)], c.center, 0.0);
    expectNear(lines[size_t(9 + 2 * e)], f.border[size_t(f.corners[size_t(e)])], 0.0);
  }
}

TEST(FrustumOutline, DistortedBorderProjectsBackOntoTheImageBorder) {
  Camera c = lookingNorth();
  LensDistortion d;
  d.center = {330.0, 235.0};
  d.c3 = -5e-7;  // barrel: the image border is a pincushion in ideal pixels, the outline curved
  c.distortion = d;
  const FrustumOutline f = frustumOutline(c, 3.0, 8);
  ASSERT_EQ(f.border.size(), 32u);
  for (size_t i = 0; i < f.border.size(); ++i) {
    const Projection p = c.project(f.border[i]);
    EXPECT_NEAR(p.depth, 3.0, 1e-9);
    // On one of the four sides of the (distorted) image, the side it was sampled on.
    const int side = int(i) / 8;
    const double along = side == 0 ? p.pxDistorted.y : side == 1 ? p.pxDistorted.x - 640.0
                                   : side == 2 ? p.pxDistorted.y - 480.0 : p.pxDistorted.x;
    EXPECT_NEAR(along, 0.0, 1e-6) << "border point " << i;
  }
  // Not a rectangle: the corners are pushed out more than the middle of a side (ideal y about -19
  // at the top corners, -6.5 at the top side's middle: 0.09 apart at depth 3 with fy = 400).
  const glm::dvec3 mid = f.border[4];
  EXPECT_LT(mid.z, f.border[0].z - 0.05);
}

TEST(FrustumOutline, PointsOutsideTheLensDomainFollowItsEdge) {
  Camera c = lookingNorth();
  LensDistortion d;
  d.center = c.principal;
  d.c3 = -1e-7;
  d.r2max = 250.0 * 250.0;  // a disc of 250 px: the corners (400 px away) are outside
  c.distortion = d;
  const FrustumOutline f = frustumOutline(c, 1.0, 4);
  for (int k = 0; k < 4; ++k) {
    const Projection p = c.project(f.border[size_t(f.corners[size_t(k)])]);
    const glm::dvec2 x = p.pxIdeal - d.center;
    // On the domain's edge (bisection to well below a pixel), on the segment to the image corner.
    EXPECT_NEAR(glm::length(x), 250.0, 1e-3);
    const glm::dvec2 cornerDir = glm::normalize(glm::dvec2(k == 1 || k == 2 ? 320.0 : -320.0, k >= 2 ? 240.0 : -240.0));
    EXPECT_NEAR(glm::dot(glm::normalize(p.pxDistorted - c.principal), cornerDir), 1.0, 1e-9);
  }
  // A side's midpoint (distorted radius 240 or 320 before the domain test) is treated alike: the
  // top midpoint is 240 px from the centre, inside; the left one 320 px, pulled in to the edge.
  EXPECT_NEAR(c.project(f.border[2]).pxDistorted.y, 0.0, 1e-6);
  EXPECT_NEAR(glm::length(c.project(f.border[14]).pxIdeal - d.center), 250.0, 1e-3);
}

}  // namespace
}  // namespace hv
