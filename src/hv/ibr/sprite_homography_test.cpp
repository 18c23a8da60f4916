#include "hv/ibr/sprite_homography.h"

#include <gtest/gtest.h>

#include <random>

namespace hv::ibr {
namespace {

// A random camera near the origin of a render frame, looking roughly at the unit cube around it.
struct RandomCamera {
  glm::dmat3 M;
  glm::dvec3 C;
};

RandomCamera randomCamera(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Camera cam;
  cam.width = 640;
  cam.height = 480;
  cam.center = glm::dvec3(20.0 * u(rng), 20.0 * u(rng), 2.0 + 5.0 * u(rng));
  glm::dmat3 r;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) r[c][k] = u(rng);
  cam.camFromWorld = orthonormalize(r);
  if (glm::determinant(cam.camFromWorld) < 0.0) cam.camFromWorld[2] = -cam.camFromWorld[2];
  cam.focal = {300.0 + 400.0 * std::abs(u(rng)), 300.0 + 400.0 * std::abs(u(rng))};
  cam.principal = {320.0 + 30.0 * u(rng), 240.0 + 30.0 * u(rng)};
  cam.skew = u(rng);
  return {cam.pixFromWorld(), cam.center};
}

// The plane point under target pixel p, by intersecting the pixel's ray with the plane
// (independent of the homography): X = C + t d, d = M^-1 p, N.(X - P) = 0.
std::optional<glm::dvec3> rayPlane(const RandomCamera& view, const glm::dvec3& p, const glm::dvec3& P,
                                   const glm::dvec3& N) {
  const glm::dvec3 d = glm::inverse(view.M) * p;
  const double denom = glm::dot(N, d);
  if (std::abs(denom) < 1e-9) return std::nullopt;
  const double t = glm::dot(N, P - view.C) / denom;
  if (t <= 0.0) return std::nullopt;
  return view.C + t * d;
}

// Relative tolerance 1e-5 on pixels and depths (the brief's figure): the double computation is
// exact to ~1e-12, so this only allows for conditioning of grazing planes, which are skipped.
TEST(SpriteHomography, PlaneVectorFormEqualsTheExplicitHomography) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const RandomCamera view = randomCamera(rng), image = randomCamera(rng);
    const glm::dvec3 P(10.0 * u(rng), 10.0 * u(rng), 10.0 * u(rng));
    const glm::dvec3 N = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const glm::dvec3 p(640.0 * (0.5 + 0.5 * u(rng)), 480.0 * (0.5 + 0.5 * u(rng)), 1.0);
    const auto X = rayPlane(view, p, P, N);
    if (!X) continue;
    // Skip grazing configurations, where the plane is seen edge-on from either camera.
    const glm::dvec3 toX = glm::normalize(*X - view.C), toXi = glm::normalize(*X - image.C);
    if (std::abs(glm::dot(N, toX)) < 0.05 || std::abs(glm::dot(N, toXi)) < 0.05) continue;
    const glm::dvec3 q = image.M * (*X - image.C);  // explicit projection of the plane point
    if (q.z <= 1e-3) continue;

