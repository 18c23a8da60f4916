// Mesh-building helpers of the demo city (quads, boxes, cars) and Layer bookkeeping.
#include "hv/demo/demo_internal.h"

namespace hv::demo {

void Layer::append(const Layer& other) {
  const auto surfaceBase = static_cast<std::uint32_t>(surfaces.size());
  mesh.append(other.mesh);
  surfaces.insert(surfaces.end(), other.surfaces.begin(), other.surfaces.end());
  for (std::uint32_t s : other.surfaceOf) surfaceOf.push_back(s + surfaceBase);
}

namespace detail {

std::uint32_t addSurface(Layer& layer, const Surface& s) {
  layer.surfaces.push_back(s);
  return static_cast<std::uint32_t>(layer.surfaces.size() - 1);
}

void addTriangle(Layer& layer, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 outward,
                 std::uint32_t surface) {
  if (glm::dot(glm::cross(b - a, c - a), outward) < 0.0) std::swap(b, c);
  const auto base = static_cast<std::uint32_t>(layer.mesh.positions.size());
  layer.mesh.positions.insert(layer.mesh.positions.end(), {a, b, c});
  layer.mesh.triangles.emplace_back(base, base + 1, base + 2);
  layer.mesh.triangleTags.push_back(static_cast<std::uint32_t>(layer.surfaces[surface].material));
  layer.surfaceOf.push_back(surface);
}

void addQuad(Layer& layer, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d, glm::dvec3 outward,
             std::uint32_t surface) {
  // Four shared vertices: the two triangles of a quad must share their diagonal exactly so that no
  // ray slips between them.
  const glm::dvec3 n = glm::cross(b - a, c - a) + glm::cross(c - a, d - a);
  if (glm::dot(n, outward) < 0.0) std::swap(b, d);
  const auto base = static_cast<std::uint32_t>(layer.mesh.positions.size());
  layer.mesh.positions.insert(layer.mesh.positions.end(), {a, b, c, d});
  layer.mesh.triangles.emplace_back(base, base + 1, base + 2);
  layer.mesh.triangles.emplace_back(base, base + 2, base + 3);
  const auto tag = static_cast<std::uint32_t>(layer.surfaces[surface].material);
  layer.mesh.triangleTags.insert(layer.mesh.triangleTags.end(), {tag, tag});
  layer.surfaceOf.insert(layer.surfaceOf.end(), {surface, surface});
}

void addBox(Layer& layer, glm::dvec3 c, glm::dvec3 ax, glm::dvec3 ay, glm::dvec3 az, glm::dvec3 h,
            std::uint32_t surface) {
  const glm::dvec3 axes[3] = {ax * h.x, ay * h.y, az * h.z};
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 n = axes[k], e1 = axes[(k + 1) % 3], e2 = axes[(k + 2) % 3];
    for (double side : {-1.0, 1.0}) {
      const glm::dvec3 f = c + side * n;
      addQuad(layer, f - e1 - e2, f + e1 - e2, f + e1 + e2, f - e1 + e2, side * n, surface);
    }
  }
}

void addCar(Layer& layer, glm::dvec3 base, glm::dvec2 dir2, glm::dvec3 color) {
  // Dimensions of a small European car (metres); enough detail for a moving occluder.
  const glm::dvec3 along(glm::normalize(dir2), 0.0), side(-along.y, along.x, 0.0), up(0.0, 0.0, 1.0);
  Surface body{Material::CarBody};
  body.tint = color;
  body.origin = base;
  body.u = along;
  const std::uint32_t sBody = addSurface(layer, body);
  Surface glass = body;
  glass.material = Material::CarGlass;
  const std::uint32_t sGlass = addSurface(layer, glass);
  Surface wheel = body;
  wheel.material = Material::CarWheel;
  const std::uint32_t sWheel = addSurface(layer, wheel);
  addBox(layer, base + 0.65 * up, along, side, up, {2.1, 0.87, 0.35}, sBody);
  addBox(layer, base + 1.25 * up - 0.2 * along, along, side, up, {1.15, 0.78, 0.25}, sGlass);
  for (double a : {-1.35, 1.35})
    for (double s : {-0.8, 0.8})
      addBox(layer, base + 0.33 * up + a * along + s * side, along, side, up, {0.32, 0.11, 0.32}, sWheel);
}

}  // namespace detail
}  // namespace hv::demo
