#include "hv/camera/frustum_outline.h"

#include <algorithm>

namespace hv {

namespace {

// The ideal pixel of distorted pixel `pd`, or of the farthest pixel towards the principal point
// that has one. Bisection on the segment principal point -> pd: the domain is a disc about the
// distortion centre, so the pixels that can be undistorted form one interval from the principal
// point (assumed inside) outwards.
glm::dvec2 undistortTowardsCentre(const Camera& camera, glm::dvec2 pd) {
  if (const auto p = camera.undistort(pd)) return *p;
  const glm::dvec2 c = camera.principal;
  double inside = 0.0, outside = 1.0;
  // 40 halvings: well below a thousandth of a pixel for images up to a million pixels wide.
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (inside + outside);
    (camera.undistort(c + mid * (pd - c)) ? inside : outside) = mid;
  }
  return camera.undistort(c + inside * (pd - c)).value_or(c);
}

}  // namespace

FrustumOutline frustumOutline(const Camera& camera, double depth, int perSide) {
  perSide = std::max(1, perSide);
  FrustumOutline out;
  out.apex = camera.center;
  const glm::dvec2 size(camera.width, camera.height);
  // Clockwise in the image (x right, y down): top, right, bottom, left sides.
  const std::array<glm::dvec2, 4> corner = {glm::dvec2(0.0), glm::dvec2(size.x, 0.0), size, glm::dvec2(0.0, size.y)};
  for (int side = 0; side < 4; ++side) {
    out.corners[size_t(side)] = int(out.border.size());
    const glm::dvec2 a = corner[size_t(side)], b = corner[size_t((side + 1) % 4)];
    for (int i = 0; i < perSide; ++i) {
      const glm::dvec2 pd = a + (b - a) * (double(i) / perSide);
      // rayDirection has camera z = 1, so this point is at `depth` along the axis.
      out.border.push_back(camera.center + depth * camera.rayDirection(undistortTowardsCentre(camera, pd)));
    }
  }
  return out;
}

std::vector<glm::dvec3> frustumLineSegments(const FrustumOutline& outline) {
  std::vector<glm::dvec3> lines;
  const size_t n = outline.border.size();
  lines.reserve(2 * (n + 4));
  for (size_t i = 0; i < n; ++i) {
    lines.push_back(outline.border[i]);
    lines.push_back(outline.border[(i + 1) % n]);
  }
  for (int c : outline.corners) {
    lines.push_back(outline.apex);
    lines.push_back(outline.border[size_t(c)]);
  }
  return lines;
}

}  // namespace hv
