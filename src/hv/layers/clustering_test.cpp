#include "hv/layers/clustering.h"

#include <gtest/gtest.h>

namespace hv::layers {
namespace {

TEST(LayerClustering, PowerOfTwoArea) {
  EXPECT_EQ(powerOfTwoAtLeast(1), 1);
  EXPECT_EQ(powerOfTwoAtLeast(9), 16);
  EXPECT_EQ(powerOfTwoAtLeast(16), 16);
  EXPECT_EQ(powerOfTwoArea({0, 0, 9, 9}), 256);   // 16 x 16
  EXPECT_EQ(powerOfTwoArea({9, 0, 16, 9}), 128);  // 7 x 9 -> 8 x 16
  EXPECT_EQ(powerOfTwoArea({3, 4, 3, 10}), 0);    // empty
  EXPECT_EQ(powerOfTwoArea({0, 0, 33, 2}), 128);  // 64 x 2
}

TEST(LayerClustering, NeighboursMergeWhenTheirTextureShrinks) {
  // A 16x16 + B 8x16 = 384 > union [0,16)x[0,9) -> 16x16 = 256: merged.
  const auto c = clusterBoxes({{0, 0, 9, 9}, {9, 0, 16, 9}});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].box, (PixelBox{0, 0, 16, 9}));
  EXPECT_EQ(c[0].members, (std::vector<std::size_t>{0, 1}));
}

TEST(LayerClustering, FarApartBoxesStaySeparate) {
  // 256 + 256 < union 510 x 510 -> 512 x 512.
  const auto c = clusterBoxes({{0, 0, 10, 10}, {500, 500, 510, 510}});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].members, (std::vector<std::size_t>{0}));
  EXPECT_EQ(c[1].box, (PixelBox{500, 500, 510, 510}));
}

TEST(LayerClustering, EqualAreaIsNotAMerge) {
  // Two 8x8 boxes side by side: A12 = 16 x 8 = 128 = A1 + A2, and the rule asks for A12 < A1 + A2.
  EXPECT_EQ(clusterBoxes({{0, 0, 8, 8}, {8, 0, 16, 8}}).size(), 2u);
}

TEST(LayerClustering, IteratesToAFixpoint) {
  // A [0,9)^2: 256; B [9,16)x[0,9): 128; D [0,16)x[9,16): 16 x 8 = 128.
  // A+B: union 16x9 -> 256, saving 128; A+D: union 16x16 -> 256, saving 128; B+D: union 16x16 ->
  // 256 = 128 + 128, no saving. Tie -> A+B first; then AB (256) + D (128) -> 256 < 384: merged.
  const auto c = clusterBoxes({{0, 0, 9, 9}, {9, 0, 16, 9}, {0, 9, 16, 16}});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].box, (PixelBox{0, 0, 16, 16}));
  EXPECT_EQ(c[0].members, (std::vector<std::size_t>{0, 1, 2}));
}

TEST(LayerClustering, TieGoesToTheLowestIndices) {
  // A [0,9)x[0,9) 256, B [9,16)x[0,9) 128, C [16,25)x[0,9) 256. A+B saves 128, B+C saves 128
  // (union 16x9 -> 256), A+C saves 0. A+B merged first; AB + C: union 25x9 -> 32 x 16 = 512 = 256 + 256:
  // not merged.
  const auto c = clusterBoxes({{0, 0, 9, 9}, {9, 0, 16, 9}, {16, 0, 25, 9}});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].members, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(c[1].members, (std::vector<std::size_t>{2}));
}

TEST(LayerClustering, EmptyBoxesAreLeftOut) {
  const auto c = clusterBoxes({{5, 5, 5, 9}, {0, 0, 4, 4}});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].members, (std::vector<std::size_t>{1}));
}

}  // namespace
}  // namespace hv::layers
