#include "hv/camera/frustum.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hv {

PinholeFrustum idealRectCoveringImage(const Camera& cam, double marginPx) {
  PinholeFrustum f;
  f.pxMin = glm::dvec2(0.0);
  f.pxMax = glm::dvec2(cam.width, cam.height);
  if (cam.distortion && !cam.distortion->isIdentity()) {
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    const int steps = 64;
    bool outsideDomain = false;
    auto visit = [&](glm::dvec2 pd) {
      if (auto p = cam.undistort(pd)) {
        lo = glm::min(lo, *p);
        hi = glm::max(hi, *p);
      } else {
        outsideDomain = true;
      }
    };
    for (int s = 0; s <= steps; ++s) {
      const double t = double(s) / steps;
      visit({t * cam.width, 0.0});
      visit({t * cam.width, double(cam.height)});
      visit({0.0, t * cam.height});
      visit({double(cam.width), t * cam.height});
    }
    if (lo.x <= hi.x) {
      f.pxMin = glm::min(lo, f.pxMin);
      f.pxMax = glm::max(hi, f.pxMax);
    }
    // Part of the image border has no undistorted preimage: the image then extends to the edge of
    // the distortion domain, an ellipse of normalised radius sqrt(r2max) whose box bounds the
    // ideal points.
    if (outsideDomain && cam.distortion->r2max < 1e29) {
      const glm::dvec2 r = std::sqrt(cam.distortion->r2max) * cam.distortion->scale;
      f.pxMin = glm::min(f.pxMin, cam.distortion->center - r);
      f.pxMax = glm::max(f.pxMax, cam.distortion->center + r);
    }
  }
  f.pxMin -= glm::dvec2(marginPx);
  f.pxMax += glm::dvec2(marginPx);
  return f;
}

void setDepthRange(PinholeFrustum& f, const Camera& cam, const Aabb& b, double nearRatio) {
  if (b.empty()) return;
  double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
    const double z = (cam.camFromWorld * (corner - cam.center)).z;
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  f.far = std::max(zmax * 1.01, 1e-3);
  f.near = std::max(zmin * 0.99, f.far * nearRatio);
}

glm::dmat4 clipFromRender(const Camera& cam, const PinholeFrustum& fr, const glm::dvec3& origin) {
  const double w = fr.pxMax.x - fr.pxMin.x, h = fr.pxMax.y - fr.pxMin.y;
  const double n = fr.near, f = fr.far;
  // Rows of the projection from camera coordinates (X, Y, Z) to clip coordinates, derived from
  // x_ndc = 2 (px - x0) / w - 1 with px = fx X/Z + s Y/Z + cx (and likewise y), clip w = Z.
  glm::dmat4 proj(0.0);  // column-major: proj[col][row]
  proj[0][0] = 2.0 * cam.focal.x / w;
  proj[1][0] = 2.0 * cam.skew / w;
  proj[2][0] = (2.0 * (cam.principal.x - fr.pxMin.x) - w) / w;
  proj[1][1] = 2.0 * cam.focal.y / h;
  proj[2][1] = (2.0 * (cam.principal.y - fr.pxMin.y) - h) / h;
  proj[2][2] = (f + n) / (f - n);
  proj[3][2] = -2.0 * f * n / (f - n);
  proj[2][3] = 1.0;
  // camera from render: X_cam = R (X_render - (C - origin))
  glm::dmat4 camFromRender(cam.camFromWorld);
  const glm::dvec3 t = -(cam.camFromWorld * (cam.center - origin));
  camFromRender[3] = glm::dvec4(t, 1.0);
  return proj * camFromRender;
}

FrustumCorners frustumCorners(const Camera& cam, const PinholeFrustum& f) {
  const glm::dvec2 px[4] = {f.pxMin, {f.pxMax.x, f.pxMin.y}, f.pxMax, {f.pxMin.x, f.pxMax.y}};
  FrustumCorners out;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 dir = cam.rayDirection(px[i]);  // camera z = 1: scaled by depth
    out[size_t(i)] = cam.center + f.near * dir;
    out[size_t(i) + 4] = cam.center + f.far * dir;
  }
  return out;
}

FrustumCorners sceneFrustum(const Camera& cam, const Aabb& bounds) {
  PinholeFrustum f = idealRectCoveringImage(cam);
  setDepthRange(f, cam, bounds);
  return frustumCorners(cam, f);
}

namespace {

// Face normals and edge directions of a truncated frustum with the corner order above.
void frustumAxes(const FrustumCorners& c, std::vector<glm::dvec3>& normals, std::vector<glm::dvec3>& edges) {
  const glm::dvec3 e[6] = {c[1] - c[0], c[3] - c[0], c[4] - c[0], c[5] - c[1], c[6] - c[2], c[7] - c[3]};
  edges.insert(edges.end(), std::begin(e), std::end(e));
  normals.push_back(glm::cross(e[0], e[1]));                // near and far faces
  for (int i = 0; i < 4; ++i) {                             // the four side faces
    const glm::dvec3 rim = c[size_t((i + 1) % 4)] - c[size_t(i)];
    normals.push_back(glm::cross(rim, c[size_t(i) + 4] - c[size_t(i)]));
  }
}

bool separatedAlong(const glm::dvec3& axis, const FrustumCorners& a, const FrustumCorners& b) {
  const double len2 = glm::dot(axis, axis);
  if (len2 < 1e-24) return false;  // parallel edges: not an axis
  double aLo = 1e300, aHi = -1e300, bLo = 1e300, bHi = -1e300;
  for (const auto& p : a) {
    const double d = glm::dot(axis, p);
    aLo = std::min(aLo, d);
    aHi = std::max(aHi, d);
  }
  for (const auto& p : b) {
    const double d = glm::dot(axis, p);
    bLo = std::min(bLo, d);
    bHi = std::max(bHi, d);
  }
  return aHi < bLo || bHi < aLo;
}

}  // namespace

bool frustaOverlap(const FrustumCorners& a, const FrustumCorners& b) {
  // Work relative to a's first corner so that projected coordinates stay small.
  FrustumCorners ra = a, rb = b;
  for (auto& p : ra) p -= a[0];
  for (auto& p : rb) p -= a[0];
  std::vector<glm::dvec3> normals, edgesA, edgesB;
  frustumAxes(ra, normals, edgesA);
  frustumAxes(rb, normals, edgesB);
  for (const auto& n : normals)
    if (separatedAlong(n, ra, rb)) return false;
  for (const auto& ea : edgesA)
    for (const auto& eb : edgesB)
      if (separatedAlong(glm::cross(ea, eb), ra, rb)) return false;
  return true;
}

}  // namespace hv
