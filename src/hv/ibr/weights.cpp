#include "hv/ibr/weights.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace hv::ibr {

double blendFalloff(double d, double sigma) { return 1.0 / (sigma * sigma + d * d); }

std::vector<double> blendWeights(const std::vector<double>& d, int k, double sigma) {
  assert(std::is_sorted(d.begin(), d.end()) && "distances must be sorted ascending");
  const size_t n = std::min(d.size(), size_t(std::max(k, 0)));
  const double fNext = d.size() > n ? blendFalloff(d[n], sigma) : 0.0;
  std::vector<double> w(n);
  for (size_t i = 0; i < n; ++i) w[i] = std::max(0.0, blendFalloff(d[i], sigma) - fNext);
  return w;
}

double rayAngle(const GeometryPenaltyInput& in) {
  const glm::dvec3 a = glm::normalize(in.point - in.imageCenter), b = glm::normalize(in.point - in.viewCenter);
  // atan2 of |a x b| and a . b: accurate near 0, where acos is not.
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

double footprintRatio(const GeometryPenaltyInput& in) {
  const glm::dvec3 toImage = in.point - in.imageCenter, toView = in.point - in.viewCenter;
  const double di = glm::length(toImage), dv = glm::length(toView);
  const glm::dvec3 n = glm::normalize(in.normal);
  const double ci = std::max(std::abs(glm::dot(n, toImage / di)), kMinCosine);
  const double cv = std::max(std::abs(glm::dot(n, toView / dv)), kMinCosine);
  return (di / (in.imageFocal * ci)) / (dv / (in.viewFocal * cv));
}

double geometryPenalty(const GeometryPenaltyInput& in, double resolutionWeight) {
  return rayAngle(in) + resolutionWeight * std::max(0.0, std::log(footprintRatio(in)));
}

double featherFactor(double distance, double width) {
  if (width <= 0.0) return 1.0;
  const double t = std::clamp(distance / width, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

double maskFeather(double m) { return std::clamp(2.0 * m - 1.0, 0.0, 1.0); }

}  // namespace hv::ibr
