#include "hv/ibr/frame_plan.h"

#include "hv/ibr/weights.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hv::ibr {

int geometryBlendCount(int k, int geometryK) {
  const int kk = std::max(k, 1);
  return std::clamp(geometryK > 0 ? std::min(geometryK, kk) : kk, 1, kMaxGeometryK);
}

FramePlan planFrame(const Scene& scene, const CameraIndex& index, const Camera& view, const BlendSettings& s,
                    const Aabb& bounds, const FrustumIndex* frusta) {
  FramePlan plan;
  plan.view = view;
  plan.settings = s;
  plan.sigma = s.sigma > 0.0 ? s.sigma : scene.cameraSpacing();
  const bool filter = s.frustumFilter && !bounds.empty();
  const FrustumCorners viewFrustum = filter ? sceneFrustum(view, bounds) : FrustumCorners{};
  // The time window, the exclusions (what any selection filters), then the frustum overlap.
  auto keepMeta = [&](int i) {
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
    return true;
  };
  auto keep = [&](int i) {
    return keepMeta(i) && (!filter || frustaOverlap(viewFrustum, sceneFrustum(scene.photos[size_t(i)].camera, bounds)));
  };
  if (s.selection == Selection::Region) {
    // Each candidate carries f(d_i); the pixel's K+1-th is the shader's (docs/design.md, step 5).
    auto add = [&](int photo, double distance) {
      plan.images.push_back({photo, distance, blendFalloff(distance, plan.sigma)});
    };
    const int count = std::max(s.candidates, 1);
    if (bounds.empty()) {
      // No geometry to sample: the nearest photographs (a panorama collection on its sphere).
      for (const auto& c : index.nearest(view.center, size_t(count), keep)) add(c.photo, c.distance);
      return plan;
    }
    std::optional<FrustumIndex> own;
    if (!frusta || frusta->size() != scene.photos.size() || frusta->bounds().lo != bounds.lo ||
        frusta->bounds().hi != bounds.hi) {
      std::vector<Camera> cameras;
      for (const auto& p : scene.photos) cameras.push_back(p.camera);
      frusta = &own.emplace(cameras, bounds);
    }
    // A photograph is listed where its frustum contains a sample of the view: that is the frustum
    // filter, finer, so its overlap test is not repeated.
    for (const auto& c : regionCandidates(*frusta, view, count, s.regionGrid, keepMeta)) add(c.photo, c.distance);
    return plan;
  }
  if (s.weighting == Weighting::Geometry) {
    // Each pixel picks its own best K by penalty: the frame passes the `candidates` nearest.
    for (const auto& c : index.nearest(view.center, size_t(std::max(s.candidates, 1)), keep))
      plan.images.push_back({c.photo, c.distance, blendFalloff(c.distance, plan.sigma)});
    return plan;
  }
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
  o[34] = float(0.5 * (cam.focal.x + cam.focal.y));
  o[35] = float(p.layer);
  o[36] = float(d.scale.x);
  o[37] = float(d.scale.y);
  o[38] = float(d.p1);
  o[39] = float(d.p2);
  o[40] = float(d.l1);
  o[41] = float(d.l2);
  o[42] = d.model == LensDistortion::Model::Fisheye ? 1.0f : 0.0f;
  o[43] = float(p.group);
  for (int c = 0; c < 3; ++c) {
    o[44 + c] = float(p.colour.gain[c]);
    o[48 + c] = float(p.colour.offset[c]);
  }
  o[47] = float(p.uvOffset.x);
  o[51] = float(p.uvOffset.y);
}

}  // namespace hv::ibr
