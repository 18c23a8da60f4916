#include "hv/scene/geocentric_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace hv {
namespace {

// WGS84 geodetic -> EPSG:4978 (the textbook formula, independent of the code under test).
glm::dvec3 ecefOf(double lon, double lat, double h) {
  const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
  const double n = a / std::sqrt(1.0 - e2 * std::sin(lat) * std::sin(lat));
  return {(n + h) * std::cos(lat) * std::cos(lon), (n + h) * std::cos(lat) * std::sin(lon),
          (n * (1.0 - e2) + h) * std::sin(lat)};
}

TEST(GeocentricFit, ReproducesAQuadraticMapExactly) {
  const glm::dvec3 c(4.2e6, 1.7e5, 4.78e6);
  auto map = [&](const glm::dvec3& p) {
    const glm::dvec3 q = (p - c) / 1000.0;
    return glm::dvec3(7e5 + 1000.0 * q.x + 3.0 * q.y * q.y, 6.8e6 + 1000.0 * q.y - 2.0 * q.x * q.z, 50.0 + q.z + q.x * q.x);
  };
  std::vector<glm::dvec3> ecef, scene;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 p = c + glm::dvec3(400.0 * i - 800.0, 400.0 * j - 800.0, 300.0 * k - 300.0);
        ecef.push_back(p);
        scene.push_back(map(p));
      }
  const GeocentricFit fit = fitGeocentric(ecef, scene);
  EXPECT_LT(fit.maxError, 1e-6);
  const glm::dvec3 off = c + glm::dvec3(123.0, -456.0, 78.0);  // between the samples
  EXPECT_LT(glm::length(applyGeocentric(fit, off) - map(off)), 1e-6);
  // The Jacobian against central differences of the map.
  const glm::dmat3 j = geocentricJacobian(fit, off);
  for (int axis = 0; axis < 3; ++axis) {
    glm::dvec3 d(0.0);
    d[axis] = 0.5;
    const glm::dvec3 numeric = (map(off + d) - map(off - d)) / 1.0;
    EXPECT_LT(glm::length(j[axis] - numeric), 1e-6) << axis;
  }
}

// An earth-centred city 2 km across mapped to a plate carrée at its latitude: a quadratic in
// ECEF stays within a millimetre (the terms left out are third order in distance / earth radius).
TEST(GeocentricFit, FitsAMapProjectionOverACityToAMillimetre) {
  const double lon0 = 2.35 * M_PI / 180.0, lat0 = 48.85 * M_PI / 180.0, r = 6378137.0;
  auto plate = [&](double lon, double lat, double h) {
    return glm::dvec3(r * std::cos(lat0) * (lon - lon0), r * (lat - lat0), h);
  };
  std::vector<glm::dvec3> ecef, scene;
  const double span = 1500.0 / r;  // radians, a little wider than the city
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 4; ++k) {
        const double lon = lon0 + span * (i / 4.0 - 1.0) / std::cos(lat0), lat = lat0 + span * (j / 4.0 - 1.0);
        const double h = 100.0 * k - 100.0;
        ecef.push_back(ecefOf(lon, lat, h));
        scene.push_back(plate(lon, lat, h));
      }
  const GeocentricFit fit = fitGeocentric(ecef, scene);
  EXPECT_LT(fit.maxError, 1e-3);
  for (const double t : {-0.9, -0.37, 0.12, 0.66}) {
    const double lon = lon0 + 1000.0 / r * t / std::cos(lat0), lat = lat0 - 1000.0 / r * t, h = 37.0 * t;
    EXPECT_LT(glm::length(applyGeocentric(fit, ecefOf(lon, lat, h)) - plate(lon, lat, h)), 1e-3) << t;
  }
}

TEST(GeocentricFit, RefusesTooFewOrFlatSamples) {
  std::vector<glm::dvec3> few(9, glm::dvec3(1.0));
  EXPECT_THROW(fitGeocentric(few, few), std::invalid_argument);
  std::vector<glm::dvec3> flat;
  for (int i = 0; i < 30; ++i) flat.push_back({double(i % 6), double(i / 6), 0.0});  // one plane: z^2 etc. vanish
  EXPECT_THROW(fitGeocentric(flat, flat), std::invalid_argument);
}

}  // namespace
}  // namespace hv
