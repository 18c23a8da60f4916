#include "hv/image/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace hv {

glm::dvec3 colorRamp(double t) {
  // Control points of a viridis-like ramp, evenly spaced in t.
  static const std::array<glm::dvec3, 5> ramp = {{{0.27, 0.00, 0.33},
                                                   {0.23, 0.32, 0.55},
                                                   {0.13, 0.57, 0.55},
                                                   {0.37, 0.79, 0.38},
                                                   {0.99, 0.91, 0.14}}};
  const double s = std::clamp(t, 0.0, 1.0) * double(ramp.size() - 1);
  const size_t i = std::min(size_t(s), ramp.size() - 2);
  const double f = s - double(i);
  return (1.0 - f) * ramp[i] + f * ramp[i + 1];
}

Image8 colorMapCounts(const Image16& counts) {
  int maxCount = 1;
  for (auto v : counts.data) maxCount = std::max<int>(maxCount, v);
  Image8 out(counts.width, counts.height, 3, 0);
  for (int y = 0; y < counts.height; ++y)
    for (int x = 0; x < counts.width; ++x) {
      const int c = counts.at(x, y, 0);
      if (c == 0) continue;
      const glm::dvec3 rgb = colorRamp(double(c) / maxCount);
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = std::uint8_t(std::lround(255.0 * rgb[k]));
    }
  return out;
}

}  // namespace hv
