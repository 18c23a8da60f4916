#include "hv/scene/geocentric_fit.h"

#include <Eigen/Dense>

#include <algorithm>
#include <stdexcept>

namespace hv {
namespace {

std::array<double, 10> terms(const glm::dvec3& q) {
  return {1.0, q.x, q.y, q.z, q.x * q.x, q.x * q.y, q.x * q.z, q.y * q.y, q.y * q.z, q.z * q.z};
}

}  // namespace

std::vector<glm::dvec3> geocentricFitSamples(const Aabb& bounds) {
  const glm::dvec3 size = bounds.size();
  const double widen = std::max(500.0, 0.5 * std::max(size.x, size.y));
  const glm::dvec3 lo = bounds.lo - glm::dvec3(widen, widen, 200.0), hi = bounds.hi + glm::dvec3(widen, widen, 200.0);
  std::vector<glm::dvec3> samples;
  samples.reserve(9 * 9 * 5);
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 4; ++k) samples.push_back(lo + (hi - lo) * glm::dvec3(i / 8.0, j / 8.0, k / 4.0));
  return samples;
}

GeocentricFit fitGeocentric(const std::vector<glm::dvec3>& ecef, const std::vector<glm::dvec3>& scene) {
  if (ecef.size() != scene.size() || ecef.size() < 10)
    throw std::invalid_argument("geocentric fit: expected at least 10 matching samples, got " +
                                std::to_string(ecef.size()) + " and " + std::to_string(scene.size()));
  GeocentricFit fit;
  for (const glm::dvec3& p : ecef) fit.centre += p / double(ecef.size());
  double far = 0.0;
  for (const glm::dvec3& p : ecef) far = std::max(far, glm::length(p - fit.centre));
  if (!(far > 0.0)) throw std::invalid_argument("geocentric fit: the samples are all at one place");
  fit.scale = far;
  const Eigen::Index n = Eigen::Index(ecef.size());
  Eigen::MatrixXd a(n, 10), b(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::array<double, 10> t = terms((ecef[std::size_t(i)] - fit.centre) / fit.scale);
    for (int k = 0; k < 10; ++k) a(i, k) = t[std::size_t(k)];
    for (int c = 0; c < 3; ++c) b(i, c) = scene[std::size_t(i)][c];
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < 10) throw std::invalid_argument("geocentric fit: the samples do not span three dimensions");
  const Eigen::MatrixXd x = qr.solve(b);
  for (int k = 0; k < 10; ++k) fit.coefficients[std::size_t(k)] = {x(k, 0), x(k, 1), x(k, 2)};
  for (std::size_t i = 0; i < ecef.size(); ++i)
    fit.maxError = std::max(fit.maxError, glm::length(applyGeocentric(fit, ecef[i]) - scene[i]));
  return fit;
}

glm::dvec3 applyGeocentric(const GeocentricFit& fit, const glm::dvec3& ecef) {
  const std::array<double, 10> t = terms((ecef - fit.centre) / fit.scale);
  glm::dvec3 out(0.0);
  for (std::size_t k = 0; k < 10; ++k) out += t[k] * fit.coefficients[k];
  return out;
}

glm::dmat3 geocentricJacobian(const GeocentricFit& fit, const glm::dvec3& ecef) {
  const glm::dvec3 q = (ecef - fit.centre) / fit.scale;
  const auto& c = fit.coefficients;
  // d/du, d/dv, d/dw of the terms, then / scale.
  const glm::dvec3 du = c[1] + 2.0 * q.x * c[4] + q.y * c[5] + q.z * c[6];
  const glm::dvec3 dv = c[2] + q.x * c[5] + 2.0 * q.y * c[7] + q.z * c[8];
  const glm::dvec3 dw = c[3] + q.x * c[6] + q.y * c[8] + 2.0 * q.z * c[9];
  return glm::dmat3(du / fit.scale, dv / fit.scale, dw / fit.scale);
}

}  // namespace hv
