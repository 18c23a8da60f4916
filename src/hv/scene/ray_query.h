// Ray queries against the scene's geometry, as an interface: what navigation (walking on the
// ground, stopping at walls, the focus + context step back) needs, without naming the library that
// answers. Natively hv::RayCaster (Embree, hv/scene/raycast.h) implements it; the browser build has
// none (walking then keeps its height and nothing blocks).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>

namespace hv {

struct RayHit {
  double t = 0.0;                   // distance along the (normalised) direction
  glm::dvec3 position{0.0};         // world
  glm::dvec3 normal{0.0};           // geometric normal of the triangle, unit, as oriented in the mesh
  std::uint32_t triangle = 0;       // index into Mesh::triangles
  glm::dvec2 barycentric{0.0};      // barycentric (u, v) of the hit in the triangle
};

class RayQuery {
 public:
  virtual ~RayQuery() = default;
  // First hit along origin + t * normalize(direction), t in [tMin, tMax].
  virtual std::optional<RayHit> intersect(const glm::dvec3& origin, const glm::dvec3& direction, double tMin = 0.0,
                                          double tMax = 1e30) const = 0;
  // True when anything lies on the segment (tMin, tMax) of the ray.
  virtual bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tMin, double tMax) const = 0;
};

}  // namespace hv
