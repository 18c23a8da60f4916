#include "hv/ibr/weights.h"

#include <gtest/gtest.h>

namespace hv::ibr {
namespace {

TEST(BlendWeights, FollowBredif2013Equation2) {
  // sigma = 1, d = 1, 2, 3: f = 1/2, 1/5, 1/10; K = 2 -> w = (1/2 - 1/10, 1/5 - 1/10).
  const auto w = blendWeights({1.0, 2.0, 3.0}, 2, 1.0);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_DOUBLE_EQ(w[0], 0.4);
  EXPECT_DOUBLE_EQ(w[1], 0.1);
}

TEST(BlendWeights, LastWeightIsZeroWhenKthAndNextTie) {
  // The K-th and (K+1)-th images at the same distance: about to swap, so w_K must vanish exactly.
  const auto w = blendWeights({1.0, 2.5, 4.0, 4.0, 7.0}, 3, 2.0);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[2], 0.0);
  EXPECT_GT(w[0], w[1]);
  EXPECT_GT(w[1], 0.0);
}

TEST(BlendWeights, NoNextCandidateMeansZeroFloor) {
  // K or fewer candidates: f(d_{K+1}) = 0, so w_i = f(d_i).
  const auto w = blendWeights({0.0, 3.0}, 4, 0.5);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_DOUBLE_EQ(w[0], 1.0 / 0.25);
  EXPECT_DOUBLE_EQ(w[1], 1.0 / (0.25 + 9.0));
  const auto exact = blendWeights({1.0, 2.0}, 2, 1.0);
  EXPECT_DOUBLE_EQ(exact[1], 0.2);
}

TEST(BlendWeights, NormalisedBlendIsAConvexCombination) {
  const auto w = blendWeights({0.5, 1.0, 1.5, 2.0, 9.0}, 4, 1.0);
  double sum = 0.0;
  for (double x : w) sum += x;
  // Normalised blend of colours 0, 1, 2, 3 stays within [0, 3] and is weighted towards the nearest.
  double c = 0.0;
  for (size_t i = 0; i < w.size(); ++i) c += w[i] / sum * double(i);
  EXPECT_GT(c, 0.0);
  EXPECT_LT(c, 1.5);
  EXPECT_TRUE(blendWeights({}, 3, 1.0).empty());
  EXPECT_TRUE(blendWeights({1.0}, 0, 1.0).empty());
}

}  // namespace
}  // namespace hv::ibr
