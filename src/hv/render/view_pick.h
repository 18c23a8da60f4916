// Picking the scene point under a pixel of the view from the renderer's own view-depth pass, for
// builds without a ray caster (the browser, docs/web.md; the native viewer without Embree). The
// view-depth target (render/gl/depth_pass.cpp) covers the view's ideal pinhole rectangle
// (Frame::rect: PinholeFrustum::pxMin..pxMax, `depthSize` texels, row 0 at the top, docs/conventions.md)
// and stores the *linear* depth along the camera axis mapped to [0, 1] between near and far
// (shaders/depth.frag); 1 is the cleared value: nothing drawn there.
#pragma once

#include "hv/camera/camera.h"
#include "hv/camera/frustum.h"

#include <glm/glm.hpp>

#include <optional>

namespace hv::render {

// The texel of the view-depth target under view pixel `px` (pixels of `view`, distorted when it
// has distortion; top-left-corner origin) and the ideal pixel at that texel's centre, the one
// whose depth the texel holds. None outside the view, outside the rectangle, or where the
// distortion cannot be inverted.
struct ViewDepthTexel {
  glm::ivec2 texel{0};
  glm::dvec2 pxIdeal{0.0};
};
std::optional<ViewDepthTexel> viewDepthTexel(const Camera& view, const PinholeFrustum& rect, glm::ivec2 depthSize,
                                             glm::dvec2 px);

// The world point seen at ideal pixel `pxIdeal` of `view` at the stored depth `stored` (the
// target's value: (z - near) / (far - near), z along the camera axis): C + z R^T K^-1 (u, v, 1).
// None for the cleared value (stored >= 1: the sky) or a value that is not a depth (< 0, NaN).
std::optional<glm::dvec3> worldFromViewDepth(const Camera& view, glm::dvec2 pxIdeal, double stored, double near,
                                             double far);

}  // namespace hv::render
