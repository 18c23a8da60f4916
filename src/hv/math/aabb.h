// Axis-aligned bounding boxes in double precision (world or render frame, as the caller's data).
#pragma once

#include <glm/glm.hpp>

#include <limits>

namespace hv {

struct Aabb {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  bool empty() const { return lo.x > hi.x; }
  void extend(const glm::dvec3& p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
  void extend(const Aabb& b) { if (!b.empty()) { extend(b.lo); extend(b.hi); } }
  glm::dvec3 center() const { return 0.5 * (lo + hi); }
  glm::dvec3 size() const { return empty() ? glm::dvec3(0.0) : hi - lo; }
};

}  // namespace hv
