#include "hv/ibr/weights.h"

#include <algorithm>
#include <cassert>

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

}  // namespace hv::ibr
