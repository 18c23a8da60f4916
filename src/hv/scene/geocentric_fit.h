// A map from earth-centred coordinates (EPSG:4978) into a scene's frame where no projection
// library is at hand (the browser build): a quadratic polynomial in each output, fitted natively
// (with PROJ) at export over the scene's neighbourhood and evaluated in the page (docs/web.md,
// "Points from 3D Tiles"). Over a city a few kilometres across the terms it leaves out (third order
// in distance / earth radius) are far below a millimetre; maxError says what the fit measured.
#pragma once

#include "hv/math/aabb.h"

#include <glm/glm.hpp>

#include <array>
#include <vector>

namespace hv {

struct GeocentricFit {
  glm::dvec3 centre{0.0};  // the samples' mean (EPSG:4978), subtracted before scaling
  double scale = 1.0;      // metres per unit of the normalised coordinates
  // Per output coordinate, the coefficients of 1, u, v, w, uu, uv, uw, vv, vw, ww, where
  // (u, v, w) = (p - centre) / scale.
  std::array<glm::dvec3, 10> coefficients{};
  double maxError = 0.0;  // the largest distance between the fit and the samples, metres
  bool valid() const { return scale > 0.0; }
};

// Where the fit is sampled, in the scene frame: `bounds` (the scene's) widened by half their size
// (at least 500 m) and 200 m up and down, a 9 x 9 x 5 grid (405 samples, ten unknowns per
// coordinate many times over). `web-export` maps them to EPSG:4978 with PROJ, the page of a
// service scene without an export with proj4js (web/services_frame.js).
std::vector<glm::dvec3> geocentricFitSamples(const Aabb& bounds);

// Least squares over matching samples (at least 10, spread in three dimensions). Throws
// std::invalid_argument when they are too few or degenerate.
GeocentricFit fitGeocentric(const std::vector<glm::dvec3>& ecef, const std::vector<glm::dvec3>& scene);

// The scene-frame position of an earth-centred one.
glm::dvec3 applyGeocentric(const GeocentricFit& fit, const glm::dvec3& ecef);
// The fit's Jacobian at `ecef` (column j: the derivative along ECEF axis j), to turn normals.
glm::dmat3 geocentricJacobian(const GeocentricFit& fit, const glm::dvec3& ecef);

}  // namespace hv
