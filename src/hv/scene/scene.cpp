#include "hv/scene/scene.h"

#include "hv/scene/robust_extent.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>

namespace hv {

namespace {

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

bool inside(const Aabb& b, const glm::dvec3& p) {
  return finite(p) && p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z &&
         p.z <= b.hi.z;
}

std::string vecText(const glm::dvec3& v) {
  std::ostringstream s;
  s << std::setprecision(6) << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

// At most this many vertices of one mesh take part in the quantiles: enough for the 5th and 95th
// percentiles to within a fraction of a percent, and linear time on a 6000 x 6000 terrain.
constexpr size_t kMaxSamplesPerSource = 65536;

void sample(const std::vector<glm::dvec3>& positions, std::vector<glm::dvec3>& out) {
  const size_t stride = std::max<size_t>(1, positions.size() / kMaxSamplesPerSource);
  for (size_t i = 0; i < positions.size(); i += stride)
    if (finite(positions[i])) out.push_back(positions[i]);
}

// The q-quantile (0..1) of one coordinate of `pts` (reorders a copy of the values).
double quantile(std::vector<double>& values, double q) {
  const size_t k = std::min(values.size() - 1, size_t(q * double(values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
  return values[k];
}

// Order-sensitive hash of the camera centres' bits: a changed, added or removed camera changes it.
std::uint64_t centreFingerprint(const std::vector<Photo>& photos) {
  std::uint64_t h = 1469598103934665603ull ^ photos.size();
  for (const Photo& p : photos)
    for (int a = 0; a < 3; ++a) {
      std::uint64_t bits = 0;
      std::memcpy(&bits, &p.camera.center[a], sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
    }
  return h;
}

struct Centres {
  std::vector<glm::dvec3> pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return pts[i][int(dim)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using CentreTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Centres>, Centres, 3, size_t>;

bool lexLess(const glm::dvec3& a, const glm::dvec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

double computeSpacing(const std::vector<Photo>& photos) {
  // Coincident centres have a nearest neighbour at 0; the kd-tree holds each distinct centre once,
  // since a kd-tree search among many equal points visits all of them (quadratic).
  std::vector<glm::dvec3> all;
  all.reserve(photos.size());
  for (const Photo& p : photos) all.push_back(p.camera.center);
  std::sort(all.begin(), all.end(), lexLess);
  Centres unique;
  std::vector<bool> repeated;
  for (size_t i = 0; i < all.size(); ++i) {
    if (i > 0 && all[i] == all[i - 1]) {
      repeated.back() = true;
      continue;
    }
    unique.pts.push_back(all[i]);
    repeated.push_back(false);
  }
  std::vector<double> nearest;
  nearest.reserve(photos.size());
  CentreTree tree(3, unique, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  for (size_t i = 0; i < unique.pts.size(); ++i) {
    double d = std::numeric_limits<double>::infinity();
    if (repeated[i]) {
      d = 0.0;
    } else if (unique.pts.size() > 1) {
      size_t idx[2];
      double dist2[2];
      const double q[3] = {unique.pts[i].x, unique.pts[i].y, unique.pts[i].z};
      const size_t found = tree.knnSearch(q, 2, idx, dist2);
      for (size_t k = 0; k < found; ++k)
        if (idx[k] != i) d = std::min(d, std::sqrt(dist2[k]));
    }
    nearest.push_back(d);
  }
  // Each camera once: the duplicates of a centre all have 0.
  for (size_t i = 0; i + 1 < all.size(); ++i)
    if (all[i] == all[i + 1]) nearest.push_back(0.0);
  std::nth_element(nearest.begin(), nearest.begin() + std::ptrdiff_t(nearest.size() / 2), nearest.end());
  const double m = nearest[nearest.size() / 2];
  return m > 0.0 && std::isfinite(m) ? m : 1.0;
}

}  // namespace

Aabb Scene::bounds() const {
  Aabb b = terrain.bounds();
  b.extend(buildings.bounds());
  b.extend(mesh.bounds());
  if (points.chunks.empty()) {
    b.extend(points.bounds());
  } else {
    for (const PointChunk& c : points.chunks) b.extend(c.bounds);
  }
  for (const auto& p : photos) b.extend(p.camera.center);
  return b;
}

RobustExtent robustExtent(const Scene& scene) {
  const Mesh& terrain = scene.terrain;
  const Mesh& buildings = scene.buildings;
  const Mesh& mesh = scene.mesh;
  const PointCloud& points = scene.points;
  const std::vector<Photo>& photos = scene.photos;
  RobustExtent r;
  std::vector<glm::dvec3> samples;
  sample(terrain.positions, samples);
  sample(buildings.positions, samples);
  sample(mesh.positions, samples);
  std::vector<glm::dvec3> chunkCorners;
  if (points.chunks.empty()) {
    sample(points.positions, samples);
  } else {
    for (const PointChunk& c : points.chunks) chunkCorners.insert(chunkCorners.end(), {c.bounds.lo, c.bounds.hi});
    sample(chunkCorners, samples);
  }
  for (const Photo& p : photos)
    if (finite(p.camera.center)) samples.push_back(p.camera.center);
  if (samples.empty()) return r;
  Aabb bulk;
  std::vector<double> values(samples.size());
  for (int a = 0; a < 3; ++a) {
    for (size_t i = 0; i < samples.size(); ++i) values[i] = samples[i][a];
    bulk.lo[a] = quantile(values, 0.05);
    bulk.hi[a] = quantile(values, 0.95);
  }
  const glm::dvec3 size = bulk.size();
  const double margin = kOutlierMargin * std::max({size.x, size.y, size.z, kOutlierMinSize});
  r.accept = bulk;
  r.accept.lo -= glm::dvec3(margin);
  r.accept.hi += glm::dvec3(margin);

  const std::string where = "outside " + vecText(r.accept.lo) + " .. " + vecText(r.accept.hi) +
                            " (the bulk of the scene with a margin of " + std::to_string(std::lround(kOutlierMargin)) +
                            " times its size); left out of the render origin and the depth range";
  auto meshSource = [&](const char* name, const std::vector<glm::dvec3>& positions, const char* what) {
    size_t out = 0;
    glm::dvec3 example(0.0);
    for (const glm::dvec3& p : positions) {
      if (inside(r.accept, p)) {
        r.geometry.extend(p);
        continue;
      }
      if (out++ == 0) example = p;
    }
    if (out)
      r.outliers.push_back(std::string(name) + ": " + std::to_string(out) + " " + what + " (e.g. " +
                           vecText(example) + ") " + where);
  };
  meshSource("terrain", terrain.positions, "vertices");
  meshSource("buildings", buildings.positions, "vertices");
  meshSource("mesh", mesh.positions, "vertices");
  if (points.chunks.empty()) {
    meshSource("points", points.positions, "points");
  } else {
    // Chunks are the unit the point pass culls and draws: a chunk counts with its whole box.
    size_t out = 0;
    glm::dvec3 example(0.0);
    for (const PointChunk& c : points.chunks) {
      if (inside(r.accept, c.bounds.lo) && inside(r.accept, c.bounds.hi)) {
        r.geometry.extend(c.bounds);
      } else if (out++ == 0) {
        example = inside(r.accept, c.bounds.lo) ? c.bounds.hi : c.bounds.lo;
      }
    }
    if (out)
      r.outliers.push_back("points: " + std::to_string(out) + " chunk(s) (e.g. a corner at " + vecText(example) +
                           ") " + where);
  }
  r.bounds = r.geometry;
  for (const Photo& p : photos) {
    if (inside(r.accept, p.camera.center))
      r.bounds.extend(p.camera.center);
    else
      r.outliers.push_back("camera '" + p.camera.id + "': centre " + vecText(p.camera.center) + " " + where);
  }
  return r;
}

double Scene::cameraSpacing() const {
  if (photos.size() < 2) return 1.0;
  // The frame planner asks every frame when --sigma is not given: the answer for the last set of
  // centres seen on this thread is remembered (a 64-bit hash of the centres tells them apart).
  struct Cache {
    std::uint64_t fingerprint = 0;
    double value = 1.0;
    bool valid = false;
  };
  static thread_local Cache cache;
  const std::uint64_t fingerprint = centreFingerprint(photos);
  if (!cache.valid || cache.fingerprint != fingerprint) cache = {fingerprint, computeSpacing(photos), true};
  return cache.value;
}

}  // namespace hv
