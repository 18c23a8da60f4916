#include "hv/scene/orthophoto.h"

#include <algorithm>
#include <cmath>

namespace hv {

glm::dvec2 orthophotoTexCoord(const Orthophoto& o, double x, double y) {
  return {(x - o.minX) / (o.maxX - o.minX), (o.maxY - y) / (o.maxY - o.minY)};
}

OrthophotoAffine orthophotoAffine(const Orthophoto& o, const glm::dvec3& origin) {
  const double sx = 1.0 / (o.maxX - o.minX), sy = 1.0 / (o.maxY - o.minY);
  OrthophotoAffine a;
  a.uRow = {sx, 0.0, (origin.x - o.minX) * sx};
  a.vRow = {0.0, -sy, (o.maxY - origin.y) * sy};
  return a;
}

glm::dvec4 sampleOrthophoto(const Orthophoto& o, glm::dvec2 uv) {
  if (o.empty()) return glm::dvec4(0.0);
  // GL_LINEAR: the four texels around uv * size - 0.5, each index clamped to the edge.
  const double fx = uv.x * o.width - 0.5, fy = uv.y * o.height - 0.5;
  const double x0 = std::floor(fx), y0 = std::floor(fy);
  const double ax = fx - x0, ay = fy - y0;
  auto texel = [&](double xi, double yi) {
    const int x = std::clamp(int(xi), 0, o.width - 1), y = std::clamp(int(yi), 0, o.height - 1);
    const std::uint8_t* p = &o.rgba[(std::size_t(y) * std::size_t(o.width) + std::size_t(x)) * 4];
    return glm::dvec4(p[0], p[1], p[2], p[3]) / 255.0;
  };
  return glm::mix(glm::mix(texel(x0, y0), texel(x0 + 1, y0), ax),
                  glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), ax), ay);
}

}  // namespace hv
