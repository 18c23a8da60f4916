#include "hv/scene/scene_scale.h"

#include "hv/scene/robust_extent.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

namespace hv {

namespace {

struct Points {
  std::vector<glm::dvec3> pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return pts[i][int(dim)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Points>, Points, 3, size_t>;

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

double boxDistance(const Aabb& b, const glm::dvec3& p) {
  if (b.empty()) return std::numeric_limits<double>::infinity();
  const glm::dvec3 d = glm::max(glm::max(b.lo - p, p - b.hi), glm::dvec3(0.0));
  return glm::length(d);
}

std::string text(double v) {
  std::ostringstream s;
  s << std::setprecision(4) << v;
  return s.str();
}

// Geometry samples inside `accept`, evenly strided over each source.
std::vector<glm::dvec3> geometrySamples(const Scene& scene, const Aabb& accept) {
  const std::vector<const std::vector<glm::dvec3>*> sources{&scene.terrain.positions, &scene.buildings.positions,
                                                            &scene.mesh.positions, &scene.points.positions};
  size_t total = 0;
  for (const auto* s : sources) total += s->size();
  std::vector<glm::dvec3> out;
  if (total == 0) return out;
  const size_t stride = std::max<size_t>(1, total / kScaleGeometrySamples);
  for (const auto* s : sources)
    for (size_t i = 0; i < s->size(); i += stride) {
      const glm::dvec3& p = (*s)[i];
      if (finite(p) && boxDistance(accept, p) == 0.0) out.push_back(p);
    }
  return out;
}

}  // namespace

SceneScale sceneScale(const Scene& scene) {
  SceneScale r;
  const RobustExtent robust = robustExtent(scene);
  if (!robust.geometry.empty()) r.extent = glm::length(robust.geometry.size());
  const std::vector<glm::dvec3> samples = geometrySamples(scene, robust.accept);

  const size_t n = scene.photos.size();
  // Surface distance per camera (sampled cameras), median over those that see geometry.
  std::vector<std::pair<size_t, double>> surface;  // (camera, median depth)
  if (!samples.empty() && n > 0) {
    const size_t stride = std::max<size_t>(1, n / kScaleCameraSamples);
    for (size_t i = 0; i < n; i += stride) {
      const Camera& c = scene.photos[i].camera;
      std::vector<double> depths;
      for (const glm::dvec3& p : samples) {
        const glm::dvec3 cam = c.camFromWorld * (p - c.center);
        if (cam.z <= 0.0) continue;
        const glm::dvec3 px = c.pixFromCam() * cam;
        const double x = px.x / px.z, y = px.y / px.z;
        if (x >= 0.0 && y >= 0.0 && x <= c.width && y <= c.height) depths.push_back(cam.z);
      }
      if (depths.size() >= 3) surface.push_back({i, median(std::move(depths))});
    }
  }
  auto surfaceMedian = [&](const std::vector<bool>* leftOut) {
    std::vector<double> v;
    for (const auto& [i, d] : surface)
      if (!leftOut || !(*leftOut)[i]) v.push_back(d);
    return median(std::move(v));
  };
  const double surfaceAll = surfaceMedian(nullptr);

  // Nearest other camera of each camera (any heading), for the outliers.
  Points centres;
  for (const Photo& p : scene.photos)
    centres.pts.push_back(finite(p.camera.center) ? p.camera.center : glm::dvec3(0.0));
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  std::vector<std::vector<std::pair<size_t, double>>> neighbours(n);  // up to kK nearest, for the spacing
  constexpr size_t kK = 32;
  if (n >= 2) {
    Tree tree(3, centres, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree.buildIndex();
    const size_t k = std::min(n, kK + 1);
    std::vector<size_t> idx(k);
    std::vector<double> d2(k);
    for (size_t i = 0; i < n; ++i) {
      const double q[3] = {centres.pts[i].x, centres.pts[i].y, centres.pts[i].z};
      const size_t found = tree.knnSearch(q, k, idx.data(), d2.data());
      for (size_t j = 0; j < found; ++j) {
        if (idx[j] == i) continue;
        const double d = std::sqrt(d2[j]);
        nearest[i] = std::min(nearest[i], d);
        neighbours[i].push_back({idx[j], d});
      }
    }
  }
  std::vector<double> finiteNearest;
  for (double d : nearest)
    if (std::isfinite(d)) finiteNearest.push_back(d);

  // Outlying cameras: far from every other camera and from the geometry.
  double reference = surfaceAll > 0.0 ? surfaceAll : median(finiteNearest);
  double far = kOutlierFactor * reference;
  if (!scene.crs.empty()) far = std::min(far > 0.0 ? far : kOutlierMetres, kOutlierMetres);
  std::vector<bool> out(n, false);
  if (far > 0.0 && n >= 1)
    for (size_t i = 0; i < n; ++i) {
      const double toGeometry = boxDistance(robust.geometry, scene.photos[i].camera.center);
      if (nearest[i] > far && toGeometry > far) {
        out[i] = true;
        r.outlying.push_back(i);
      }
    }
  for (size_t k = 0; k < r.outlying.size(); ++k) {
    if (k == 10) {
      r.warnings.push_back(std::to_string(r.outlying.size() - 10) + " more outlying camera(s)");
      break;
    }
    const size_t i = r.outlying[k];
    const Camera& c = scene.photos[i].camera;
    r.warnings.push_back(
        "camera '" + c.id + "': centre (" + text(c.center.x) + ", " + text(c.center.y) + ", " + text(c.center.z) +
        ") is " +
        (std::isfinite(nearest[i]) ? text(nearest[i]) + " from the nearest other camera" : "the only camera") +
        (robust.geometry.empty() ? " and the scene has no geometry"
                                 : " and " + text(boxDistance(robust.geometry, c.center)) + " from the geometry") +
        " (more than " + text(far) + "): left out of the scene's scale; check its orientation");
  }
  r.surfaceDistance = surfaceMedian(&out);  // the outliers left out

  // Spacing: nearest neighbour looking the same way, among the inlying cameras.
  const double cosMax = std::cos(kSameHeadingDeg * std::numbers::pi / 180.0);
  auto forward = [&](size_t i) { return glm::transpose(scene.photos[i].camera.camFromWorld)[2]; };
  std::vector<double> spacing;
  for (size_t i = 0; i < n; ++i) {
    if (out[i]) continue;
    for (const auto& [j, d] : neighbours[i]) {  // nearest first (knnSearch sorts)
      if (out[j] || d <= 0.0) continue;
      if (glm::dot(forward(i), forward(j)) >= cosMax) {
        spacing.push_back(d);
        break;
      }
    }
  }
  r.spacing = median(spacing);

  if (r.surfaceDistance > 0.0) {
    r.scale = r.surfaceDistance;
    r.source = "the typical camera-to-surface distance";
  } else if (r.spacing > 0.0) {
    r.scale = r.spacing;
    r.source = "the spacing of the cameras";
    if (!scene.crs.empty() && (r.spacing < kMetricSpacingScale[0] || r.spacing > kMetricSpacingScale[1])) {
      // In metres, with no geometry to measure against: photographs a kilometre apart (panoramas
      // across a city) or centimetres apart say nothing of the distance to a façade.
      r.scale = std::clamp(r.spacing, kMetricSpacingScale[0], kMetricSpacingScale[1]);
      r.source = "the spacing of the cameras, " + text(r.spacing) + " m, brought within street level (" +
                 text(kMetricSpacingScale[0]) + " to " + text(kMetricSpacingScale[1]) + " m)";
    }
  } else if (r.extent > 0.0) {
    r.scale = r.extent / 10.0;
    r.source = "a tenth of the geometry's extent";
  } else {
    r.scale = kDefaultScale;
    r.source = "a default: no geometry, no camera spacing to measure";
  }
  return r;
}

CameraUp cameraUp(const std::vector<Photo>& photos) {
  CameraUp r;
  glm::dvec3 sum(0.0);
  for (const Photo& p : photos) {
    const glm::dvec3 imageUp = -glm::transpose(p.camera.camFromWorld)[1];
    if (!finite(imageUp)) continue;
    sum += imageUp;
    ++r.cameras;
  }
  if (r.cameras == 0) return r;
  const glm::dvec3 mean = sum / double(r.cameras);
  r.agreement = glm::length(mean);
  if (r.agreement > 0.0) r.up = mean / r.agreement;
  return r;
}

std::string upOrigin(const Scene& scene) {
  if (!scene.crs.empty()) return "(the scene CRS's vertical)";
  const CameraUp c = cameraUp(scene.photos);
  if (c.cameras > 0 && c.agreement >= kCameraUpAgreement && scene.up == c.up)
    return "(inferred from the " + std::to_string(c.cameras) + " cameras' image up: no crs, no up in scene.json)";
  if (scene.up == glm::dvec3(0.0, 0.0, 1.0))
    return c.cameras > 0 && c.agreement < kCameraUpAgreement
               ? "(z, the default: the cameras' image up vectors disagree)"
               : "(z, the default)";
  return "(as scene.json gives it)";
}

}  // namespace hv
