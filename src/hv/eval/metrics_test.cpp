#include "hv/eval/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace hv::eval {
namespace {

constexpr double kC1 = (0.01 * 255.0) * (0.01 * 255.0);
constexpr double kC2 = (0.03 * 255.0) * (0.03 * 255.0);

// A deterministic textured RGB image (gradients plus a pattern), so SSIM has structure to compare.
Image8 textured(int w, int h, int channels = 3, unsigned seed = 1) {
  Image8 im(w, h, channels);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> jitter(0, 40);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      im.at(x, y, 0) = std::uint8_t((x * 7 + y * 3 + jitter(rng)) % 256);
      im.at(x, y, 1) = std::uint8_t(((x / 4 + y / 4) % 2) ? 200 - jitter(rng) : 40 + jitter(rng));
      im.at(x, y, 2) = std::uint8_t((x * y + jitter(rng)) % 256);
      if (channels == 4) im.at(x, y, 3) = 255;
    }
  return im;
}

std::vector<std::uint8_t> allScored(const Image8& im) {
  return std::vector<std::uint8_t>(std::size_t(im.width) * im.height, 1);
}

Image8 addNoise(const Image8& im, double sigma, unsigned seed) {
  Image8 out = im;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (auto& v : out.data) v = std::uint8_t(std::clamp(std::lround(v + noise(rng)), 0L, 255L));
  return out;
}

// Textbook SSIM of one pixel, straight from Wang et al. 2004 eqs. (13)-(16): the full 11x11 Gaussian
// window (sigma 1.5, weights normalised to sum 1), no mask, no separability. Only valid where the window
// lies inside the image.
double referenceSsimAt(const std::vector<double>& a, const std::vector<double>& b, int width, int x, int y) {
  double g[11], gs = 0.0;
  for (int k = -5; k <= 5; ++k) gs += (g[k + 5] = std::exp(-k * k / (2.0 * 1.5 * 1.5)));
  double ma = 0, mb = 0;
  for (int j = -5; j <= 5; ++j)
    for (int i = -5; i <= 5; ++i) {
      const double w = g[i + 5] * g[j + 5] / (gs * gs);
      ma += w * a[(y + j) * width + x + i];
      mb += w * b[(y + j) * width + x + i];
    }
  double va = 0, vb = 0, cab = 0;
  for (int j = -5; j <= 5; ++j)
    for (int i = -5; i <= 5; ++i) {
      const double w = g[i + 5] * g[j + 5] / (gs * gs);
      const double da = a[(y + j) * width + x + i] - ma, db = b[(y + j) * width + x + i] - mb;
      va += w * da * da;
      vb += w * db * db;
      cab += w * da * db;
    }
  return ((2 * ma * mb + kC1) * (2 * cab + kC2)) / ((ma * ma + mb * mb + kC1) * (va + vb + kC2));
}

// The same with the window restricted to the mask and to the image (normalised convolution), by brute
// force in 2-D: checks the separable implementation at the mask's and the image's borders.
double referenceMaskedSsimAt(const std::vector<double>& a, const std::vector<double>& b,
                             const std::vector<std::uint8_t>& m, int width, int height, int x, int y) {
  double sw = 0, ma = 0, mb = 0;
  auto weight = [&](int i, int j) {
    const int xx = x + i, yy = y + j;
    if (xx < 0 || yy < 0 || xx >= width || yy >= height || !m[yy * width + xx]) return 0.0;
    return std::exp(-(i * i + j * j) / (2.0 * 1.5 * 1.5));
  };
  for (int j = -5; j <= 5; ++j)
    for (int i = -5; i <= 5; ++i) {
      const double w = weight(i, j);
      if (w == 0.0) continue;
      sw += w;
      ma += w * a[(y + j) * width + x + i];
      mb += w * b[(y + j) * width + x + i];
    }
  ma /= sw;
  mb /= sw;
  double va = 0, vb = 0, cab = 0;
  for (int j = -5; j <= 5; ++j)
    for (int i = -5; i <= 5; ++i) {
      const double w = weight(i, j) / sw;
      if (w == 0.0) continue;
      const double da = a[(y + j) * width + x + i] - ma, db = b[(y + j) * width + x + i] - mb;
      va += w * da * da;
      vb += w * db * db;
      cab += w * da * db;
    }
  return ((2 * ma * mb + kC1) * (2 * cab + kC2)) / ((ma * ma + mb * mb + kC1) * (va + vb + kC2));
}