    const SpriteImage si = spriteImage(view.M, view.C, image.M, image.C);
    const glm::dvec3 nPrime = spritePlaneVector(view.M, view.C, P, N);
    ASSERT_GT(glm::dot(nPrime, p), 0.0);  // the ray meets the plane in front: N'.p > 0
    const glm::dvec3 pi = spriteProject(si, nPrime, p);
    const glm::dvec3 H = spriteHomography2016(view.M, view.C, image.M, image.C, P, N) * p;
    const double scale = std::max(1.0, glm::length(glm::dvec2(q) / q.z));
    // Pixel in image i: the 2022 form, the 2016 form, and the explicit projection.
    EXPECT_NEAR(pi.x / pi.z, q.x / q.z, 1e-5 * scale);
    EXPECT_NEAR(pi.y / pi.z, q.y / q.z, 1e-5 * scale);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(H[k], pi[k], 1e-9 * glm::length(pi));
    // Depth in image i: p_i.z / (N'.p) against ray-plane intersection then projection.
    EXPECT_NEAR(spriteDepth(pi, nPrime, p), q.z, 1e-5 * std::max(1.0, q.z));
    // Depth in the view itself: 1 / (N'.p).
    EXPECT_NEAR(1.0 / glm::dot(nPrime, p), (view.M * (*X - view.C)).z, 1e-5 * std::max(1.0, q.z));
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

TEST(SpriteHomography, TargetMatrixMapsIdealPixelsToTexels) {
  Camera cam = lookAtCamera("v", {0, -10, 2}, {0, 0, 2}, 320, 240, 300.0);
  PinholeFrustum fr;
  fr.pxMin = {-16.0, -8.0};
  fr.pxMax = {336.0, 248.0};
  const glm::dmat3 m = targetCameraMatrix(cam, fr, {704, 512});
  const glm::dvec3 X(1.0, 3.0, 2.5);
  const Projection pr = cam.project(X);
  const glm::dvec3 q = m * (X - cam.center);
  EXPECT_NEAR(q.x / q.z, (pr.pxIdeal.x + 16.0) * 2.0, 1e-9);
  EXPECT_NEAR(q.y / q.z, (pr.pxIdeal.y + 8.0) * 2.0, 1e-9);
  EXPECT_NEAR(q.z, pr.depth, 1e-12);
}

TEST(SpriteHomography, NormalFallsBackToTheFrontFacingGuess) {
  const glm::dvec3 C(0.0), P(0.0, 10.0, 0.0);
  EXPECT_EQ(spriteNormal(P, C, std::nullopt), glm::dvec3(0.0, -1.0, 0.0));
  EXPECT_EQ(spriteNormal(P, C, glm::dvec3(0.0, 0.0, 2.0)), glm::dvec3(0.0, -1.0, 0.0));  // edge-on
  const glm::dvec3 own = spriteNormal(P, C, glm::dvec3(0.0, 1.0, 1.0));
  EXPECT_NEAR(own.y, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(own.z, std::sqrt(0.5), 1e-12);
}

TEST(SpriteHomography, SpriteSizeBoundsTheProjectedDisk) {
  Camera cam = lookAtCamera("v", {0, -10, 0}, {0, 0, 0}, 320, 240, 300.0);
  const glm::dmat3 m = cam.pixFromWorld();
  // On the axis at depth 10, a disk of radius 0.1 spans 2 * 300 * 0.1 / 10 = 6 px; the bound
  // uses z - r for the nearest part of the sphere.
  EXPECT_NEAR(spriteSizePixels(m, cam.center, {0, 0, 0}, 0.1), 2.0 * 300.0 * 0.1 / 9.9, 1e-9);
  EXPECT_EQ(spriteSizePixels(m, cam.center, {0, -9.95, 0}, 0.1), 0.0);
  // Off axis, every point of the disk facing the camera projects within the sprite.
  const glm::dvec3 P(6.0, 0.0, 4.0);
  const double half = 0.5 * spriteSizePixels(m, cam.center, P, 0.3);
  const glm::dvec2 c = cam.project(P).pxIdeal;
  const glm::dvec3 n = glm::normalize(cam.center - P);
  const glm::dvec3 a = glm::normalize(glm::cross(n, glm::dvec3(0, 0, 1))), b = glm::cross(n, a);
  for (int k = 0; k < 64; ++k) {
    const double t = 2.0 * M_PI * k / 64.0;
    const glm::dvec2 q = cam.project(P + 0.3 * (std::cos(t) * a + std::sin(t) * b)).pxIdeal;
    EXPECT_LE(std::abs(q.x - c.x), half);
    EXPECT_LE(std::abs(q.y - c.y), half);
  }
}

}  // namespace
}  // namespace hv::ibr
