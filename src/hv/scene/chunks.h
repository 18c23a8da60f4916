// The spatial organisation of a point cloud for drawing: at load
// time the points are reordered into chunks, the leaves of a k-d tree whose nodes are split at
// the median of their longest axis until at most `maxPointsPerChunk` points remain, so chunks hold
// about the same number of points wherever the density is (airborne or mobile mapping). Inside a
// chunk the points are shuffled, so the first k points of a chunk are a uniform random subsample
// of it: a frame draws a prefix of each visible chunk, as many points as the budget gives it.
#pragma once

#include "hv/camera/camera.h"
#include "hv/scene/point_cloud.h"

#include <cstdint>
#include <vector>

namespace hv {

struct ChunkSettings {
  std::uint32_t maxPointsPerChunk = 16384;
  std::uint64_t seed = 1;  // of the shuffle inside chunks (deterministic)
};

// Reorders every attribute of `cloud` chunk by chunk and fills cloud.chunks (bounds, first,
// count). The chunks cover [0, size()) in order.
void organizeChunks(PointCloud& cloud, const ChunkSettings& settings = {});

// A uniform subsample of at most `maxPoints` points (all of them when the cloud has no more): a
// prefix of each chunk, which is a uniform subsample of that chunk since its points are shuffled,
// the prefixes' lengths proportional to the chunks' counts (cumulative rounding, so they add up to
// exactly min(maxPoints, size())). The result is organised: its chunks are those prefixes, in the
// same order, with their bounds recomputed (chunks given no point are dropped). A cloud that is
// not organised yet is organised (a copy, default settings) first.
PointCloud subsampleChunks(const PointCloud& cloud, std::size_t maxPoints);

// How many points of a chunk a frame draws: points [first, first + count) of chunk `chunk`.
struct ChunkDraw {
  std::uint32_t chunk = 0;
  std::uint32_t count = 0;
};

// The chunks a view sees and how many points of each to draw within `pointBudget` points.
// Visible: the chunk's box meets the view's pinhole frustum (hv::sceneFrustum, truncated at
// the depth range of the chunks' bounds) by the separating-axis test. Share: proportional to the
// chunk's projected area in pixels, pi (f r / max(d, r))^2 with r its bounding-sphere radius and
// d the distance of its centre to the camera, capped at the image area, and never more than the
// chunk holds (the leftover goes to the others: water-filling), so near and large chunks get
// more points and the screen density is about even. Nearest chunk first; chunks given no point are
// left out. With a budget at least the visible points, every visible point is drawn.
std::vector<ChunkDraw> selectChunks(const PointCloud& cloud, const Camera& view, std::uint64_t pointBudget);

}  // namespace hv