TEST(Metrics, IdenticalImagesGiveInfinitePsnrAndSsimOne) {
  const Image8 a = textured(64, 48);
  const Scores s = compareImages(a, a, allScored(a));
  EXPECT_TRUE(std::isinf(s.psnr));
  EXPECT_GT(s.psnr, 0.0);
  EXPECT_NEAR(s.ssim, 1.0, 1e-12);
  EXPECT_EQ(s.scoredPixels, 64u * 48u);
  EXPECT_TRUE(std::isinf(psnrFromMse(0.0)));
}

TEST(Metrics, ConstantOffsetGivesExactPsnr) {
  Image8 a = textured(40, 30);
  for (auto& v : a.data) v = std::min<std::uint8_t>(v, 240);  // room for +10 without clamping
  Image8 b = a;
  for (auto& v : b.data) v = std::uint8_t(v + 10);
  const Scores s = compareImages(a, b, allScored(a));
  // MSE = 10^2 on every channel of every pixel.
  EXPECT_DOUBLE_EQ(s.psnr, 10.0 * std::log10(255.0 * 255.0 / 100.0));
  EXPECT_NEAR(s.psnr, 28.1308, 1e-4);
}

TEST(Metrics, RgbaUsesOnlyTheColourChannels) {
  Image8 a = textured(32, 32, 4), b = a;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) b.at(x, y, 3) = std::uint8_t(x * 8);  // alpha differs, colour equal
  const Scores s = compareImages(a, b, allScored(a));
  EXPECT_TRUE(std::isinf(s.psnr));
  EXPECT_NEAR(s.ssim, 1.0, 1e-12);
  // Mixed RGB / RGBA is fine too.
  Image8 rgb(32, 32, 3);
  for (int i = 0; i < 32 * 32; ++i)
    for (int c = 0; c < 3; ++c) rgb.data[i * 3 + c] = a.data[i * 4 + c];
  EXPECT_TRUE(std::isinf(compareImages(rgb, a, allScored(a)).psnr));
}

TEST(Metrics, MaskExcludesCorruptedRegion) {
  const Image8 a = textured(80, 60);
  Image8 b = a;
  std::vector<std::uint8_t> mask = allScored(a);
  for (int y = 20; y < 40; ++y)
    for (int x = 30; x < 50; ++x) {
      for (int c = 0; c < 3; ++c) b.at(x, y, c) = std::uint8_t(255 - b.at(x, y, c));
      mask[y * 80 + x] = 0;
    }
  const Scores unmasked = compareImages(a, b, allScored(a));
  EXPECT_TRUE(std::isfinite(unmasked.psnr));
  EXPECT_LT(unmasked.ssim, 0.95);

  // Excluded, the corruption leaves no trace: not in the MSE and not in the SSIM windows of the
  // scored pixels right next to it.
  const Scores masked = compareImages(a, b, mask);
  EXPECT_TRUE(std::isinf(masked.psnr));
  EXPECT_NEAR(masked.ssim, 1.0, 1e-12);
  EXPECT_EQ(masked.scoredPixels, 80u * 60u - 20u * 20u);

  // With some real error elsewhere, the score equals the score of the images without the corruption.
  const Image8 noisy = addNoise(a, 8.0, 7);
  Image8 noisyCorrupt = noisy;
  for (int y = 20; y < 40; ++y)
    for (int x = 30; x < 50; ++x)
      for (int c = 0; c < 3; ++c) noisyCorrupt.at(x, y, c) = 0;
  const Scores clean = compareImages(a, noisy, mask);
  const Scores corrupt = compareImages(a, noisyCorrupt, mask);
  EXPECT_DOUBLE_EQ(clean.psnr, corrupt.psnr);
  EXPECT_DOUBLE_EQ(clean.ssim, corrupt.ssim);
}

