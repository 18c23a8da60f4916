#include "hv/scene/orthophoto.h"

#include <gtest/gtest.h>

namespace hv {
namespace {

// 4 x 2 texels over x in [100, 108], y in [50, 54] (2 m a texel): texel (i, j) has red 10 i + 100 j,
// green 7, blue 200 j, alpha 255.
Orthophoto small() {
  Orthophoto o;
  o.width = 4;
  o.height = 2;
  o.minX = 100, o.maxX = 108, o.minY = 50, o.maxY = 54;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i)
      o.rgba.insert(o.rgba.end(), {std::uint8_t(10 * i + 100 * j), 7, std::uint8_t(200 * j), 255});
  return o;
}

TEST(Orthophoto, TexCoordsRunEastAndSouthFromTheNorthWestCorner) {
  const Orthophoto o = small();
  EXPECT_EQ(orthophotoTexCoord(o, 100, 54), glm::dvec2(0.0, 0.0));
  EXPECT_EQ(orthophotoTexCoord(o, 108, 50), glm::dvec2(1.0, 1.0));
  EXPECT_EQ(orthophotoTexCoord(o, 104, 53), glm::dvec2(0.5, 0.25));
  EXPECT_DOUBLE_EQ(o.metresPerPixelX(), 2.0);
  EXPECT_DOUBLE_EQ(o.metresPerPixelY(), 2.0);
  EXPECT_EQ(o.bytes(), 32u);
}

TEST(Orthophoto, TheAffineMapOfTheRenderFrameAgreesWithTheTexCoords) {
  const Orthophoto o = small();
  const glm::dvec3 origin(103.0, 51.0, 40.0);
  const OrthophotoAffine a = orthophotoAffine(o, origin);
  for (const glm::dvec2 w : {glm::dvec2(100, 54), glm::dvec2(108, 50), glm::dvec2(101.3, 52.7), glm::dvec2(90, 60)}) {
    const glm::dvec3 r(w.x - origin.x, w.y - origin.y, 1.0);
    const glm::dvec2 want = orthophotoTexCoord(o, w.x, w.y);
    EXPECT_NEAR(glm::dot(a.uRow, r), want.x, 1e-12) << w.x << "," << w.y;
    EXPECT_NEAR(glm::dot(a.vRow, r), want.y, 1e-12) << w.x << "," << w.y;
  }
}

TEST(Orthophoto, BilinearSamplingAsGlLinearWithClampToEdge) {
  const Orthophoto o = small();
  // A texel's centre: that texel.
  EXPECT_NEAR(sampleOrthophoto(o, {2.5 / 4, 0.5 / 2}).r * 255, 20, 1e-9);
  EXPECT_NEAR(sampleOrthophoto(o, {1.5 / 4, 1.5 / 2}).r * 255, 110, 1e-9);
  EXPECT_NEAR(sampleOrthophoto(o, {1.5 / 4, 1.5 / 2}).b * 255, 200, 1e-9);
  // Half-way between texels (1, 0) and (2, 0), and a quarter of the way from row 0 to row 1.
  EXPECT_NEAR(sampleOrthophoto(o, {2.0 / 4, 0.5 / 2}).r * 255, 15, 1e-9);
  EXPECT_NEAR(sampleOrthophoto(o, {2.0 / 4, 0.75 / 2}).r * 255, 15 + 0.25 * 100, 1e-9);
  EXPECT_NEAR(sampleOrthophoto(o, {2.0 / 4, 0.75 / 2}).b * 255, 0.25 * 200, 1e-9);
  // The edges clamp: the corner's half texel is the corner texel.
  EXPECT_NEAR(sampleOrthophoto(o, {0.0, 0.0}).r * 255, 0, 1e-9);
  EXPECT_NEAR(sampleOrthophoto(o, {1.0, 1.0}).r * 255, 130, 1e-9);
  EXPECT_NEAR(sampleOrthophoto(o, {0.5, 0.5}).a, 1.0, 1e-12);
  EXPECT_EQ(sampleOrthophoto(Orthophoto{}, {0.5, 0.5}), glm::dvec4(0.0));
}

}  // namespace
}  // namespace hv
