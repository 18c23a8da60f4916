#include "hv/render/untextured.h"

#include <algorithm>
#include <cmath>

namespace hv::render {

TangentFrame tangentFrame(const glm::dvec3& up) {
  TangentFrame f;
  f.up = glm::normalize(up);
  const glm::dvec3 seed = std::abs(f.up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  f.east = glm::normalize(seed - glm::dot(seed, f.up) * f.up);
  f.north = glm::cross(f.up, f.east);
  return f;
}

glm::dvec3 sunDirection(const glm::dvec3& up, const UntexturedSettings& s) {
  const TangentFrame f = tangentFrame(up);
  const double az = glm::radians(s.sunAzimuthDeg), el = glm::radians(s.sunElevationDeg);
  return std::cos(el) * (std::sin(az) * f.east + std::cos(az) * f.north) + std::sin(el) * f.up;
}

glm::dvec3 shadeUntextured(const glm::dvec3& normal, const glm::dvec3& up, const UntexturedSettings& s) {
  const glm::dvec3 u = glm::normalize(up);
  const double t = 0.5 * (1.0 + glm::dot(normal, u));
  const glm::dvec3 ambient = glm::mix(s.groundLight, s.skyLight, t);
  const double sun = std::max(0.0, glm::dot(normal, sunDirection(u, s)));
  return glm::clamp(s.albedo * (ambient + s.sunLight * sun), 0.0, 1.0);
}

glm::dvec3 skyColor(const glm::dvec3& direction, const glm::dvec3& up, const UntexturedSettings& s) {
  const double e = std::clamp(glm::dot(glm::normalize(direction), glm::normalize(up)), 0.0, 1.0);
  return glm::mix(s.horizon, s.zenith, std::sqrt(e));
}

}  // namespace hv::render
