// Control points of a photograph: a pixel of the photograph and the world point it shows.
// The file format `histoview pose --gcp` reads (docs/pose.md): CSV with a header naming at
// least the columns u, v, x, y, z (any order; other columns, such as `id`, are kept as labels or
// ignored); u, v in pixels with the top-left-corner origin (as everywhere in histoview), x, y, z
// in the scene CRS. Blank lines and lines starting with '#' are skipped.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace hv::pose {

struct ControlPoint {
  glm::dvec2 pixel{0.0};
  glm::dvec3 world{0.0};
  std::string label;  // the `id` (or `label`, `name`) column, else "line N"
};

// Parses the CSV. Throws hv::InputError naming `source`, the line, the column and what was
// expected (a missing column, a value that is not a finite number, a row of the wrong width).
std::vector<ControlPoint> parseControlPoints(std::string_view text, const std::string& source);

}  // namespace hv::pose
