#include "hv/render/view_pick.h"

#include <cmath>

namespace hv::render {

std::optional<ViewDepthTexel> viewDepthTexel(const Camera& view, const PinholeFrustum& rect, glm::ivec2 depthSize,
                                             glm::dvec2 px) {
  if (!(px.x >= 0.0 && px.y >= 0.0 && px.x < view.width && px.y < view.height)) return std::nullopt;
  if (depthSize.x <= 0 || depthSize.y <= 0) return std::nullopt;
  const std::optional<glm::dvec2> ideal = view.undistort(px);
  if (!ideal) return std::nullopt;
  const glm::dvec2 extent = rect.pxMax - rect.pxMin;
  if (!(extent.x > 0.0 && extent.y > 0.0)) return std::nullopt;
  const glm::dvec2 t = (*ideal - rect.pxMin) / extent * glm::dvec2(depthSize);
  if (!(t.x >= 0.0 && t.y >= 0.0 && t.x < depthSize.x && t.y < depthSize.y)) return std::nullopt;
  ViewDepthTexel out;
  out.texel = glm::ivec2(int(std::floor(t.x)), int(std::floor(t.y)));
  out.pxIdeal = rect.pxMin + (glm::dvec2(out.texel) + 0.5) / glm::dvec2(depthSize) * extent;
  return out;
}

std::optional<glm::dvec3> worldFromViewDepth(const Camera& view, glm::dvec2 pxIdeal, double stored, double near,
                                             double far) {
  if (!(stored >= 0.0 && stored < 1.0) || !(far > near)) return std::nullopt;
  const double z = near + stored * (far - near);
  // K^-1 (u, v, 1) has a third component of 1 (K's last row is 0 0 1): z times it is the
  // camera-frame point at depth z.
  const glm::dvec3 cam = view.camFromPix() * glm::dvec3(pxIdeal, 1.0);
  return view.center + glm::transpose(view.camFromWorld) * (z / cam.z * cam);
}

}  // namespace hv::render
