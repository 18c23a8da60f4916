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
    auto visit = [&](glm::dvec2 pd) {
      if (auto p = cam.undistort(pd)) {
        lo = glm::min(lo, *p);
        hi = glm::max(hi, *p);
      }
    };
    for (int s = 0; s <= steps; ++s) {
      const double t = double(s) / steps;
      visit({t * cam.width, 0.0});
      visit({t * cam.width, double(cam.height)});
      visit({0.0, t * cam.height});
      visit({double(cam.width), t * cam.height});
    }
    // The border may lie outside the distortion domain (undistort fails there); the domain's own
    // disc then bounds the image, so include the image rectangle too.
    if (lo.x <= hi.x) {
      f.pxMin = glm::min(lo, f.pxMin);
      f.pxMax = glm::max(hi, f.pxMax);
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

std::vector<glm::dvec3> viewFrustumSamples(const Camera& view, const Aabb& b, int nx, int ny, int nz) {
  std::vector<glm::dvec3> out;
  if (b.empty()) return out;
  const PinholeFrustum rect = idealRectCoveringImage(view);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const glm::dvec2 px = glm::mix(rect.pxMin, rect.pxMax, glm::dvec2((i + 0.5) / nx, (j + 0.5) / ny));
      const glm::dvec3 dir = view.rayDirection(px);  // camera z = 1: t is the depth
      // Slab test: the ray's interval inside the box.
      double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        if (std::abs(dir[a]) < 1e-15) {
          if (view.center[a] < b.lo[a] || view.center[a] > b.hi[a]) t1 = -1.0;
          continue;
        }
        double ta = (b.lo[a] - view.center[a]) / dir[a], tb = (b.hi[a] - view.center[a]) / dir[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (!(t1 > t0)) continue;
      const double start = std::max(t0, 1e-3 * t1);
      for (int k = 0; k < nz; ++k) {
        const double t = start * std::pow(t1 / start, (k + 0.5) / nz);
        out.push_back(view.center + t * dir);
      }
    }
  }
  return out;
}

bool seesAnySample(const Camera& photo, const std::vector<glm::dvec3>& samples) {
  for (const auto& p : samples)
    if (photo.project(p).inImage) return true;
  return false;
}

FramePlan planFrame(const Scene& scene, const CameraIndex& index, const Camera& view, const BlendSettings& s,
                    const Aabb& bounds) {
  FramePlan plan;
  plan.view = view;
  plan.settings = s;
  plan.sigma = s.sigma > 0.0 ? s.sigma : scene.cameraSpacing();
  const std::vector<glm::dvec3> samples = s.frustumFilter ? viewFrustumSamples(view, bounds) : std::vector<glm::dvec3>{};
  auto keep = [&](int i) {
    const Camera& cam = scene.photos[size_t(i)].camera;
    if (std::find(s.exclude.begin(), s.exclude.end(), cam.id) != s.exclude.end()) return false;
    return !s.frustumFilter || seesAnySample(cam, samples);
  };
  const auto cands = index.nearest(view.center, size_t(std::max(s.k, 0)) + 1, keep);
  std::vector<double> d;
  for (const auto& c : cands) d.push_back(c.distance);
  const auto w = blendWeights(d, s.k, plan.sigma);
  for (size_t i = 0; i < w.size(); ++i) plan.images.push_back({cands[i].photo, cands[i].distance, w[i]});
  plan.nextDistance = cands.size() > w.size() ? cands[w.size()].distance : -1.0;
  return plan;
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
  const RadialDistortion d = distorted ? *cam.distortion : RadialDistortion{};
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
}

}  // namespace hv::ibr
