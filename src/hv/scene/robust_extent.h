// The extent of a scene without its outliers (docs/reliability.md): one absurd coordinate (a
// camera at 1e9, an unflagged no-data cell of 1e38, an inf vertex, a LAS offset of 1e15) would
// otherwise move the render origin and stretch every depth range until the picture is black.
#pragma once

#include "hv/scene/scene.h"

#include <string>
#include <vector>

namespace hv {

struct RobustExtent {
  Aabb bounds;    // geometry and camera centres inside `accept` (empty when there are none)
  Aabb geometry;  // the same for the geometry alone (terrain, buildings, mesh, points)
  Aabb accept;    // the box a coordinate must fall in to count (empty: no data)
  // One sentence per outlying camera or source: "camera 'ID': centre (...) ..." or
  // "terrain: 3 vertices ...", each saying what it is left out of.
  std::vector<std::string> outliers;
};

// The bulk of the data is the box between the 5th and 95th percentiles of every coordinate
// (camera centres, vertices, point-chunk corners); a coordinate counts when it lies within
// kOutlierMargin times that box's largest side (at least kOutlierMinSize) of it, and non-finite
// ones never do. Linear in the data (vertices are sampled, at most 65536 per mesh for the
// percentiles).
inline constexpr double kOutlierMargin = 100.0;
inline constexpr double kOutlierMinSize = 10.0;  // metres: a single building still has a margin
RobustExtent robustExtent(const Scene& scene);

}  // namespace hv
