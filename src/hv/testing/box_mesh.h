// A closed axis-aligned box as a mesh, for the tests of what sorts, peels or culls objects
// (layers/native/scene_objects_test.cpp, render/layer_peeling_gltest.cpp).
#pragma once

#include "hv/scene/mesh.h"

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

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

// A stick from a to b (axis not vertical) with a rectangular cross-section, 2 halfWidth across
// (horizontal) by 2 halfHeight: `segments` equal segments along the axis, each side a quad of two
// triangles per segment, and the two end caps; closed, outward, every triangle tagged `tag`.
inline Mesh taggedStick(glm::dvec3 a, glm::dvec3 b, double halfWidth, double halfHeight, int segments,
                        std::uint32_t tag) {
  const glm::dvec3 d = glm::normalize(b - a);
  const glm::dvec3 side = glm::normalize(glm::cross(d, glm::dvec3(0, 0, 1)));
  const glm::dvec3 up = glm::cross(side, d);
  const std::array<glm::dvec3, 4> corner = {-halfWidth * side - halfHeight * up, halfWidth * side - halfHeight * up,
                                            halfWidth * side + halfHeight * up, -halfWidth * side + halfHeight * up};
  Mesh m;
  for (int k = 0; k <= segments; ++k)
    for (const glm::dvec3& c : corner) m.positions.push_back(a + (b - a) * (double(k) / segments) + c);
  // Adds triangle (i, j, l) facing away from the point `inside`.
  auto add = [&](unsigned i, unsigned j, unsigned l, glm::dvec3 inside) {
    const glm::dvec3 n = glm::cross(m.positions[j] - m.positions[i], m.positions[l] - m.positions[i]);
    if (glm::dot(n, m.positions[i] - inside) < 0.0) std::swap(j, l);
    m.triangles.push_back({i, j, l});
  };
  for (int k = 0; k < segments; ++k) {
    const glm::dvec3 mid = a + (b - a) * ((k + 0.5) / segments);
    for (unsigned c = 0; c < 4; ++c) {
      const unsigned p0 = unsigned(4 * k) + c, p1 = unsigned(4 * k) + (c + 1) % 4, q0 = p0 + 4, q1 = p1 + 4;
      add(p0, p1, q1, mid);
      add(p0, q1, q0, mid);
    }
  }
  const unsigned last = unsigned(4 * segments);
  add(0, 1, 2, b);
  add(0, 2, 3, b);
  add(last, last + 1, last + 2, a);
  add(last, last + 2, last + 3, a);
  m.triangleTags.assign(m.triangles.size(), tag);
  return m;
}

// Three sticks overlapping in a ring, as seen from above (the "three sticks" no order of whole
// objects can draw): stick i (tag i) runs along the side V_i V_(i+1) of the equilateral triangle
// inscribed in the circle of radius 10 m about the origin (V_i at 90 + 120 i degrees), 3 m past
// both corners, rising from 2 m at V_i to 6 m at V_(i+1) (its axis); 2 m wide, 1 m thick. At corner
// V_(i+1) stick i passes 3 m above stick i + 1 (mod 3): each hides part of the next.
inline Mesh threeSticks(int segments) {
  const double pi = 3.14159265358979323846, r = 10.0, extend = 3.0;
  Mesh m;
  for (std::uint32_t i = 0; i < 3; ++i) {
    auto corner = [&](std::uint32_t k) {
      const double t = (90.0 + 120.0 * double(k % 3)) * pi / 180.0;
      return glm::dvec3(r * std::cos(t), r * std::sin(t), 0.0);
    };
    const glm::dvec3 v0 = corner(i) + glm::dvec3(0, 0, 2), v1 = corner(i + 1) + glm::dvec3(0, 0, 6);
    const glm::dvec3 along = (v1 - v0) * (extend / glm::length(glm::dvec2(v1 - v0)));  // 3 m across the ground
    m.append(taggedStick(v0 - along, v1 + along, 1.0, 0.5, segments, i));
  }
  return m;
}

}  // namespace hv::testing
