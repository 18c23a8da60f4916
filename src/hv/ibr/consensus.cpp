#include "hv/ibr/consensus.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hv::ibr {

void consensusWeights(std::span<const glm::dvec3> colour, std::span<double> weight, double spread) {
  const size_t n = std::min({colour.size(), weight.size(), size_t(kMaxConsensusSamples)});
  if (!(spread > 0.0)) return;
  std::array<std::array<double, kMaxConsensusSamples>, 3> channel{};
  size_t m = 0;
  for (size_t i = 0; i < n; ++i)
    if (weight[i] > 0.0) {
      for (int c = 0; c < 3; ++c) channel[c][m] = colour[i][c];
      ++m;
    }
  if (m < 3) return;
  glm::dvec3 mode(0.0);
  for (int c = 0; c < 3; ++c) {
    std::sort(channel[c].begin(), channel[c].begin() + m);
    mode[c] = m % 2 ? channel[c][m / 2] : 0.5 * (channel[c][m / 2 - 1] + channel[c][m / 2]);
  }
  // The kernel relative to the sample nearest the mode, exp(-k (d_i^2 - d_min^2)): 1 for that
  // sample, so it never underflows to nothing.
  const double k = 0.5 / (spread * spread);
  std::array<double, kMaxConsensusSamples> g{};
  const auto kernels = [&] {
    std::array<double, kMaxConsensusSamples> d2{};
    double least = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec3 d = colour[i] - mode;
      d2[i] = glm::dot(d, d);
      if (weight[i] > 0.0) least = std::min(least, d2[i]);
    }
    for (size_t i = 0; i < n; ++i) g[i] = weight[i] > 0.0 ? std::exp(-k * (d2[i] - least)) : 0.0;
  };
  for (int step = 0; step < 3; ++step) {
    kernels();
    glm::dvec3 sum(0.0);
    double total = 0.0;
    for (size_t i = 0; i < n; ++i) {
      sum += weight[i] * g[i] * colour[i];
      total += weight[i] * g[i];
    }
    mode = sum / total;  // total >= the nearest sample's weight > 0
  }
  kernels();
  for (size_t i = 0; i < n; ++i)
    if (weight[i] > 0.0) weight[i] *= g[i];
}

}  // namespace hv::ibr
