// The CPU reference's picture-quality options against hand-computed values: geometry weights
// (best K by penalty), feathering, and the slices' mip chain it samples (docs/design.md, step 5).
#include "hv/ibr/reference_blend.h"

#include "hv/ibr/slice_image.h"
#include "hv/ibr/weights.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::ibr {
namespace {

Camera look(const std::string& id, glm::dvec3 center, glm::dvec3 target) {
  return lookAtCamera(id, center, target, 160, 120, 100.0, {0, 1, 0});
}

// Ground point P = 0 with normal z, the view 10 above it (focal 100); three photographs listed
// farthest-penalty first: C (8, 0, 6), B (0, -5, 10), A (0, 1, 10), coloured blue, green, red.
class GeometryBlend : public ::testing::Test {
 protected:
  void SetUp() override {
    PinholeFrustum fr;
    fr.pxMax = {160, 120};
    const glm::dvec3 centres[3] = {{8, 0, 6}, {0, -5, 10}, {0, 1, 10}};
    for (int i = 0; i < 3; ++i)
      images.push_back(makeImageParams(look("c" + std::to_string(i), centres[i], {0, 0, 0}), {0, 0, 0},
                                       {i, {1.0 / 160, 1.0 / 120}}, 1.0, fr, {}));
    opt.weighting = Weighting::Geometry;
    opt.resolutionWeight = 0.5;
    opt.penaltyEpsilon = 0.05;
    opt.viewCenter = {0, 0, 10};
    opt.viewFocal = 100.0;
    opt.normal = {0, 0, 1};
  }
  BlendResult blend(int k) {
    return referenceBlend({0, 0, 0}, images, BlendMethod::Blend, tex, nullptr, Selection::Global, k, opt);
  }
  static double f(double p) { return 1.0 / (0.05 * 0.05 + p * p); }
  // By hand: A: theta = atan(1/10), rho = (101/1000) / (10/100) = 1.01; B: theta = atan(1/2),
  // rho = (125/1000) / 0.1 = 1.25; C: theta = acos(0.6), rho = (10 / 60) / 0.1 = 5/3.
  const double pA = std::atan(0.1) + 0.5 * std::log(1.01);
  const double pB = std::atan(0.5) + 0.5 * std::log(1.25);
  const double pC = std::acos(0.6) + 0.5 * std::log(5.0 / 3.0);
  std::vector<ImageParams> images;
  BlendOptions opt;
  glm::dvec4 colour[3] = {{0, 0, 1, 1}, {0, 1, 0, 1}, {1, 0, 0, 1}};
  TextureLookup tex = [this](int slice, glm::dvec2) { return colour[slice]; };
};

TEST_F(GeometryBlend, BestKByPenaltyWeightedAgainstTheNext) {
  ASSERT_LT(pA, pB);
  ASSERT_LT(pB, pC);
  // K = 2: A and B, against C.
  BlendResult r = blend(2);
  EXPECT_EQ(r.count, 2);
  const double wA = f(pA) - f(pC), wB = f(pB) - f(pC);
  EXPECT_NEAR(r.alpha, wA + wB, 1e-9);
  EXPECT_NEAR(r.color.r, wA / (wA + wB), 1e-12);
  EXPECT_NEAR(r.color.g, wB / (wA + wB), 1e-12);
  EXPECT_EQ(r.contribution[0], 0.0);
  // K = 1: A alone (w = f(pA) - f(pB)), whatever the list order.
  r = blend(1);
  EXPECT_EQ(r.count, 1);
  EXPECT_NEAR(r.alpha, f(pA) - f(pB), 1e-9);
  EXPECT_NEAR(r.color.r, 1.0, 1e-12);
  // K = 3: no K+1-th, w = f(p).
  r = blend(3);
  EXPECT_NEAR(r.alpha, f(pA) + f(pB) + f(pC), 1e-9);
  // The distance weighting (the papers') ignores the penalties: equal plan weights, equal shares.
  opt.weighting = Weighting::Distance;
  r = blend(3);
  EXPECT_NEAR(r.color.b, 1.0 / 3.0, 1e-12);
}

// geometryK: the images blended per pixel apart from --k, which stays the most blended at a pixel.
TEST_F(GeometryBlend, GeometryKBlendsTheBestFewAgainstTheNext) {
  EXPECT_EQ(geometryBlendCount(8, 0), 8);
  EXPECT_EQ(geometryBlendCount(8, 4), 4);
  EXPECT_EQ(geometryBlendCount(2, 4), 2);
  EXPECT_EQ(geometryBlendCount(40, 0), kMaxGeometryK);
  EXPECT_EQ(geometryBlendCount(0, 0), 1);
  // K = 3 but geometryK = 1: A alone against B, as with K = 1.
  opt.geometryK = 1;
  BlendResult r = blend(3);
  EXPECT_EQ(r.count, 1);
  EXPECT_NEAR(r.alpha, f(pA) - f(pB), 1e-9);
  EXPECT_NEAR(r.color.r, 1.0, 1e-12);
  // geometryK = 2 with K = 1: K still bounds it.
  opt.geometryK = 2;
  r = blend(1);
  EXPECT_EQ(r.count, 1);
  EXPECT_NEAR(r.alpha, f(pA) - f(pB), 1e-9);
  // geometryK = 2 with K = 3: A and B against C.
  r = blend(3);
  EXPECT_EQ(r.count, 2);
  EXPECT_NEAR(r.alpha, f(pA) + f(pB) - 2.0 * f(pC), 1e-9);
}

TEST_F(GeometryBlend, ResolutionWeightPrefersTheSharperPhotograph) {
  // Move B right above P, closer than the view: theta 0, sharper (no penalty); A now loses.
  PinholeFrustum fr;
  fr.pxMax = {160, 120};
  images[1] = makeImageParams(look("b", {0, 0.01, 4}, {0, 0, 0}), {0, 0, 0}, {1, {1.0 / 160, 1.0 / 120}}, 1.0, fr, {});
  EXPECT_NEAR(blend(1).color.g, 1.0, 1e-12);
}

TEST(Feathering, BorderDistanceAndWeights) {
  PinholeFrustum fr;
  fr.pxMax = {160, 120};
  // A camera 10 above the ground, focal 100: P = (-7, 0, 0) lands 70 pixels from the centre along
  // x, 10 from the border (either side); the other camera sees it in its centre.
  const std::vector<ImageParams> images = {
      makeImageParams(look("edge", {0, 0, 10}, {0, 0, 0}), {0, 0, 0}, {0, {1.0 / 160, 1.0 / 120}}, 1.0, fr, {}),
      makeImageParams(look("centre", {-7, 0, 10}, {-7, 0, 0}), {0, 0, 0}, {1, {1.0 / 160, 1.0 / 120}}, 1.0, fr, {})};
  const glm::dvec3 P{-7, 0, 0};
  const auto hit = projectIntoImage(images[0], P);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(borderDistance(images[0], *hit), 10.0, 1e-9);
  EXPECT_NEAR(borderDistance(images[1], *projectIntoImage(images[1], P)), 60.0, 1e-9);
  const glm::dvec4 colour[2] = {{1, 0, 0, 1}, {0, 1, 0, 1}};
  const TextureLookup tex = [&](int slice, glm::dvec2) { return colour[slice]; };
  BlendOptions opt;
  opt.featherPx = 20.0;  // smoothstep(10 / 20) = 0.5 for the edge image, 1 for the centre one
  const BlendResult r = referenceBlend(P, images, BlendMethod::Blend, tex, nullptr, Selection::Global, 2, opt);
  EXPECT_NEAR(r.color.r, 0.5 / 1.5, 1e-12);
  EXPECT_NEAR(r.color.g, 1.0 / 1.5, 1e-12);
  // Without feathering: equal shares.
  EXPECT_NEAR(referenceBlend(P, images, BlendMethod::Blend, tex, nullptr).color.r, 0.5, 1e-12);
  // A mask averaged to 0.75 over the feather width halves the centre image's weight too.
  opt.mask = [](int slice, glm::dvec2, double) { return slice == 1 ? 0.75 : 1.0; };
  const BlendResult m = referenceBlend(P, images, BlendMethod::Blend, tex, nullptr, Selection::Global, 2, opt);
  EXPECT_NEAR(m.color.r, 0.5, 1e-12);
  // The level: 20 px times uvScale 1/160 times a 320-texel slice = 40 texels: log2 40.
  EXPECT_NEAR(featherLevel(images[0], 20.0, 320), std::log2(40.0), 1e-12);
  EXPECT_EQ(featherLevel(images[0], 0.5, 160), 0.0);
}

// A layered photograph (Layered projective texture maps, 2003, §5): its edited layers stand for its
// shadow test, texture and mask; its weight and bounds stay.
TEST(LayeredBlend, EditedLayersStandForThePhotograph) {
  PinholeFrustum fr;
  fr.pxMax = {160, 120};
  const std::vector<ImageParams> images = {
      makeImageParams(look("layered", {0, 0, 10}, {0, 0, 0}), {0, 0, 0}, {0, {1.0 / 160, 1.0 / 120}}, 1.0, fr, {}),
      makeImageParams(look("plain", {-7, 0, 10}, {-7, 0, 0}), {0, 0, 0}, {1, {1.0 / 160, 1.0 / 120}}, 1.0, fr, {})};
  const glm::dvec3 P{-3, 0, 0};
  const glm::dvec4 colour[2] = {{1, 0, 0, 1}, {0, 1, 0, 1}};
  const TextureLookup tex = [&](int slice, glm::dvec2) { return colour[slice]; };
  // The photograph's own shadow test says image 0 does not see P: the layers decide instead.
  const VisibilityTest hidden = [](size_t i, const glm::dvec3&, double) { return i != 0; };
  std::optional<glm::dvec4> layer = glm::dvec4(0, 0, 1, 1);
  BlendOptions opt;
  opt.layered = {[&](const glm::dvec3& at) {
    EXPECT_EQ(at, P);
    return layer;
  }};
  const auto blend = [&](BlendMethod m) {
    return referenceBlend(P, images, m, tex, hidden, Selection::Global, 2, opt);
  };
  // Equal weights: the painted blue and the other photograph's green, half each.
  BlendResult r = blend(BlendMethod::Blend);
  EXPECT_EQ(r.count, 2);
  EXPECT_NEAR(r.color.b, 0.5, 1e-12);
  EXPECT_NEAR(r.color.g, 0.5, 1e-12);
  EXPECT_NEAR(r.color.r, 0.0, 1e-12);
  // Half transparent (premultiplied 0.5 blue, alpha 0.5): weight 1 * 0.5 against 1.
  layer = glm::dvec4(0, 0, 0.5, 0.5);
  r = blend(BlendMethod::Blend);
  EXPECT_NEAR(r.color.b, 0.5 / 1.5, 1e-12);
  EXPECT_NEAR(r.color.g, 1.0 / 1.5, 1e-12);
  EXPECT_NEAR(r.share(0), 0.5 / 1.5, 1e-12);
  // No sub-image textures P: the photograph adds nothing, whatever its own test says.
  layer = std::nullopt;
  r = blend(BlendMethod::Blend);
  EXPECT_EQ(r.count, 1);
  EXPECT_EQ(r.contribution[0], 0.0);
  EXPECT_NEAR(r.color.g, 1.0, 1e-12);
  r = blend(BlendMethod::Nearest);
  EXPECT_EQ(r.contribution[1], 1.0);
  layer = glm::dvec4(0, 0, 1, 1);
  EXPECT_NEAR(blend(BlendMethod::Nearest).color.b, 1.0, 1e-12);
  // The colour correction applies to the layers as to the photograph: gain 0.5 on blue.
  std::vector<ImageParams> corrected = images;
  corrected[0].colour.gain = {1.0, 1.0, 0.5};
  r = referenceBlend(P, corrected, BlendMethod::Blend, tex, hidden, Selection::Global, 2, opt);
  EXPECT_NEAR(r.color.b, 0.25, 1e-12);
  // Out of the photograph's bounds its layers are not asked.
  bool asked = false;
  opt.layered = {[&](const glm::dvec3&) {
    asked = true;
    return layer;
  }};
  referenceBlend({-30, 0, 0}, images, BlendMethod::Blend, tex, hidden, Selection::Global, 2, opt);
  EXPECT_FALSE(asked);
}

TEST(SliceMipChain, BoxFilteredLevelsDownToOneTexel) {
  Image8 img(5, 3, 4, 0);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      const std::uint8_t v = (x + y) % 2 ? 255 : 0;
      for (int c = 0; c < 4; ++c) img.at(x, y, c) = v;
    }
  EXPECT_EQ(mipLevelCount(5, 3), 3);
  EXPECT_EQ(mipLevelCount(1, 1), 1);
  EXPECT_EQ(mipLevelCount(2048, 1536), 12);
  EXPECT_EQ(mipChainBytes(4, 4), size_t(21 * 4));
  const auto chain = sliceMipChain(img);
  ASSERT_EQ(chain.size(), 3u);
  EXPECT_EQ(chain[1].width, 2);
  EXPECT_EQ(chain[1].height, 1);
  EXPECT_EQ(chain[2].width, 1);
  // A checkerboard's 2 x 2 means: (0 + 255 + 255 + 0 + 2) / 4 = 128.
  EXPECT_EQ(chain[1].at(0, 0, 0), 128);
  EXPECT_EQ(chain[1].at(1, 0, 3), 128);
  EXPECT_EQ(chain[2].at(0, 0, 0), 128);
  // Trilinear: halfway between level 0 at a black texel's centre and level 1 (128/255).
  const glm::dvec2 uv(0.5 / 5, 0.5 / 3);
  EXPECT_NEAR(sampleTrilinear(chain, uv, 0.0).r, 0.0, 1e-12);
  EXPECT_NEAR(sampleTrilinear(chain, uv, 0.5).r, 0.5 * 128.0 / 255.0, 1e-12);
  EXPECT_NEAR(sampleTrilinear(chain, uv, 9.0).r, 128.0 / 255.0, 1e-12);  // clamped to the last level
}

}  // namespace
}  // namespace hv::ibr
