// Closed-form map projections for tests: expected coordinates from an independent source, not
// from PROJ. Degrees in, metres out; GRS80 (RGF93, NAD83(HARN)). WGS84's flattening differs by
// 1e-11 relative: 0.1 mm at the pole.
#pragma once

#include <glm/glm.hpp>

#include <cmath>

namespace hv::testing {

constexpr double kDeg = M_PI / 180.0;
constexpr double kA = 6378137.0, kF = 1.0 / 298.257222101;
inline const double kE2 = kF * (2.0 - kF), kE = std::sqrt(kE2);

// Geodetic -> ECEF (e.g. Hofmann-Wellenhof, GNSS, eq. 2.5 ff.).
inline glm::dvec3 ecefFromGeodetic(double latDeg, double lonDeg, double h) {
  const double lat = latDeg * kDeg, lon = lonDeg * kDeg;
  const double n = kA / std::sqrt(1.0 - kE2 * std::sin(lat) * std::sin(lat));
  return {(n + h) * std::cos(lat) * std::cos(lon), (n + h) * std::cos(lat) * std::sin(lon),
          (n * (1.0 - kE2) + h) * std::sin(lat)};
}

// Lambert conformal conic, two standard parallels, ellipsoidal (Snyder 1987, Map Projections — A
// Working Manual, eqs. 15-1, 15-2, 15-7 to 15-10, 14-15).
inline glm::dvec2 lcc2sp(double latDeg, double lonDeg, double lat1Deg, double lat2Deg, double lat0Deg,
                         double lon0Deg, double e0, double n0) {
  auto m = [](double lat) { return std::cos(lat) / std::sqrt(1.0 - kE2 * std::sin(lat) * std::sin(lat)); };
  auto t = [](double lat) {
    return std::tan(M_PI / 4.0 - lat / 2.0) / std::pow((1.0 - kE * std::sin(lat)) / (1.0 + kE * std::sin(lat)), kE / 2.0);
  };
  const double p1 = lat1Deg * kDeg, p2 = lat2Deg * kDeg, p0 = lat0Deg * kDeg, lat = latDeg * kDeg;
  const double n = (std::log(m(p1)) - std::log(m(p2))) / (std::log(t(p1)) - std::log(t(p2)));
  const double f = m(p1) / (n * std::pow(t(p1), n));
  const double rho = kA * f * std::pow(t(lat), n), rho0 = kA * f * std::pow(t(p0), n);
  const double theta = n * (lonDeg - lon0Deg) * kDeg;
  return {e0 + rho * std::sin(theta), n0 + rho0 - rho * std::cos(theta)};
}

// Lambert-93 (EPSG:2154): parallels 49 and 44 N, origin 46.5 N 3 E, false origin (700 km, 6600 km).
inline glm::dvec2 lambert93(double latDeg, double lonDeg) {
  return lcc2sp(latDeg, lonDeg, 49.0, 44.0, 46.5, 3.0, 700000.0, 6600000.0);
}

}  // namespace hv::testing
