// CPU ray casting against a triangle mesh (Embree 3). Used for the demo city's ground truth,
// the CPU reference blend of the tests, and (later) the simulated lidar scan.
// Embree works in float: the mesh is shifted by its bounding-box centre internally, so world
// coordinates in a projected CRS keep centimetre precision. Queries are thread-safe.
#pragma once

#include "hv/scene/mesh.h"
#include "hv/scene/ray_query.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>

namespace hv {

class RayCaster final : public RayQuery {
 public:
  explicit RayCaster(const Mesh& mesh);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // First hit along origin + t * normalize(direction), t in [tMin, tMax].
  std::optional<RayHit> intersect(const glm::dvec3& origin, const glm::dvec3& direction, double tMin = 0.0,
                                  double tMax = 1e30) const override;
  // True when anything lies on the segment (tMin, tMax) of the ray.
  bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tMin, double tMax) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hv