TEST(Metrics, ConstantImagesMatchHandDerivedSsim) {
  // For constant images x = a, y = b the variances and covariance vanish, so eq. (13) reduces to
  // (2ab + C1) / (a^2 + b^2 + C1) times C2 / C2.
  const Image8 a(30, 20, 3, 100), b(30, 20, 3, 120);
  const Scores s = compareImages(a, b, allScored(a));
  const double expected = (2.0 * 100 * 120 + kC1) / (100.0 * 100 + 120.0 * 120 + kC1);
  EXPECT_NEAR(s.ssim, expected, 1e-9);
  EXPECT_NEAR(s.ssim, 24006.5025 / 24406.5025, 1e-9);  // the same, numerically
  EXPECT_DOUBLE_EQ(s.psnr, 10.0 * std::log10(255.0 * 255.0 / 400.0));
}

TEST(Metrics, BrightnessShiftOnFlatRegionMatchesHandDerivedSsim) {
  // Textured image with a flat 24x20 patch of grey 80; in b the patch is 30 levels brighter. Scoring the
  // patch only, every scored window sees only flat, scored pixels (the texture around it is
  // unscored), so every pixel of the map -- border of the patch included -- has the constant-image value.
  Image8 a = textured(64, 48);
  for (int y = 10; y < 30; ++y)
    for (int x = 20; x < 44; ++x)
      for (int c = 0; c < 3; ++c) a.at(x, y, c) = 80;
  Image8 b = a;
  std::vector<std::uint8_t> mask(64 * 48, 0);
  for (int y = 10; y < 30; ++y)
    for (int x = 20; x < 44; ++x) {
      for (int c = 0; c < 3; ++c) b.at(x, y, c) = 110;
      mask[y * 64 + x] = 255;
    }
  const double ya = 0.299 * 80 + 0.587 * 80 + 0.114 * 80, yb = 0.299 * 110 + 0.587 * 110 + 0.114 * 110;
  const double expected = (2.0 * ya * yb + kC1) / (ya * ya + yb * yb + kC1);
  const Scores s = compareImages(a, b, mask);
  EXPECT_EQ(s.scoredPixels, 24u * 20u);
  EXPECT_NEAR(s.ssim, expected, 1e-9);
  EXPECT_DOUBLE_EQ(s.psnr, 10.0 * std::log10(255.0 * 255.0 / 900.0));

  // Scoring everything instead, windows straddling the patch edge mix in the texture: a different value.
  EXPECT_GT(std::abs(compareImages(a, b, allScored(a)).ssim - expected), 1e-3);
}

TEST(Metrics, NoiseLowersSsimSymmetrically) {
  const Image8 a = textured(96, 64);
  const Image8 b = addNoise(a, 12.0, 3);
  const auto mask = allScored(a);
  const Scores ab = compareImages(a, b, mask), ba = compareImages(b, a, mask);
  EXPECT_LT(ab.ssim, 1.0);
  EXPECT_GT(ab.ssim, 0.0);
  EXPECT_NEAR(ab.ssim, ba.ssim, 1e-12);
  EXPECT_DOUBLE_EQ(ab.psnr, ba.psnr);
  // More noise, lower scores.
  const Scores worse = compareImages(a, addNoise(a, 30.0, 3), mask);
  EXPECT_LT(worse.ssim, ab.ssim);
  EXPECT_LT(worse.psnr, ab.psnr);
}

