#include "hv/scene/mesh.h"

namespace hv {

void Mesh::append(const Mesh& other) {
  const auto base = static_cast<std::uint32_t>(positions.size());
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  const bool tags = !triangleTags.empty() || !other.triangleTags.empty();
  if (tags) triangleTags.resize(triangles.size(), 0);
  for (const auto& t : other.triangles) triangles.push_back(t + glm::uvec3(base));
  if (tags) {
    if (other.triangleTags.empty()) triangleTags.resize(triangles.size(), 0);
    else triangleTags.insert(triangleTags.end(), other.triangleTags.begin(), other.triangleTags.end());
  }
}

Aabb Mesh::bounds() const {
  Aabb b;
  for (const auto& p : positions) b.extend(p);
  return b;
}

double Mesh::signedVolume() const {
  double v = 0.0;
  for (const auto& t : triangles) v += glm::dot(positions[t.x], glm::cross(positions[t.y], positions[t.z]));
  return v / 6.0;
}

double Mesh::area() const {
  double a = 0.0;
  for (const auto& t : triangles)
    a += 0.5 * glm::length(glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]));
  return a;
}

}  // namespace hv
