#include "hv/ibr/frame_plan.h"

#include "hv/ibr/weights.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hv::ibr {

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

FramePlan planFrame(const Scene& scene, const CameraIndex& index, const Camera& view, const BlendSettings& s,
                    const Aabb& bounds) {
  FramePlan plan;
  plan.view = view;
  plan.settings = s;
  plan.sigma = s.sigma > 0.0 ? s.sigma : scene.cameraSpacing();
  const bool filter = s.frustumFilter && !bounds.empty();
  const FrustumCorners viewFrustum = filter ? sceneFrustum(view, bounds) : FrustumCorners{};
  auto keep = [&](int i) {
    const Camera& cam = scene.photos[size_t(i)].camera;
    if (std::find(s.exclude.begin(), s.exclude.end(), cam.id) != s.exclude.end()) return false;
    if (s.window || s.datedOnly) {
      const std::string& date = scene.photos[size_t(i)].date;
      const std::optional<DateInterval> when = date.empty() ? std::nullopt : parseDate(date);
      if (!when) {
        if (s.datedOnly) return false;
      } else if (s.window && !overlaps(*when, *s.window)) {
        return false;
      }
    }
    return !filter || frustaOverlap(viewFrustum, sceneFrustum(cam, bounds));
  };
  const auto cands = index.nearest(view.center, size_t(std::max(s.k, 0)) + 1, keep);
  std::vector<double> d;
  for (const auto& c : cands) d.push_back(c.distance);
  const auto w = blendWeights(d, s.k, plan.sigma);
  for (size_t i = 0; i < w.size(); ++i) plan.images.push_back({cands[i].photo, cands[i].distance, w[i]});
  plan.nextDistance = cands.size() > w.size() ? cands[w.size()].distance : -1.0;
  return plan;
}

glm::vec2 gpuDays(const DateInterval& d) {
  auto clampDay = [](std::int64_t v) { return float(std::clamp<double>(double(v), -kOpenDay, kOpenDay)); };
  return {clampDay(d.first), clampDay(d.last)};
}

double shadowBias(const DepthBias& b, double z, double cosIncidence) {
  const double c = std::max(std::abs(cosIncidence), 0.1);
  return b.absolute + b.relative * z * (1.0 + std::sqrt(std::max(1.0 - c * c, 0.0)) / c);
}

ImageParams makeImageParams(const Camera& cam, const glm::dvec3& origin, const SliceLayout& layout, double weight,
                            const PinholeFrustum& depth, const DepthBias& bias) {
  ImageParams p;
  p.pixFromWorld = cam.pixFromWorld();
  p.centerRender = cam.center - origin;
  p.camera = cam;
  p.layout = layout;
  p.weight = weight;
  p.depth = depth;
  p.bias = bias;
  return p;
}

void packImageParams(const ImageParams& p, float* o) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) o[4 * r + c] = float(p.pixFromWorld[c][r]);
    o[4 * r + 3] = float(p.centerRender[r]);
  }
  const Camera& cam = p.camera;
  const bool distorted = cam.distortion && !cam.distortion->isIdentity();
  const LensDistortion d = distorted ? *cam.distortion : LensDistortion{};
  o[12] = float(d.center.x);
  o[13] = float(d.center.y);
  o[14] = float(d.c3);
  o[15] = float(d.c5);
  o[16] = float(d.c7);
  o[17] = distorted ? float(std::min(d.r2max, 1e30)) : -1.0f;
  o[18] = float(cam.width);
  o[19] = float(cam.height);
  o[20] = float(p.layout.uvScale.x);
  o[21] = float(p.layout.uvScale.y);
  o[22] = float(p.layout.slice);
  o[23] = float(p.weight);
  o[24] = float(p.depth.pxMin.x);
  o[25] = float(p.depth.pxMin.y);
  o[26] = float(1.0 / (p.depth.pxMax.x - p.depth.pxMin.x));
  o[27] = float(1.0 / (p.depth.pxMax.y - p.depth.pxMin.y));
  o[28] = float(p.depth.near);
  o[29] = float(p.depth.far);
  o[30] = float(p.bias.absolute);
  o[31] = float(p.bias.relative);
  const glm::vec2 days = gpuDays(p.date);
  o[32] = days.x;
  o[33] = days.y;
  o[34] = 0.0f;
  o[35] = 0.0f;
  o[36] = float(d.scale.x);
  o[37] = float(d.scale.y);
  o[38] = float(d.p1);
  o[39] = float(d.p2);
  o[40] = float(d.l1);
  o[41] = float(d.l2);
  o[42] = d.model == LensDistortion::Model::Fisheye ? 1.0f : 0.0f;
  o[43] = 0.0f;
}

}  // namespace hv::ibr
