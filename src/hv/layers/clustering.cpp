#include "hv/layers/clustering.h"

#include <algorithm>

namespace hv::layers {

PixelBox unionBox(const PixelBox& a, const PixelBox& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

std::int64_t powerOfTwoAtLeast(std::int64_t n) {
  std::int64_t p = 1;
  while (p < n) p *= 2;
  return p;
}

std::int64_t powerOfTwoArea(const PixelBox& box) {
  if (box.empty()) return 0;
  return powerOfTwoAtLeast(box.width()) * powerOfTwoAtLeast(box.height());
}

std::vector<BoxCluster> clusterBoxes(const std::vector<PixelBox>& boxes) {
  std::vector<BoxCluster> clusters;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    if (!boxes[i].empty()) clusters.push_back({boxes[i], {i}});
  for (;;) {
    std::int64_t bestSaving = 0;
    std::size_t bi = 0, bj = 0;
    for (std::size_t i = 0; i < clusters.size(); ++i) {
      const std::int64_t ai = powerOfTwoArea(clusters[i].box);
      for (std::size_t j = i + 1; j < clusters.size(); ++j) {
        const std::int64_t saving =
            ai + powerOfTwoArea(clusters[j].box) - powerOfTwoArea(unionBox(clusters[i].box, clusters[j].box));
        if (saving > bestSaving) bestSaving = saving, bi = i, bj = j;
      }
    }
    if (bestSaving <= 0) break;  // A12 >= A1 + A2 for every pair: the fixpoint
    BoxCluster& into = clusters[bi];
    into.box = unionBox(into.box, clusters[bj].box);
    into.members.insert(into.members.end(), clusters[bj].members.begin(), clusters[bj].members.end());
    std::sort(into.members.begin(), into.members.end());
    clusters.erase(clusters.begin() + std::ptrdiff_t(bj));
  }
  std::sort(clusters.begin(), clusters.end(),
            [](const BoxCluster& a, const BoxCluster& b) { return a.members.front() < b.members.front(); });
  return clusters;
}

}  // namespace hv::layers
