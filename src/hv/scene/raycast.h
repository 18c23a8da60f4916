// CPU ray casting against a triangle mesh (Embree 3). Used for the demo city's ground truth,
// the CPU reference blend of the tests, and (later) the simulated lidar scan.
// Embree works in float: the mesh is shifted by its bounding-box centre internally, so world
// coordinates in a projected CRS keep centimetre precision. Queries are thread-safe.
#pragma once

#include "hv/scene/mesh.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>

namespace hv {

struct RayHit {
  double t = 0.0;                   // distance along the (normalised) direction
  glm::dvec3 position{0.0};         // world
  glm::dvec3 normal{0.0};           // geometric normal of the triangle, unit, as oriented in the mesh
  std::uint32_t triangle = 0;       // index into Mesh::triangles
  glm::dvec2 barycentric{0.0};      // Embree's (u, v)
};

class RayCaster {
 public:
  explicit RayCaster(const Mesh& mesh);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // First hit along origin + t * normalize(direction), t in [tMin, tMax].
  std::optional<RayHit> intersect(const glm::dvec3& origin, const glm::dvec3& direction, double tMin = 0.0,
                                  double tMax = 1e30) const;
  // True when anything lies on the segment (tMin, tMax) of the ray.
  bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tMin, double tMax) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hv
