#include "hv/scene/scene.h"

#include <algorithm>
#include <limits>

namespace hv {

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

double Scene::cameraSpacing() const {
  if (photos.size() < 2) return 1.0;
  std::vector<double> nearest;
  nearest.reserve(photos.size());
  // Quadratic, but only called once per load and on at most a few thousand cameras.
  for (size_t i = 0; i < photos.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < photos.size(); ++j)
      if (i != j) best = std::min(best, glm::length(photos[i].camera.center - photos[j].camera.center));
    nearest.push_back(best);
  }
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  const double m = nearest[nearest.size() / 2];
  return m > 0.0 ? m : 1.0;
}

}  // namespace hv
