#include "hv/ibr/sprite_homography.h"

#include <algorithm>
#include <cmath>

namespace hv::ibr {

SpriteImage spriteImage(const glm::dmat3& targetM, const glm::dvec3& targetC, const glm::dmat3& imageM,
                        const glm::dvec3& imageC) {
  // 2022 §2.3: the part of the homography that does not depend on the point.
  return {imageM * glm::inverse(targetM), imageM * (targetC - imageC)};
}

glm::dmat3 targetFromPix(const PinholeFrustum& frustum, glm::ivec2 size) {
  const glm::dvec2 s = glm::dvec2(size) / (frustum.pxMax - frustum.pxMin);
  glm::dmat3 m(1.0);
  m[0][0] = s.x;
  m[1][1] = s.y;
  m[2][0] = -frustum.pxMin.x * s.x;
  m[2][1] = -frustum.pxMin.y * s.y;
  return m;
}

glm::dmat3 targetCameraMatrix(const Camera& camera, const PinholeFrustum& frustum, glm::ivec2 size) {
  return targetFromPix(frustum, size) * camera.pixFromWorld();
}

glm::dvec3 spriteNormal(const glm::dvec3& P, const glm::dvec3& C, const std::optional<glm::dvec3>& own) {
  const glm::dvec3 toView = C - P;
  const double dist = glm::length(toView);
  if (own) {
    const double len = glm::length(*own);
    if (len > 0.0 && dist > 0.0 && std::abs(glm::dot(*own, toView)) >= kGrazingCos * len * dist) return *own / len;
  }
  return dist > 0.0 ? toView / dist : glm::dvec3(0.0, 0.0, 1.0);
}

glm::dvec3 spritePlaneVector(const glm::dmat3& targetM, const glm::dvec3& targetC, const glm::dvec3& P,
                             const glm::dvec3& N) {
  const double d = glm::dot(N, P - targetC);
  if (d == 0.0) return glm::dvec3(0.0);
  return glm::transpose(glm::inverse(targetM)) * N / d;
}

glm::dvec3 spriteProject(const SpriteImage& image, const glm::dvec3& nPrime, const glm::dvec3& p) {
  return image.hPrime * p + glm::dot(nPrime, p) * image.e;
}

double spriteDepth(const glm::dvec3& pImage, const glm::dvec3& nPrime, const glm::dvec3& p) {
  return pImage.z / glm::dot(nPrime, p);
}

glm::dmat3 spriteHomography2016(const glm::dmat3& targetM, const glm::dvec3& targetC, const glm::dmat3& imageM,
                                const glm::dvec3& imageC, const glm::dvec3& P, const glm::dvec3& N) {
  // Devaux & Brédif 2016 §3: H_i = (M_i + E_i N^T / (N^T (P - C))) M^-1; glm's outerProduct(a, b) = a b^T.
  const glm::dvec3 e = imageM * (targetC - imageC);
  return (imageM + glm::outerProduct(e, N) / glm::dot(N, P - targetC)) * glm::inverse(targetM);
}

double spriteSizePixels(const glm::dmat3& targetM, const glm::dvec3& targetC, const glm::dvec3& P, double radius) {
  const glm::dvec3 q = targetM * (P - targetC);
  const double z = q.z;  // K's last row is (0, 0, 1): q.z is the depth along the axis
  if (z - radius <= 0.0) return 0.0;
  // The Jacobian of the pixel w.r.t. a displacement of P is J / z with the rows of J the rows of M
  // minus p times its third row; its largest singular value (the root of the largest eigenvalue
  // of J J^T, 2x2) bounds how far a displacement of length r moves the pixel.
  const glm::dvec2 p(q.x / z, q.y / z);
  const glm::dvec3 m1(targetM[0][0], targetM[1][0], targetM[2][0]), m2(targetM[0][1], targetM[1][1], targetM[2][1]),
      m3(targetM[0][2], targetM[1][2], targetM[2][2]);
  const glm::dvec3 j1 = m1 - p.x * m3, j2 = m2 - p.y * m3;
  const double a = glm::dot(j1, j1), b = glm::dot(j1, j2), c = glm::dot(j2, j2);
  const double lambda = 0.5 * (a + c) + std::sqrt(0.25 * (a - c) * (a - c) + b * b);
  return 2.0 * radius * std::sqrt(lambda) / (z - radius);
}

}  // namespace hv::ibr
