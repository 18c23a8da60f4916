// View-dependent blending weights (Brédif 2013, eq. 1-2; docs/design.md, step 5).
//   f(d) = 1 / (sigma^2 + d^2),   w_i = f(d_i) - f(d_{K+1}),   i = 1..K
// with d_i the distances from the view centre to the camera centres, sorted ascending, and
// f(d_{K+1}) = 0 when there are K or fewer candidates. When the K-th and (K+1)-th images swap,
// w_K = 0, so the blend does not pop where other images also cover the pixel.
#pragma once

#include <vector>

namespace hv::ibr {

double blendFalloff(double distance, double sigma);

// `sortedDistances` ascending, at least the K+1 nearest when there are that many. Returns K
// weights (fewer when fewer candidates), each >= 0.
std::vector<double> blendWeights(const std::vector<double>& sortedDistances, int k, double sigma);

}  // namespace hv::ibr