TEST(Metrics, UnscoredBackgroundDoesNotChangeTheScore) {
  const Image8 a = textured(72, 56);
  const Image8 b = addNoise(a, 10.0, 11);
  std::vector<std::uint8_t> mask(72 * 56, 0);
  for (int y = 0; y < 56; ++y)
    for (int x = 0; x < 72; ++x)
      if ((x - 36) * (x - 36) + (y - 28) * (y - 28) < 20 * 20) mask[y * 72 + x] = 1;
  const Scores s = compareImages(a, b, mask);

  // Repaint the background of both images (as two methods with different background colours would).
  Image8 a2 = a, b2 = b;
  for (int i = 0; i < 72 * 56; ++i)
    if (!mask[i])
      for (int c = 0; c < 3; ++c) {
        a2.data[i * 3 + c] = 0;
        b2.data[i * 3 + c] = std::uint8_t(c == 0 ? 255 : i % 256);
      }
  const Scores s2 = compareImages(a2, b2, mask);
  EXPECT_EQ(s.scoredPixels, s2.scoredPixels);
  EXPECT_DOUBLE_EQ(s.psnr, s2.psnr);
  EXPECT_DOUBLE_EQ(s.ssim, s2.ssim);
}

TEST(Metrics, AllOnesMaskInteriorEqualsStandardSsim) {
  const Image8 a = textured(48, 40), b = addNoise(a, 15.0, 5);
  const std::vector<double> ya = luma(a), yb = luma(b);
  const auto map = ssimMap(ya, yb, 48, 40, allScored(a));
  for (int y = 5; y < 40 - 5; ++y)
    for (int x = 5; x < 48 - 5; ++x) ASSERT_NEAR(map[y * 48 + x], referenceSsimAt(ya, yb, 48, x, y), 1e-10);
}

TEST(Metrics, MaskedMapEqualsBruteForceNormalisedConvolution) {
  // Ragged masks (3/4 scored) on images larger and smaller than the window, so that the separable
  // filter's clipping at the image border and at the mask is checked against the 2-D definition.
  const int sizes[][2] = {{40, 36}, {7, 4}, {1, 1}, {12, 3}, {3, 17}};
  for (const auto& size : sizes) {
    const int w = size[0], h = size[1];
    const Image8 a = textured(w, h, 3, 4), b = addNoise(a, 20.0, 9);
    const std::vector<double> ya = luma(a), yb = luma(b);
    std::vector<std::uint8_t> mask(std::size_t(w) * h, 0);
    std::mt19937 rng(2);
    for (auto& m : mask) m = std::uint8_t(rng() % 4 != 0);
    mask[0] = 1;
    const auto map = ssimMap(ya, yb, w, h, mask);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (!mask[y * w + x]) {
          ASSERT_TRUE(std::isnan(map[y * w + x]));
          continue;
        }
        ASSERT_NEAR(map[y * w + x], referenceMaskedSsimAt(ya, yb, mask, w, h, x, y), 1e-9)
            << w << "x" << h << " at " << x << "," << y;
      }
  }
}

