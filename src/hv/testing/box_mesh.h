// A closed axis-aligned box as a mesh, for the tests of what sorts, peels or culls objects
// (layers/native/scene_objects_test.cpp, render/layer_peeling_gltest.cpp).
#pragma once

#include "hv/scene/mesh.h"

#include <glm/glm.hpp>

#include <cstdint>

namespace hv::testing {

// The box [lo, hi]: 8 corners (corner i takes hi on axis k when bit k of i is set), 12 triangles
// counter-clockwise seen from outside (hv/scene/mesh.h), every one tagged `tag`.
inline Mesh taggedBox(glm::dvec3 lo, glm::dvec3 hi, std::uint32_t tag) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  const unsigned quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  m.triangleTags.assign(m.triangles.size(), tag);
  return m;
}

}  // namespace hv::testing
