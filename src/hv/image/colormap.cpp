#include "hv/image/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace hv {

Image8 colorMapCounts(const Image16& counts) {
  // Control points of a viridis-like ramp.
  static const std::array<std::array<double, 3>, 5> ramp = {
      {{0.27, 0.00, 0.33}, {0.23, 0.32, 0.55}, {0.13, 0.57, 0.55}, {0.37, 0.79, 0.38}, {0.99, 0.91, 0.14}}};
  int maxCount = 1;
  for (auto v : counts.data) maxCount = std::max<int>(maxCount, v);
  Image8 out(counts.width, counts.height, 3, 0);
  for (int y = 0; y < counts.height; ++y)
    for (int x = 0; x < counts.width; ++x) {
      const int c = counts.at(x, y, 0);
      if (c == 0) continue;
      const double t = double(c) / maxCount * (ramp.size() - 1);
      const size_t i = std::min(size_t(t), ramp.size() - 2);
      const double f = t - double(i);
      for (int k = 0; k < 3; ++k)
        out.at(x, y, k) = std::uint8_t(std::lround(255.0 * ((1 - f) * ramp[i][k] + f * ramp[i + 1][k])));
    }
  return out;
}

}  // namespace hv
