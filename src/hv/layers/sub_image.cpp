#include "hv/layers/sub_image.h"

#include <algorithm>
#include <limits>

namespace hv::layers {

PinholeFrustum subImageFrustum(const Camera& camera, const SubImageWindow& window, double near, double far) {
  PinholeFrustum f;
  f.near = near;
  f.far = far;
  f.pxMin = window.pxMin;
  f.pxMax = window.pxMax;
  if (!camera.distortion || camera.distortion->isIdentity()) return f;
  // The box of the undistorted border: the distortion models are monotonic along rays from their
  // centre within their domain, so the border's image bounds the window's.
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  const glm::dvec2 size = window.size();
  const int steps = std::clamp(int(std::max(size.x, size.y) / 4.0), 16, 1024);
  auto visit = [&](glm::dvec2 pd) {
    if (auto p = camera.undistort(pd)) {
      lo = glm::min(lo, *p);
      hi = glm::max(hi, *p);
    }
  };
  for (int s = 0; s <= steps; ++s) {
    const double t = double(s) / steps;
    visit({window.pxMin.x + t * size.x, window.pxMin.y});
    visit({window.pxMin.x + t * size.x, window.pxMax.y});
    visit({window.pxMin.x, window.pxMin.y + t * size.y});
    visit({window.pxMax.x, window.pxMin.y + t * size.y});
  }
  if (lo.x < hi.x && lo.y < hi.y) {
    f.pxMin = lo;
    f.pxMax = hi;
  }
  return f;
}

FrustumBounds shearedFrustumBounds(const FrustumBounds& whole, double w, double h, const SubImageWindow& window) {
  const double xi = window.pxMin.x, yi = window.pxMin.y, wi = window.size().x, hi = window.size().y;
  FrustumBounds s;
  s.xmin = whole.xmin + xi * (whole.xmax - whole.xmin) / w;
  s.xmax = whole.xmin + (xi + wi) * (whole.xmax - whole.xmin) / w;
  s.ymin = whole.ymin + yi * (whole.ymax - whole.ymin) / h;
  s.ymax = whole.ymin + (yi + hi) * (whole.ymax - whole.ymin) / h;
  return s;
}

std::optional<glm::dvec2> subImageUv(const Camera& camera, const PinholeFrustum& frustum, const SubImageWindow& window,
                                     const glm::dmat4& clipFromRenderMatrix, const glm::dvec3& renderPoint) {
  const glm::dvec4 clip = clipFromRenderMatrix * glm::dvec4(renderPoint, 1.0);
  if (!(clip.w > 0.0)) return std::nullopt;
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  // NDC y = -1 is the top of the rectangle (pxMin.y), as clipFromRender documents.
  const glm::dvec2 pxIdeal = frustum.pxMin + (ndc + 1.0) * 0.5 * (frustum.pxMax - frustum.pxMin);
  const glm::dvec2 pxDistorted = camera.distort(pxIdeal);
  return (pxDistorted - window.pxMin) / window.size();
}

}  // namespace hv::layers
