#include "hv/scene/chunks.h"

#include "hv/camera/frustum.h"
#include "hv/scene/point_normals.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <numeric>

namespace hv {
namespace {

// SplitMix64 (Steele, Lea & Flood 2014): a fixed sequence for a seed, unlike std:: engines'
// distributions, so the chunk order is the same on every platform.
std::uint64_t splitMix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// A box as the eight corners of a (degenerate) frustum, in the corner order of
// hv::frustumCorners, so that hv::frustaOverlap tests it against a view frustum.
hv::FrustumCorners boxCorners(const Aabb& b) {
  // Flat chunks (a horizontal patch of ground) would have zero-length edges: give the box a
  // millimetre of thickness so that every face normal exists.
  const glm::dvec3 lo = b.lo - 0.001, hi = b.hi + 0.001;
  return {glm::dvec3{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
          glm::dvec3{lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
}

}  // namespace

void organizeChunks(PointCloud& cloud, const ChunkSettings& settings) {
  assert(cloud.size() < (std::size_t(1) << 32) && "organizeChunks: at most 2^32 - 1 points");
  const std::uint32_t maxPoints = std::max<std::uint32_t>(settings.maxPointsPerChunk, 1);
  const std::uint32_t n = std::uint32_t(cloud.size());
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);

  // k-d tree, depth first: the leaves come out left to right, so each is a contiguous range.
  struct Range {
    std::uint32_t begin, end;
  };
  std::vector<Range> leaves, stack{{0, n}};
  while (!stack.empty()) {
    const Range r = stack.back();
    stack.pop_back();
    if (r.end - r.begin <= maxPoints) {
      if (r.end > r.begin) leaves.push_back(r);
      continue;
    }
    Aabb box;
    for (std::uint32_t i = r.begin; i < r.end; ++i) box.extend(cloud.positions[order[i]]);
    const glm::dvec3 size = box.size();
    const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    const std::uint32_t mid = r.begin + (r.end - r.begin) / 2;
    std::nth_element(order.begin() + r.begin, order.begin() + mid, order.begin() + r.end,
                     [&](std::uint32_t a, std::uint32_t b) { return cloud.positions[a][axis] < cloud.positions[b][axis]; });
    stack.push_back({mid, r.end});  // popped second: the left half comes first
    stack.push_back({r.begin, mid});
  }

  // Fisher-Yates inside each chunk: any prefix is a uniform random subsample.
  std::uint64_t state = settings.seed;
  for (const Range& r : leaves)
    for (std::uint32_t i = r.end - 1; i > r.begin; --i) {
      const std::uint32_t j = r.begin + std::uint32_t(splitMix64(state) % std::uint64_t(i - r.begin + 1));
      std::swap(order[i], order[j]);
    }

  cloud.permute(order);
  cloud.chunks.reserve(leaves.size());
  for (const Range& r : leaves) {
    PointChunk c;
    c.first = r.begin;
    c.count = r.end - r.begin;
    for (std::uint32_t i = r.begin; i < r.end; ++i) c.bounds.extend(cloud.positions[i]);
    cloud.chunks.push_back(c);
  }
}

PointCloud subsampleChunks(const PointCloud& cloud, std::size_t maxPoints) {
  if (cloud.size() <= maxPoints) return cloud;
  if (cloud.chunks.empty()) {
    PointCloud organised = cloud;
    organizeChunks(organised);
    return subsampleChunks(organised, maxPoints);
  }
  PointFields fields = cloud.fields();
  // Deferred normals are estimated over the whole cloud, then subsampled with it.
  const std::vector<glm::vec3>& normals = pointNormals(cloud);
  fields.normals = !normals.empty();
  PointCloud out;
  out.sourcePath = cloud.sourcePath;
  out.crs = cloud.crs;
  out.resize(0, fields);
  auto take = [&](std::uint32_t i) {
    out.positions.push_back(cloud.positions[i]);
    if (fields.intensity) out.intensity.push_back(cloud.intensity[i]);
    if (fields.classification) out.classification.push_back(cloud.classification[i]);
    if (fields.rgb) out.rgb.push_back(cloud.rgb[i]);
    if (fields.normals) out.normals.push_back(normals[i]);
  };
  // Chunk c keeps floor(N S_c / total) - floor(N S_{c-1} / total) points, S_c the count of the
  // chunks up to c: within one point of its share, and N in all. N < total < 2^32, so the
  // products fit in 64 bits.
  const std::uint64_t total = cloud.size(), n = maxPoints;
  std::uint64_t cumulative = 0, taken = 0;
  for (const PointChunk& c : cloud.chunks) {
    cumulative += c.count;
    const std::uint64_t upTo = n * cumulative / total;
    const auto keep = std::uint32_t(upTo - taken);
    taken = upTo;
    if (keep == 0) continue;
    PointChunk chunk;
    chunk.first = std::uint32_t(out.positions.size());
    chunk.count = keep;
    for (std::uint32_t i = c.first; i < c.first + keep; ++i) {
      take(i);
      chunk.bounds.extend(cloud.positions[i]);
    }
    out.chunks.push_back(chunk);
  }
  return out;
}

std::vector<ChunkDraw> selectChunks(const PointCloud& cloud, const Camera& view, std::uint64_t pointBudget) {
  Aabb all;
  for (const PointChunk& c : cloud.chunks) all.extend(c.bounds);
  if (all.empty()) return {};
  const hv::FrustumCorners frustum = hv::sceneFrustum(view, all);
  const double focal = std::max(view.focal.x, view.focal.y);
  const double imageArea = double(view.width) * double(view.height);

  struct Candidate {
    std::uint32_t chunk;
    double distance, weight;
    std::uint64_t points;
  };
  std::vector<Candidate> visible;
  for (std::uint32_t i = 0; i < cloud.chunks.size(); ++i) {
    const PointChunk& c = cloud.chunks[i];
    if (c.count == 0 || !hv::frustaOverlap(frustum, boxCorners(c.bounds))) continue;
    const double r = std::max(0.5 * glm::length(c.bounds.size()), 1e-6);
    const double d = glm::length(c.bounds.center() - view.center);
    const double px = focal * r / std::max(d, r);
    // Degenerate input (infinite extents) must not poison the shares: such a chunk gets a token weight.
    const double area = std::numbers::pi * px * px;
    visible.push_back({i, d, std::isfinite(area) && area > 0.0 ? std::min(area, imageArea) : 1e-12, c.count});
  }

  // Water-filling: find lambda with sum_c min(n_c, lambda w_c) = budget. Chunks that saturate
  // first (small n_c / w_c) take all their points; the rest share what is left by weight.
  std::vector<std::uint32_t> bySaturation(visible.size());
  std::iota(bySaturation.begin(), bySaturation.end(), 0u);
  std::sort(bySaturation.begin(), bySaturation.end(), [&](std::uint32_t a, std::uint32_t b) {
    return double(visible[a].points) * visible[b].weight < double(visible[b].points) * visible[a].weight;
  });
  std::uint64_t visiblePoints = 0;
  double weightLeft = 0.0;
  for (const Candidate& c : visible) {
    weightLeft += c.weight;
    visiblePoints += c.points;
  }
  double budgetLeft = double(std::min(pointBudget, visiblePoints));  // exact in a double below 2^53
  std::vector<std::uint64_t> draw(visible.size(), 0);
  for (std::uint32_t k : bySaturation) {
    const Candidate& c = visible[k];
    // The last chunk takes the rest; the tolerance keeps rounding from cutting a point off a
    // chunk that the budget covers.
    const double share = weightLeft <= c.weight ? budgetLeft : budgetLeft * (c.weight / weightLeft);
    draw[k] = double(c.points) <= share * (1.0 + 1e-12) ? std::min<std::uint64_t>(c.points, std::uint64_t(budgetLeft))
                                                          : std::uint64_t(std::floor(share));
    budgetLeft = std::max(budgetLeft - double(draw[k]), 0.0);
    weightLeft -= c.weight;
  }

  std::vector<std::uint32_t> byDistance(visible.size());
  std::iota(byDistance.begin(), byDistance.end(), 0u);
  std::sort(byDistance.begin(), byDistance.end(),
            [&](std::uint32_t a, std::uint32_t b) { return visible[a].distance < visible[b].distance; });
  std::vector<ChunkDraw> out;
  for (std::uint32_t k : byDistance)
    if (draw[k] > 0) out.push_back({visible[k].chunk, std::uint32_t(draw[k])});
  return out;
}

}  // namespace hv
