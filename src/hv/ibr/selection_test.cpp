#include "hv/ibr/selection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace hv::ibr {
namespace {

TEST(CameraIndex, NearestMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-500.0, 500.0);
  std::vector<glm::dvec3> pts;
  for (int i = 0; i < 2000; ++i) pts.push_back({651000.0 + u(rng), 6862000.0 + u(rng), 40.0 + 0.05 * u(rng)});
  CameraIndex index(pts);
  for (int q = 0; q < 20; ++q) {
    const glm::dvec3 query(651000.0 + u(rng), 6862000.0 + u(rng), 40.0);
    std::vector<std::pair<double, int>> brute;
    for (int i = 0; i < int(pts.size()); ++i) brute.emplace_back(glm::length(pts[size_t(i)] - query), i);
    std::sort(brute.begin(), brute.end());
    const auto got = index.nearest(query, 9);
    ASSERT_EQ(got.size(), 9u);
    for (size_t k = 0; k < 9; ++k) {
      EXPECT_EQ(got[k].photo, brute[k].second);
      EXPECT_NEAR(got[k].distance, brute[k].first, 1e-9);
    }
  }
}

TEST(CameraIndex, FilterSkipsExcludedAndFewerCandidates) {
  CameraIndex index({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  const auto got = index.nearest({0.1, 0, 0}, 3, [](int i) { return i != 1; });
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].photo, 0);
  EXPECT_EQ(got[1].photo, 2);
  EXPECT_EQ(got[2].photo, 3);
  EXPECT_EQ(index.nearest({0, 0, 0}, 10).size(), 4u);
  EXPECT_TRUE(CameraIndex({}).nearest({0, 0, 0}, 3).empty());
}

}  // namespace
}  // namespace hv::ibr
