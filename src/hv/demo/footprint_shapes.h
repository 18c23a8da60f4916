// Footprint shapes of the demo city's lots: which cells of a 3 x 3 lot grid a building covers, and
// the boundary rings of such a cell set; point-in-polygon and signed area for the rings.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <vector>

namespace hv::demo::detail {

// Even-odd point in polygon over all rings (outer and holes).
bool insideRings(const std::vector<std::vector<glm::dvec2>>& rings, glm::dvec2 p);
double signedArea(const std::vector<glm::dvec2>& ring);

// Footprint shapes on a 3 x 3 cell grid in lot coordinates (u along the street, v into the block;
// row 0 touches the street). Chosen so that no two cells touch by a corner only (no pinched rings).
using CellSet = std::array<std::array<bool, 3>, 3>;  // [col][row]
enum class Shape { Rect, L, LMirror, U, T, NotchCorner, NotchBack, Step, Courtyard, Count };
CellSet cellsOf(Shape s);

// Boundary rings of a cell set, as grid-vertex indices, with the inside on the left; collinear
// vertices removed. Outer rings come out counter-clockwise, holes clockwise (in the grid frame).
std::vector<std::vector<glm::ivec2>> traceRings(const CellSet& cells);

}  // namespace hv::demo::detail