TEST(Metrics, SizeMismatchThrows) {
  const Image8 a(10, 8, 3), b(10, 9, 3);
  try {
    compareImages(a, b, std::vector<std::uint8_t>(80, 1));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("10x8x3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("10x9x3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(compareImages(a, a, std::vector<std::uint8_t>(79, 1)), std::invalid_argument);
  EXPECT_THROW(compareImages(Image8(10, 8, 1), Image8(10, 8, 1), std::vector<std::uint8_t>(80, 1)),
               std::invalid_argument);
}

TEST(Metrics, NothingScoredGivesNaN) {
  const Image8 a = textured(16, 16);
  const Scores s = compareImages(a, a, std::vector<std::uint8_t>(256, 0));
  EXPECT_EQ(s.scoredPixels, 0u);
  EXPECT_TRUE(std::isnan(s.psnr));
  EXPECT_TRUE(std::isnan(s.ssim));
}

TEST(Metrics, HdFrameIsFast) {
  const Image8 a = textured(1280, 720), b = addNoise(a, 10.0, 1);
  const auto mask = allScored(a);
  const auto t0 = std::chrono::steady_clock::now();
  const Scores s = compareImages(a, b, mask);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("compareImages 1280x720: %.1f ms (PSNR %.2f dB, SSIM %.4f)\n", ms, s.psnr, s.ssim);
  EXPECT_LT(s.ssim, 1.0);
  // A generous bound so debug and sanitizer builds pass; the printed figure is the measurement.
  EXPECT_LT(ms, 5000.0);
}

// A grey pixel's luma is its value (0.299 + 0.587 + 0.114 = 1).
Image8 greyRow(const std::vector<int>& values, int width, int channels = 3) {
  Image8 im(width, int(values.size()) / width, channels, 255);
  for (std::size_t i = 0; i < values.size(); ++i)
    for (int c = 0; c < 3; ++c) im.data[i * std::size_t(channels) + std::size_t(c)] = std::uint8_t(values[i]);
  return im;
}

Image16 countsOf(const std::vector<int>& values, int width) {
  Image16 im(width, int(values.size()) / width, 1, 0);
  for (std::size_t i = 0; i < values.size(); ++i) im.data[i] = std::uint16_t(values[i]);
  return im;
}

TEST(BorderSeams, StepsAcrossPairsWhoseCountsDiffer) {
  // 3 x 2: count borders between columns 0|1 (both rows) and between rows in column 2.
  //   render        truth         counts
  //   0  100 100    0  50 100     1 2 2
  //   0  100  40    0  50  90     1 2 3
  const Image8 render = greyRow({0, 100, 100, 0, 100, 40}, 3), truth = greyRow({0, 50, 100, 0, 50, 90}, 3);
  const Image16 counts = countsOf({1, 2, 2, 1, 2, 3}, 3);
  const std::vector<std::uint8_t> all(6, 1);
  // Pairs: (0,1) r 100 t 50; (3,4) r 100 t 50; (4,5) r 60 t 40; (2,5) r 60 t 10.
  const BorderSeams s = borderSeams(render, truth, counts, all);
  EXPECT_EQ(s.pairs, 4u);
  EXPECT_NEAR(s.renderStep, (100 + 100 + 60 + 60) / 4.0, 1e-9);
  EXPECT_NEAR(s.truthStep, (50 + 50 + 40 + 10) / 4.0, 1e-9);
  EXPECT_NEAR(s.excess, s.renderStep - s.truthStep, 1e-12);
  // A pixel left unscored takes its pairs out: without pixel 5, only the two column pairs remain.
  std::vector<std::uint8_t> some = all;
  some[5] = 0;
  const BorderSeams t = borderSeams(render, truth, counts, some);
  EXPECT_EQ(t.pairs, 2u);
  EXPECT_NEAR(t.excess, 50.0, 1e-9);
}

TEST(BorderSeams, NoBorderIsNaNAndSizesAreChecked) {
  const Image8 a = greyRow({10, 20, 30, 40}, 2);
  const BorderSeams s = borderSeams(a, a, countsOf({2, 2, 2, 2}, 2), std::vector<std::uint8_t>(4, 1));
  EXPECT_EQ(s.pairs, 0u);
  EXPECT_TRUE(std::isnan(s.excess));
  EXPECT_THROW(borderSeams(a, a, countsOf({2, 2}, 2), std::vector<std::uint8_t>(4, 1)), std::invalid_argument);
}

TEST(FrameDifference, MeanOverPixelsBothFramesCover) {
  // RGBA frames, 2 x 1. Frame 1's second pixel is uncovered: that pair counts pixel 0 only.
  Image8 f0 = greyRow({10, 20}, 2, 4), f1 = greyRow({30, 99}, 2, 4), f2 = greyRow({30, 26}, 2, 4);
  f1.data[7] = 0;
  // Pair (0,1): |10 - 30| = 20 (one pixel). Pair (1,2): pixel 0: 0; pixel 1 uncovered in f1.
  EXPECT_NEAR(meanFrameDifference({f0, f1, f2}), (20.0 + 0.0) / 2.0, 1e-9);
  // RGB frames cover every pixel: |10-30| + |20-26| over 2.
  EXPECT_NEAR(meanFrameDifference({greyRow({10, 20}, 2), greyRow({30, 26}, 2)}), 13.0, 1e-9);
  EXPECT_TRUE(std::isnan(meanFrameDifference({f0})));
  EXPECT_THROW(meanFrameDifference({f0, greyRow({1, 2, 3}, 3, 4)}), std::invalid_argument);
}

}  // namespace
}  // namespace hv::eval
