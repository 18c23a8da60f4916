// Colour corrections from the overlaps (hv/ibr/colour_correction.h): synthetic photographs of a
// known surface colour, ray cast and given known casts, are brought back to agree.
#include "hv/ibr/colour_correction.h"

#include "hv/ibr/reference_blend.h"
#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::ibr {
namespace {

// A 60 m square of ground with a 6 x 6 x 8 m box in the middle: the box hides parts of the ground
// (and of itself) from each camera, so the depth test has work to do.
Mesh groundAndBox() {
  Mesh m;
  auto quad = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d) {
    const auto base = std::uint32_t(m.positions.size());
    for (const glm::dvec3& p : {a, b, c, d}) m.positions.push_back(p);
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  };
  quad({-30, -30, 0}, {30, -30, 0}, {30, 30, 0}, {-30, 30, 0});
  const double h = 8.0;
  quad({-3, -3, 0}, {3, -3, 0}, {3, -3, h}, {-3, -3, h});
  quad({3, -3, 0}, {3, 3, 0}, {3, 3, h}, {3, -3, h});
  quad({3, 3, 0}, {-3, 3, 0}, {-3, 3, h}, {3, 3, h});
  quad({-3, 3, 0}, {-3, -3, 0}, {-3, -3, h}, {-3, 3, h});
  quad({-3, -3, h}, {3, -3, h}, {3, 3, h}, {-3, 3, h});
  return m;
}

// The true colour of a surface point, in [0.2, 0.8]; the box is far from the ground's colours so
// that a pair mixing the two shows.
glm::dvec3 albedo(const glm::dvec3& p) {
  if (p.z > 1e-6) return {0.75 + 0.05 * std::sin(0.9 * p.z), 0.25 + 0.05 * std::cos(0.8 * (p.x + p.y)), 0.2};
  return {0.5 + 0.3 * std::sin(0.31 * p.x) * std::cos(0.23 * p.y), 0.5 + 0.3 * std::cos(0.27 * p.x + 0.4),
          0.5 + 0.3 * std::sin(0.19 * p.y - 0.2 * p.x)};
}

struct Cast {
  glm::dvec3 gain{1.0}, offset{0.0};
  glm::dvec3 apply(const glm::dvec3& c) const { return gain * c + offset; }
};

// Premultiplied RGBA8 photograph of the scene (one ray per pixel centre), through `cast`.
Image8 photograph(const Camera& cam, const RayCaster& caster, const Cast& cast) {
  Image8 img(cam.width, cam.height, 4, 0);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const auto hit = caster.intersect(cam.center, cam.rayDirection({x + 0.5, y + 0.5}));
      glm::dvec3 c = hit ? cast.apply(albedo(hit->position)) : glm::dvec3(0.0);
      std::uint8_t* o = img.px(x, y);
      for (int k = 0; k < 3; ++k) o[k] = std::uint8_t(std::lround(std::clamp(c[k], 0.0, 1.0) * 255.0));
      o[3] = hit ? 255 : 0;
    }
  return img;
}

struct Rig {
  Mesh mesh = groundAndBox();
  RayCaster caster{mesh};
  std::vector<Camera> cameras;
  std::vector<Image8> images;
  std::vector<OverlapImage> overlap;

  explicit Rig(const std::vector<Cast>& casts) {
    for (size_t i = 0; i < casts.size(); ++i) {
      const double a = 2.0 * M_PI * double(i) / double(casts.size());
      const glm::dvec3 c(22.0 * std::cos(a), 22.0 * std::sin(a), 9.0 + double(i % 2));
      cameras.push_back(lookAtCamera("p" + std::to_string(i), c, {0.0, 0.0, 2.0}, 160, 120, 110.0));
      images.push_back(photograph(cameras.back(), caster, casts[i]));
    }
    for (size_t i = 0; i < casts.size(); ++i)
      overlap.push_back({cameras[i], &images[i], glm::dvec2(1.0 / 160, 1.0 / 120)});
  }
};

