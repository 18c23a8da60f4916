// Projective texturing of point sprites through per-point plane homographies (docs/design.md, step 6;
// Devaux & Brédif 2016 §3, de Castro & Brédif 2022 §2.3). Plain C++: the GLSL twins are in
// shaders/points.vert and shaders/points.frag, tested against these by src/hv/render/points_gltest.cpp.
//
// Conventions (owned here):
// - A "target" camera matrix M maps a world direction to homogeneous pixels of a render target:
//   p = M (X - C). For the view or a depth map it is targetFromPix * K * R, so that p = (x, y, 1)
//   is gl_FragCoord.xy of that target directly (offscreen targets are stored top row first,
//   docs/conventions.md), and no y flip is needed.
// - For a point P with normal N, its tangent plane {X : N.(X - P) = 0} induces, for each image i
//   (M_i, C_i), the homography from the target pixel p to image i:
//     2016 form:  H_i = (M_i + E_i N^T / (N^T (P - C))) M^-1
//     2022 form:  N' = M^-T N / (N^T (P - C)),  p_i = H'_i p + (N'.p) E_i,
//                 H'_i = M_i M^-1,  E_i = M_i (C - C_i)
//   so that p_i = H_i p = M_i (X - C_i) * (N'.p) where X is the plane point under p: the depth of X
//   in image i is p_i.z / (N'.p), and its depth in the target camera is 1 / (N'.p) (docs/design.md, step 6).
// - A fragment whose N'.p <= 0 sees the plane's back side (or misses it): rejected.
#pragma once

#include "hv/camera/camera.h"
#include "hv/ibr/frame_plan.h"

#include <glm/glm.hpp>

#include <optional>

namespace hv::ibr {

// The per-frame, per-image data of the 2022 form.
struct SpriteImage {
  glm::dmat3 hPrime{1.0};  // H'_i = M_i M^-1
  glm::dvec3 e{0.0};       // E_i = M_i (C - C_i)
};
SpriteImage spriteImage(const glm::dmat3& targetM, const glm::dvec3& targetC, const glm::dmat3& imageM,
                        const glm::dvec3& imageC);

// Maps ideal pixels of a pinhole frustum's rectangle to pixels of a target of `size` texels:
// p_t = (p - pxMin) * size / (pxMax - pxMin).
glm::dmat3 targetFromPix(const PinholeFrustum& frustum, glm::ivec2 size);
// targetFromPix * K * R for a camera drawn into that target.
glm::dmat3 targetCameraMatrix(const Camera& camera, const PinholeFrustum& frustum, glm::ivec2 size);

// Below this |cos| between the normal and the viewing ray, a point's own normal is replaced by the
// front-facing guess: a plane seen edge-on has an unbounded homography over the sprite.
inline constexpr double kGrazingCos = 0.02;

// The normal used for a point at P seen from C: its own (when given, non-zero and not grazing),
// else the front-facing guess C - P (the plane through P perpendicular to the viewing ray).
glm::dvec3 spriteNormal(const glm::dvec3& P, const glm::dvec3& C, const std::optional<glm::dvec3>& own);

// N' = M^-T N / (N^T (P - C)) (2022 form). Degenerate (N^T (P - C) = 0): zero vector.
glm::dvec3 spritePlaneVector(const glm::dmat3& targetM, const glm::dvec3& targetC, const glm::dvec3& P,
                             const glm::dvec3& N);

// p_i = H'_i p + (N'.p) E_i for a homogeneous target pixel p.
glm::dvec3 spriteProject(const SpriteImage& image, const glm::dvec3& nPrime, const glm::dvec3& p);
// Depth in image i of the plane point under p: p_i.z / (N'.p). Only meaningful when N'.p > 0.
double spriteDepth(const glm::dvec3& pImage, const glm::dvec3& nPrime, const glm::dvec3& p);

// The 2016 form: a full 3x3 per point and image.
glm::dmat3 spriteHomography2016(const glm::dmat3& targetM, const glm::dvec3& targetC, const glm::dmat3& imageM,
                                const glm::dvec3& imageC, const glm::dvec3& P, const glm::dvec3& N);

// Sprite side in target pixels for a disk of world radius r at P: 2 r sigma / (z - r), with z the
// depth along the axis and sigma the largest singular value of the pixel's Jacobian (times z);
// 0 when the disk's bounding sphere reaches behind the camera. Twin of hv_spriteSize (points.vert).
double spriteSizePixels(const glm::dmat3& targetM, const glm::dvec3& targetC, const glm::dvec3& P, double radius);

}  // namespace hv::ibr
