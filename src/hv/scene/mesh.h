// Triangle meshes in world coordinates (double precision). The renderer converts them to the
// render frame (world minus the scene origin, float) when it uploads them.
// Orientation: triangles are counter-clockwise seen from outside, so normals point outwards
// (up for terrain and roofs, away from the building for walls).
#pragma once

#include "hv/math/aabb.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <vector>

namespace hv {

struct Mesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::uvec3> triangles;
  // One tag per triangle (e.g. the building's feature index, or a material id in the demo city's
  // ground truth); empty when the mesh carries none.
  std::vector<std::uint32_t> triangleTags;

  bool empty() const { return triangles.empty(); }
  void append(const Mesh& other);
  Aabb bounds() const;
  // Signed volume (divergence theorem); positive for a closed outward-oriented mesh.
  double signedVolume() const;
  double area() const;
};

}  // namespace hv