// How far the correction is from undoing the cast: max over colours c of |h(cast(c)) - ref(c)|
// per channel, c on a grid of the colours the photographs hold ([0.2, 0.8]).
double worstError(const ColourCorrection& h, const Cast& cast, const ColourCorrection& ref = {}) {
  double worst = 0.0;
  for (double v = 0.2; v <= 0.8 + 1e-9; v += 0.05) {
    const glm::dvec3 c(v);
    const glm::dvec3 d = (h.gain * cast.apply(c) + h.offset) - (ref.gain * c + ref.offset);
    worst = std::max({worst, std::abs(d.r), std::abs(d.g), std::abs(d.b)});
  }
  return worst;
}

const std::vector<Cast> kCasts = {
    {}, {}, {}, {}, {{0.8, 1.1, 0.9}, {0.1, -0.05, 0.04}}, {}, {{1.15, 0.9, 0.7}, {-0.08, 0.06, 0.15}}, {}};

TEST(ColourCorrection, RecoversKnownCastsWhenMostPhotographsAgree) {
  const Rig rig(kCasts);
  HarmonizeSettings s;
  s.samplesPerImage = 3000;
  s.prior = 1e-6;  // exact overlaps: nothing for the default's pull towards the identity to guard against
  const auto pairs = collectColourPairs(rig.overlap, rig.caster, s);
  ASSERT_GT(pairs.size(), 5000u);
  const HarmonizeResult r = solveColourCorrections(kCasts.size(), pairs, s);
  ASSERT_EQ(r.corrections.size(), kCasts.size());
  for (size_t i = 0; i < kCasts.size(); ++i) {
    EXPECT_GT(r.pairsPerPhoto[i], 1000) << i;
    // The goal: the known cast recovered to within 2/255 per channel.
    EXPECT_LE(worstError(r.corrections[i], kCasts[i]), 2.0 / 255.0)
        << "photograph " << i << ": gain " << r.corrections[i].gain.r << " " << r.corrections[i].gain.g << " "
        << r.corrections[i].gain.b << ", offset " << r.corrections[i].offset.r << " " << r.corrections[i].offset.g
        << " " << r.corrections[i].offset.b;
  }
  // The cast photograph 4: gain 1/0.8 on red, offset -0.1/0.8, as computed by hand.
  EXPECT_NEAR(r.corrections[4].gain.r, 1.25, 0.02);
  EXPECT_NEAR(r.corrections[4].offset.r, -0.125, 0.01);
  EXPECT_GT(r.rmsBefore, 0.02);
  EXPECT_LT(r.inlierRmsAfter, 2.0 / 255.0);
}

// Every photograph cast differently: the overlaps fix the corrections only up to one common affine
// map per channel (the gauge), which the prior settles. Relative to photograph 0's corrected
// colours, each photograph's are recovered.
TEST(ColourCorrection, RecoversRelativeCastsWhenNoneAgree) {
  std::vector<Cast> casts;
  for (int i = 0; i < 6; ++i)
    casts.push_back({glm::dvec3(0.85 + 0.05 * i, 1.1 - 0.04 * i, 0.9 + 0.03 * (i % 3)),
                     glm::dvec3(0.02 * (i % 4) - 0.03, 0.05 - 0.015 * i, 0.01 * i)});
  const Rig rig(casts);
  HarmonizeSettings s;
  s.samplesPerImage = 3000;
  s.prior = 1e-6;  // exact overlaps, as above
  const HarmonizeResult r = solveColourCorrections(casts.size(), collectColourPairs(rig.overlap, rig.caster, s), s);
  // ref(c) = h_0(cast_0(c)): what photograph 0 shows for a true colour c.
  ColourCorrection ref;
  ref.gain = r.corrections[0].gain * casts[0].gain;
  ref.offset = r.corrections[0].gain * casts[0].offset + r.corrections[0].offset;
  for (size_t i = 1; i < casts.size(); ++i) EXPECT_LE(worstError(r.corrections[i], casts[i], ref), 2.0 / 255.0) << i;
}

