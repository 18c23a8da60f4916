#include "hv/ibr/weights.h"

#include <gtest/gtest.h>

#include <cmath>

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

// Geometry weights: values worked out by hand (docs/design.md, "Weights that know geometry").
GeometryPenaltyInput flatGround(glm::dvec3 image) {
  GeometryPenaltyInput g;
  g.point = {0.0, 0.0, 0.0};
  g.viewCenter = {0.0, 0.0, 2.0};  // straight above P at 2
  g.imageCenter = image;
  g.normal = {0.0, 0.0, -1.0};  // either orientation counts
  g.viewFocal = 100.0;
  g.imageFocal = 100.0;
  return g;
}

TEST(GeometryWeights, RayAngleIsTheAngleBetweenTheTwoRaysToThePoint) {
  // P - V = (0, 0, -2), P - C = (-1, 0, -1): 45 degrees.
  EXPECT_NEAR(rayAngle(flatGround({1.0, 0.0, 1.0})), 0.25 * 3.14159265358979, 1e-12);
  // Same ray, farther along it: 0 (and exact there, where acos would not be).
  EXPECT_EQ(rayAngle(flatGround({0.0, 0.0, 7.0})), 0.0);
  // Opposite side of the surface straight below: 180 degrees.
  EXPECT_NEAR(rayAngle(flatGround({0.0, 0.0, -3.0})), 3.14159265358979, 1e-12);
}

TEST(GeometryWeights, FootprintRatioComparesTexelAndPixelOnTheSurface) {
  // Twice as far with the same focal: texels twice the view's pixels.
  EXPECT_NEAR(footprintRatio(flatGround({0.0, 0.0, 4.0})), 2.0, 1e-12);
  // ... unless the photograph has twice the focal length.
  GeometryPenaltyInput g = flatGround({0.0, 0.0, 4.0});
  g.imageFocal = 200.0;
  EXPECT_NEAR(footprintRatio(g), 1.0, 1e-12);
  // Oblique: |P - C| = 5, cos = 4/5, so (5 / 0.8) / 2 = 3.125.
  EXPECT_NEAR(footprintRatio(flatGround({3.0, 0.0, 4.0})), 3.125, 1e-12);
  // Grazing: cosine clamped at kMinCosine, so the ratio stays finite: (10 / 0.05) / 2.
  EXPECT_NEAR(footprintRatio(flatGround({10.0, 0.0, 0.0})), 100.0, 1e-9);
}

TEST(GeometryWeights, PenaltyAddsTheResolutionTermOnlyForBlurrierPhotographs) {
  // Straight above, twice as far: theta = 0, rho = 2.
  EXPECT_NEAR(geometryPenalty(flatGround({0.0, 0.0, 4.0}), 0.5), 0.5 * std::log(2.0), 1e-12);
  // Closer than the view (sharper): no resolution penalty at all.
  EXPECT_EQ(geometryPenalty(flatGround({0.0, 0.0, 1.0}), 0.5), 0.0);
  // 45 degrees at |P - C| = sqrt 2, cos 1/sqrt 2: rho = (sqrt2 / (1/sqrt2)) / 2 = 1, angle only.
  EXPECT_NEAR(geometryPenalty(flatGround({1.0, 0.0, 1.0}), 3.0), 0.25 * 3.14159265358979, 1e-12);
  // A far photograph seeing the ground at grazing incidence loses against a steep one.
  const double steep = geometryPenalty(flatGround({0.0, 0.0, 3.0}), 0.5);
  const double grazing = geometryPenalty(flatGround({20.0, 0.0, 1.0}), 0.5);
  EXPECT_LT(steep, grazing);
}

TEST(GeometryWeights, BestKWeightsVanishContinuouslyAsAnImageLeaves) {
  // Penalties as blendWeights' distances: the K-th weight goes to 0 as p_K reaches p_K+1.
  const double eps = 0.05;
  double last = 1e9;
  for (double pk : {0.20, 0.25, 0.29, 0.299, 0.2999, 0.3}) {
    const auto w = blendWeights({0.1, pk, 0.3}, 2, eps);
    ASSERT_EQ(w.size(), 2u);
    EXPECT_LT(w[1], last);
    last = w[1];
  }
  EXPECT_EQ(last, 0.0);
  // 1/(eps^2 + p^2): p = 0.1 -> 80, p = 0.3 -> 1/0.0925.
  EXPECT_NEAR(blendWeights({0.1, 0.2, 0.3}, 2, eps)[0], 80.0 - 1.0 / 0.0925, 1e-9);
}

TEST(Feathering, SmoothstepOfTheDistanceOverTheWidth) {
  EXPECT_EQ(featherFactor(5.0, 10.0), 0.5);
  EXPECT_DOUBLE_EQ(featherFactor(2.5, 10.0), 0.15625);  // t = 1/4: t^2 (3 - 2t)
  EXPECT_EQ(featherFactor(-1.0, 10.0), 0.0);
  EXPECT_EQ(featherFactor(0.0, 10.0), 0.0);
  EXPECT_EQ(featherFactor(25.0, 10.0), 1.0);
  EXPECT_EQ(featherFactor(0.0, 0.0), 1.0);  // no feather: hard edges
  EXPECT_EQ(maskFeather(0.5), 0.0);         // on the mask's edge
  EXPECT_EQ(maskFeather(0.75), 0.5);
  EXPECT_EQ(maskFeather(1.0), 1.0);
  EXPECT_EQ(maskFeather(0.1), 0.0);
}

}  // namespace
}  // namespace hv::ibr
