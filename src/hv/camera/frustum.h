// Pinhole frusta of cameras (depth maps, the view's geometry pass, culling): the ideal pixel
// rectangle that covers a distorted image, the depth range from bounds, the clip matrix, and the
// exact overlap test of two truncated frusta. Plain camera maths, no GL.
#pragma once

#include "hv/camera/camera.h"
#include "hv/math/aabb.h"

#include <glm/glm.hpp>

#include <array>

namespace hv {

// The pinhole frustum a depth map (or the view's geometry pass) is rendered with: the ideal
// (undistorted) pixel rectangle that covers the whole distorted image, and the depth range.
struct PinholeFrustum {
  glm::dvec2 pxMin{0.0}, pxMax{0.0};  // ideal pixels
  double near = 0.01, far = 1000.0;   // along the camera axis, scene units
};

// Covers the distorted image domain [0,W]x[0,H]: the bounding box of the undistorted image border
// (sampled every few pixels), widened by `marginPx`. Without distortion: [0,W]x[0,H] (+ margin).
PinholeFrustum idealRectCoveringImage(const Camera& camera, double marginPx = 0.0);
// Near/far from the scene bounds (corners' depths); near is kept above far * nearRatio.
void setDepthRange(PinholeFrustum& frustum, const Camera& camera, const Aabb& sceneBounds, double nearRatio = 1e-5);

// Column-major 4x4 clip-from-render matrix for that frustum, for a camera in the render frame
// (camera centre minus origin). NDC y = -1 is the *top* of the image (pxMin.y): offscreen targets
// are stored top row first, so texture row 0 is the image's top row and gl_FragCoord.xy is the
// pixel position in the top-left convention (see docs/conventions.md).
glm::dmat4 clipFromRender(const Camera& camera, const PinholeFrustum& frustum, const glm::dvec3& origin);

// A pinhole frustum truncated at near and far, as its 8 corners (world): near face then far face,
// each in the order (pxMin.x, pxMin.y), (pxMax.x, pxMin.y), (pxMax.x, pxMax.y), (pxMin.x, pxMax.y).
using FrustumCorners = std::array<glm::dvec3, 8>;
FrustumCorners frustumCorners(const Camera& camera, const PinholeFrustum& frustum);
// The frustum a camera sees the scene with: its ideal rectangle covering the image, truncated at
// the depth range of `bounds`.
FrustumCorners sceneFrustum(const Camera& camera, const Aabb& bounds);
// Exact overlap test of two truncated frusta (convex polyhedra) by the separating axis theorem:
// face normals of both and cross products of their edge directions.
bool frustaOverlap(const FrustumCorners& a, const FrustumCorners& b);

}  // namespace hv