// The depth test: a point one photograph sees is paired only with photographs that see it too.
// Without it (a tolerance that turns the ray back off), points on the box's far side and on the
// ground behind it are paired with what hides them, and many pairs disagree.
TEST(ColourCorrection, PairsOnlyWhatBothPhotographsSee) {
  const Rig rig(std::vector<Cast>(6));
  HarmonizeSettings s;
  s.samplesPerImage = 2000;
  auto disagreeing = [](const std::vector<ColourPair>& pairs) {
    size_t bad = 0;
    for (const ColourPair& p : pairs) {
      const glm::dvec3 d = glm::abs(p.ca - p.cb);
      if (std::max({d.r, d.g, d.b}) > 0.05) ++bad;
    }
    return double(bad) / double(std::max<size_t>(pairs.size(), 1));
  };
  const auto tested = collectColourPairs(rig.overlap, rig.caster, s);
  s.occlusionTolerance = 2.0;
  const auto untested = collectColourPairs(rig.overlap, rig.caster, s);
  ASSERT_GT(tested.size(), 2000u);
  EXPECT_GT(untested.size(), tested.size() * 11 / 10);
  // What still disagrees with the test: texels on the box's silhouettes, which mix box and ground
  // (bilinear), about 1 %.
  EXPECT_LT(disagreeing(tested), 0.02);
  EXPECT_GT(disagreeing(untested), 5.0 * disagreeing(tested)) << disagreeing(untested);
  // Uncast photographs: the corrections are the identity.
  const HarmonizeResult r = solveColourCorrections(6, tested, s);
  for (const ColourCorrection& c : r.corrections) EXPECT_LE(worstError(c, Cast{}), 1.0 / 255.0);
}

// The correction on a premultiplied texel (twin of hv_correctColour): straight colour c = rgb / a.
TEST(ColourCorrection, CorrectsPremultipliedTexels) {
  const ColourCorrection h{{2.0, 0.5, 1.0}, {0.1, 0.0, -0.25}};
  // a = 0.5, straight (0.4, 0.8, 0.2) -> (0.9, 0.4, -0.05 -> 0), premultiplied (0.45, 0.2, 0).
  const glm::dvec4 t = correctTexel(h, {0.2, 0.4, 0.1, 0.5});
  EXPECT_NEAR(t.r, 0.45, 1e-12);
  EXPECT_NEAR(t.g, 0.2, 1e-12);
  EXPECT_NEAR(t.b, 0.0, 1e-12);
  EXPECT_EQ(t.a, 0.5);
  // Straight 0.8 red -> 1.7, clamped to 1: premultiplied a.
  EXPECT_NEAR(correctTexel(h, {0.4, 0.0, 0.0, 0.5}).r, 0.5, 1e-12);
  EXPECT_EQ(correctTexel(h, {0.0, 0.0, 0.0, 0.0}), glm::dvec4(0.0));
  EXPECT_EQ(correctTexel(ColourCorrection{}, {0.1, 0.2, 0.3, 0.4}), glm::dvec4(0.1, 0.2, 0.3, 0.4));
}

TEST(ColourCorrection, PhotographWithoutPairsKeepsTheIdentity) {
  const std::vector<ColourPair> pairs = {{0, 1, {0.5, 0.5, 0.5}, {0.6, 0.6, 0.6}},
                                         {1, 0, {0.3, 0.2, 0.1}, {0.2, 0.1, 0.0}},
                                         {7, 0, {0.3, 0.2, 0.1}, {0.2, 0.1, 0.0}}};  // 7: no such photograph
  const HarmonizeResult r = solveColourCorrections(3, pairs, HarmonizeSettings{});
  ASSERT_EQ(r.corrections.size(), 3u);
  EXPECT_TRUE(r.corrections[2].isIdentity());
  EXPECT_EQ(r.pairsPerPhoto[2], 0);
  EXPECT_EQ(r.pairsPerPhoto[0], 2);
  EXPECT_TRUE(solveColourCorrections(0, pairs, HarmonizeSettings{}).corrections.empty());
}

