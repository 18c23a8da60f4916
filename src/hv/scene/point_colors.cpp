#include "hv/scene/point_colors.h"

#include <algorithm>

namespace hv {

glm::u8vec3 classColor(std::uint8_t c) {
  switch (c) {
    case 0:
    case 1: return {170, 170, 170};  // never classified, unclassified
    case 2: return {176, 136, 96};   // ground
    case 3: return {150, 210, 110};  // low vegetation
    case 4: return {90, 180, 70};    // medium vegetation
    case 5: return {40, 130, 40};    // high vegetation
    case 6: return {220, 90, 70};    // building
    case 7: return {255, 0, 255};    // low point (noise)
    case 9: return {60, 120, 220};   // water
    case 10: return {140, 110, 140}; // rail
    case 11: return {100, 100, 100}; // road surface
    case 17: return {210, 200, 110}; // bridge deck
    default: {
      const std::uint32_t h = std::uint32_t(c) * 2654435761u;
      return {std::uint8_t(64 + (h >> 8) % 192), std::uint8_t(64 + (h >> 16) % 192), std::uint8_t(64 + (h >> 24) % 192)};
    }
  }
}

std::vector<glm::u8vec4> pointDisplayColors(const PointCloud& cloud, PointColorMode mode) {
  const PointFields f = cloud.fields();
  if (mode == PointColorMode::Auto)
    mode = f.rgb ? PointColorMode::Rgb
                 : f.classification ? PointColorMode::Classification
                                    : f.intensity ? PointColorMode::Intensity : PointColorMode::Rgb;
  std::uint16_t lo = 0, hi = 65535;
  if (mode == PointColorMode::Intensity && f.intensity && !cloud.intensity.empty()) {
    std::vector<std::uint16_t> sorted = cloud.intensity;
    const size_t a = sorted.size() * 2 / 100, b = std::min(sorted.size() - 1, sorted.size() * 98 / 100);
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(a), sorted.end());
    lo = sorted[a];
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(b), sorted.end());
    hi = std::max<std::uint16_t>(sorted[b], std::uint16_t(lo + 1));
  }
  std::vector<glm::u8vec4> out(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const std::uint8_t cls = f.classification ? cloud.classification[i] : 1;
    glm::u8vec3 rgb(170);
    switch (mode) {
      case PointColorMode::Rgb:
        if (f.rgb) rgb = glm::u8vec3(cloud.rgb[i] / std::uint16_t(257));
        break;
      case PointColorMode::Classification: rgb = classColor(cls); break;
      case PointColorMode::Intensity:
        if (f.intensity) {
          const double t = std::clamp((double(cloud.intensity[i]) - lo) / double(hi - lo), 0.0, 1.0);
          rgb = glm::u8vec3(std::uint8_t(40 + 215 * t));
        }
        break;
      case PointColorMode::Auto: break;
    }
    out[i] = glm::u8vec4(rgb, cls);
  }
  return out;
}

}  // namespace hv
