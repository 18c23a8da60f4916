// The demo city's orthophoto: a top-down ray cast of its ground truth (demo_internal.h).
#include <algorithm>
#include <cmath>

#include "hv/demo/demo_internal.h"

namespace hv::demo::detail {

Orthophoto orthophotoFromAbove(const World& world, const RayCaster& truthCaster, int maxSide) {
  const Heightfield& dtm = world.dtm;
  const glm::dvec2 a = dtm.samplePosition(0, 0), b = dtm.samplePosition(dtm.cols - 1, dtm.rows - 1);
  Orthophoto o;
  o.minX = std::min(a.x, b.x), o.maxX = std::max(a.x, b.x);
  o.minY = std::min(a.y, b.y), o.maxY = std::max(a.y, b.y);
  const double w = o.maxX - o.minX, h = o.maxY - o.minY;
  const double pixel = std::max(w, h) / std::max(maxSide, 1);
  o.width = std::max(1, int(std::lround(w / pixel)));
  o.height = std::max(1, int(std::lround(h / pixel)));
  o.rgba.assign(std::size_t(o.width) * o.height * 4, 0);
  const double top = world.truth.mesh.bounds().hi.z + 10.0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const glm::dvec3 from(o.minX + (x + 0.5) * w / o.width, o.maxY - (y + 0.5) * h / o.height, top);
      const auto hit = truthCaster.intersect(from, {0.0, 0.0, -1.0});
      if (!hit) continue;
      const glm::dvec3 c = shade(world, *hit);
      std::uint8_t* p = &o.rgba[(std::size_t(y) * o.width + x) * 4];
      for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(std::lround(255.0 * std::clamp(c[k], 0.0, 1.0)));
      p[3] = 255;
    }
  return o;
}

}  // namespace hv::demo::detail