// The prior (harmonize --prior) trades the overlaps against the identity: a tiny one leaves a cast
// to the overlaps alone, the default (0.1) alone undoes it only in part, and never past it (the
// refinement after it, on by default, undoes it: see RefinementUndoesACastThroughMisregisteredPairs).
TEST(ColourCorrection, StrongPriorUndoesACastInPartOnly) {
  // Photographs 0 and 1 agree; photograph 2 shows every colour at 0.8 of its value (its
  // correction's gain is 1.25).
  std::vector<ColourPair> pairs;
  for (int k = 0; k < 200; ++k) {
    const double c = 0.1 + 0.8 * double(k) / 199.0;
    const glm::dvec3 colour(c, 0.9 - 0.5 * c, 0.5);
    pairs.push_back({0, 1, colour, colour});
    pairs.push_back({0, 2, colour, 0.8 * colour});
    pairs.push_back({1, 2, colour, 0.8 * colour});
  }
  HarmonizeSettings tiny;
  tiny.prior = 1e-6;
  const HarmonizeResult exact = solveColourCorrections(3, pairs, tiny);
  EXPECT_NEAR(exact.corrections[2].gain.r, 1.25, 1e-3);
  EXPECT_NEAR(exact.corrections[0].gain.r, 1.0, 1e-3);
  HarmonizeSettings prior;  // the default prior, 0.1, alone: no refinement after it
  prior.refineScale = 0.0;
  const HarmonizeResult held = solveColourCorrections(3, pairs, prior);
  for (int ch = 0; ch < 2; ++ch) {  // blue is 0.5 everywhere: its gain and offset trade, only the colour counts
    EXPECT_GT(held.corrections[2].gain[ch], 1.02) << ch;
    EXPECT_LT(held.corrections[2].gain[ch], 1.24) << ch;
  }
  // The corrected colour of photograph 2 lies between its own and the exact one.
  const double shown = held.corrections[2].gain.b * 0.4 + held.corrections[2].offset.b;
  EXPECT_GT(shown, 0.4 + 1e-3);
  EXPECT_LT(shown, 0.5 - 1e-3);
}

// A small deterministic generator for the tests below (xorshift64*), uniform in [0, 1).
struct Rng {
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  double operator()() {
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return double((state * 0x2545F4914F6CDD1Dull) >> 11) * 0x1.0p-53;
  }
};

glm::dvec3 quantized(const glm::dvec3& c) { return glm::round(glm::clamp(c, 0.0, 1.0) * 255.0) / 255.0; }

// The demo city's faded print: 0.62 c + (0.27, 0.25, 0.19); undone by gain 1/0.62.
const Cast kFaded{glm::dvec3(0.62), {0.27, 0.25, 0.19}};

// Overlaps seen through an inexact proxy: of the pairs, a share holds two nearby points (colours
// that differ by a few hundredths, both ways), the rest one point; photograph 3 is faded. The
// prior alone dilutes its gain; the refinement keeps the pairs that agree and undoes the cast.
TEST(ColourCorrection, RefinementUndoesACastThroughMisregisteredPairs) {
  Rng rng;
  std::vector<ColourPair> pairs;
  const std::vector<Cast> casts = {{}, {}, {}, kFaded, {}};
  for (int k = 0; k < 20000; ++k) {
    const int a = int(rng() * 5.0), b = (a + 1 + int(rng() * 4.0)) % 5;
    const glm::dvec3 c(0.1 + 0.7 * rng(), 0.1 + 0.7 * rng(), 0.1 + 0.7 * rng());
    glm::dvec3 d = c;
    if (rng() < 0.4)
      d = glm::clamp(c + 0.08 * glm::dvec3(rng() - 0.5, rng() - 0.5, rng() - 0.5) + glm::dvec3(0.15 * (rng() - 0.5)),
                     0.0, 1.0);
    pairs.push_back({a, b, quantized(casts[size_t(a)].apply(c)), quantized(casts[size_t(b)].apply(d))});
  }
  const HarmonizeResult refined = solveColourCorrections(5, pairs, HarmonizeSettings{});
  for (size_t i = 0; i < casts.size(); ++i) {
    EXPECT_FALSE(refined.monochrome[i]) << i;
    EXPECT_LE(worstError(refined.corrections[i], casts[i]), 2.0 / 255.0) << i;
  }
  HarmonizeSettings prior;
  prior.refineScale = 0.0;
  const HarmonizeResult held = solveColourCorrections(5, pairs, prior);
  EXPECT_GT(worstError(held.corrections[3], kFaded), 6.0 / 255.0);
}

