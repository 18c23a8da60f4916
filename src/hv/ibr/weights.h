// View-dependent blending weights (Brédif 2013, eq. 1-2; docs/design.md, step 5).
//   f(d) = 1 / (sigma^2 + d^2),   w_i = f(d_i) - f(d_{K+1}),   i = 1..K
// with d_i the distances from the view centre to the camera centres, sorted ascending, and
// f(d_{K+1}) = 0 when there are K or fewer candidates. When the K-th and (K+1)-th images swap,
// w_K = 0, so the blend does not pop where other images also cover the pixel.
//
// Geometry-aware weights (after Buehler et al. 2001, Unstructured Lumigraph Rendering; docs/design.md,
// "Weights that know geometry"): per surface point P, image i is penalised by
//   p_i = theta_i + lambda * max(0, ln rho_i)
// theta_i the angle between the photograph's ray (C_i -> P) and the view's ray (V -> P), rho_i the
// ratio of the photograph's texel footprint on the surface to the view's pixel footprint there,
//   rho_i = (|P - C_i| / (f_i cos_i)) / (|P - V| / (f_v cos_v)),
// f the focal lengths in pixels, cos the incidence cosines on the surface (clamped at kMinCosine):
// a photograph that is blurrier than the view at P, or that sees the surface at grazing incidence
// (its texels stretched by 1 / cos_i), is penalised; a sharper one is not. The best K per pixel
// blend with w_i = f(p_i) - f(p_{K+1}), the same f with sigma = epsilon (radians): the weight of
// the K-th vanishes continuously as it is about to leave the best K, as ULR's 1 - p_i / p_{K+1}.
//
// Feathering: a weight is multiplied by smoothstep(0, width, distance of the projection to the
// photograph's border or lens domain edge, in photograph pixels), and by a mask factor
// clamp(2 m_L - 1, 0, 1), m_L the mask averaged over about `width` pixels (a mip level).
#pragma once

#include <glm/glm.hpp>

#include <vector>

namespace hv::ibr {

double blendFalloff(double distance, double sigma);

// `sortedDistances` ascending, at least the K+1 nearest when there are that many. Returns K
// weights (fewer when fewer candidates), each >= 0.
std::vector<double> blendWeights(const std::vector<double>& sortedDistances, int k, double sigma);

// Incidence cosines below this count as this (a surface seen edge-on): keeps rho finite.
inline constexpr double kMinCosine = 0.05;

struct GeometryPenaltyInput {
  glm::dvec3 point{0.0};             // P
  glm::dvec3 viewCenter{0.0};        // V
  glm::dvec3 imageCenter{0.0};       // C_i
  glm::dvec3 normal{0.0, 0.0, 1.0};  // the surface's, either orientation
  double viewFocal = 1.0;            // pixels
  double imageFocal = 1.0;           // pixels of the photograph
};

// theta_i, radians in [0, pi].
double rayAngle(const GeometryPenaltyInput& in);
// rho_i (> 0).
double footprintRatio(const GeometryPenaltyInput& in);
// p_i = theta_i + lambda * max(0, ln rho_i).
double geometryPenalty(const GeometryPenaltyInput& in, double resolutionWeight);

// The Hermite smoothstep of distance / width clamped to [0, 1]; 1 when width <= 0 (no feather).
double featherFactor(double distance, double width);
// The mask factor from the mask averaged over the feather width: clamp(2 m - 1, 0, 1).
double maskFeather(double averagedMask);

}  // namespace hv::ibr