// Pairs on texture weigh less: here every pair on texture is misregistered the same way (its
// second colour brighter by 0.1, as a shadow edge would give), every flat one exact.
TEST(ColourCorrection, PairsOnTextureWeighLess) {
  Rng rng;
  std::vector<ColourPair> pairs;
  for (int k = 0; k < 6000; ++k) {
    const int a = k % 3, b = (a + 1) % 3;
    const glm::dvec3 c(0.1 + 0.6 * rng(), 0.1 + 0.6 * rng(), 0.1 + 0.6 * rng());
    const bool textured = k % 2 == 0 && b == 2;
    pairs.push_back({a, b, c, textured ? c + 0.1 : c, glm::dvec3(textured ? 0.2 : 0.0)});
  }
  HarmonizeSettings s;
  s.refineScale = 0.0;
  s.prior = 1e-6;
  EXPECT_LE(worstError(solveColourCorrections(3, pairs, s).corrections[2], Cast{}), 2.0 / 255.0);
  s.textureScale = 0.0;  // every pair the same: photograph 2 moves
  EXPECT_GT(worstError(solveColourCorrections(3, pairs, s).corrections[2], Cast{}), 5.0 / 255.0);
}

// Luma (Rec. 601), as the demo city's monochrome casts use it.
double luma(const glm::dvec3& c) { return 0.299 * c.r + 0.587 * c.g + 0.114 * c.b; }
glm::dvec3 sepia(const glm::dvec3& c) {
  const double y = luma(c);
  return {0.08 + 0.98 * y, 0.05 + 0.84 * y, 0.02 + 0.62 * y};
}

// A sepia photograph has one luma per pixel: it is found monochrome, takes no part in the others'
// solve (which it would pull towards its line), and is matched to them in luma; its chroma is not
// given back (no per-photograph colour map can).
TEST(ColourCorrection, MonochromePhotographIsMatchedInLumaOnly) {
  Rng rng;
  std::vector<ColourPair> pairs;
  std::vector<glm::dvec3> colours;
  for (int k = 0; k < 8000; ++k) {
    const int a = k % 4, b = (a + 1 + k / 4 % 3) % 4;  // every pair of the four photographs
    const glm::dvec3 c(0.1 + 0.7 * rng(), 0.1 + 0.7 * rng(), 0.1 + 0.7 * rng());
    colours.push_back(c);
    auto seen = [&](int i) { return quantized(i == 3 ? sepia(c) : c); };
    pairs.push_back({a, b, seen(a), seen(b)});
  }
  const HarmonizeResult r = solveColourCorrections(4, pairs, HarmonizeSettings{});
  EXPECT_EQ(r.monochrome, std::vector<bool>({false, false, false, true}));
  for (size_t i = 0; i < 3; ++i) EXPECT_LE(worstError(r.corrections[i], Cast{}), 1.0 / 255.0) << i;
  double lumaError = 0.0, lumaCast = 0.0, chromaError = 0.0;
  for (const glm::dvec3& c : colours) {
    const glm::dvec3 shown = r.corrections[3].apply(quantized(sepia(c)));
    lumaError += (luma(shown) - luma(c)) * (luma(shown) - luma(c));
    lumaCast += (luma(sepia(c)) - luma(c)) * (luma(sepia(c)) - luma(c));
    chromaError = std::max({chromaError, std::abs(shown.r - c.r), std::abs(shown.b - c.b)});
  }
  lumaError = std::sqrt(lumaError / double(colours.size()));
  lumaCast = std::sqrt(lumaCast / double(colours.size()));
  EXPECT_LE(lumaError, 1.0 / 255.0);
  EXPECT_GT(lumaCast, 5.0 / 255.0);
  EXPECT_GT(chromaError, 0.2);  // the chroma stays lost
}

}  // namespace
}  // namespace hv::ibr
