#include "hv/eval/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hv::eval {

namespace {

// Wang et al. 2004, section III.C: an 11x11 circular-symmetric Gaussian window, sigma 1.5. The 2-D
// window is the outer product of this 1-D kernel, which is what makes the filtering separable.
constexpr int kRadius = 5;
constexpr double kSigma = 1.5;
// Wang et al. 2004, eq. (13) with K1 = 0.01, K2 = 0.03, L = 255 (8-bit dynamic range).
constexpr double kC1 = (0.01 * 255.0) * (0.01 * 255.0);
constexpr double kC2 = (0.03 * 255.0) * (0.03 * 255.0);

std::array<double, 2 * kRadius + 1> gaussianKernel() {
  std::array<double, 2 * kRadius + 1> g{};
  double sum = 0.0;
  for (int k = -kRadius; k <= kRadius; ++k) {
    g[k + kRadius] = std::exp(-double(k * k) / (2.0 * kSigma * kSigma));
    sum += g[k + kRadius];
  }
  // Normalisation cancels in the normalised convolution; kept so the weights match fspecial's.
  for (double& v : g) v /= sum;
  return g;
}

std::string describe(const Image8& im) {
  return std::to_string(im.width) + "x" + std::to_string(im.height) + "x" + std::to_string(im.channels);
}

// The six windowed sums the local statistics need, per pixel: sum w, sum w x, sum w y, sum w x^2,
// sum w y^2, sum w x y, with w = window weight * mask.
constexpr int kFields = 6;

}  // namespace

double psnrFromMse(double mse) {
  if (mse <= 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

std::size_t countScored(const std::vector<std::uint8_t>& scored) {
  return std::size_t(std::count_if(scored.begin(), scored.end(), [](std::uint8_t v) { return v != 0; }));
}

std::vector<double> luma(const Image8& image) {
  if (image.channels < 3)
    throw std::invalid_argument("luma: need an RGB or RGBA image, got " + describe(image));
  const std::size_t n = std::size_t(image.width) * image.height;
  std::vector<double> y(n);
  const std::uint8_t* p = image.data.data();
  for (std::size_t i = 0; i < n; ++i, p += image.channels) y[i] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  return y;
}

std::vector<double> ssimMap(const std::vector<double>& lumaA, const std::vector<double>& lumaB, int width,
                            int height, const std::vector<std::uint8_t>& scored) {
  const std::size_t n = std::size_t(std::max(width, 0)) * std::size_t(std::max(height, 0));
  if (width < 0 || height < 0 || lumaA.size() != n || lumaB.size() != n || scored.size() != n)
    throw std::invalid_argument("ssimMap: expected " + std::to_string(width) + "x" + std::to_string(height) +
                                " values, got " + std::to_string(lumaA.size()) + ", " +
                                std::to_string(lumaB.size()) + " and a mask of " +
                                std::to_string(scored.size()));
  const auto g = gaussianKernel();
  const std::size_t w = std::size_t(width);
  std::vector<double> map(n, std::numeric_limits<double>::quiet_NaN());
  if (n == 0) return map;

  // Pass 1, horizontal: the products of the masked samples, filtered along one row into `out`
  // (kFields planes of w values). Samples outside the image are simply absent, exactly like unscored
  // ones, so the border needs no padding convention.
  std::vector<double> prod(kFields * w);
  auto filterRow = [&](int y, double* out) {
    const std::size_t row = std::size_t(y) * w;
    for (std::size_t x = 0; x < w; ++x) {
      const double m = scored[row + x] ? 1.0 : 0.0;
      const double a = m * lumaA[row + x], b = m * lumaB[row + x];
      prod[0 * w + x] = m;
      prod[1 * w + x] = a;
      prod[2 * w + x] = b;
      prod[3 * w + x] = a * lumaA[row + x];
      prod[4 * w + x] = b * lumaB[row + x];
      prod[5 * w + x] = a * lumaB[row + x];
    }
    for (int f = 0; f < kFields; ++f) {
      const double* src = prod.data() + f * w;
      double* dst = out + f * w;
      // Clipped taps only near the ends of the row; the fixed-length loop in between vectorises.
      auto clipped = [&](int x) {
        const int k0 = std::max(-kRadius, -x), k1 = std::min(kRadius, width - 1 - x);
        double s = 0.0;
        for (int k = k0; k <= k1; ++k) s += g[k + kRadius] * src[x + k];
        dst[x] = s;
      };
      int x = 0;
      for (; x < std::min(kRadius, width); ++x) clipped(x);
      for (; x < width - kRadius; ++x) {
        double s = 0.0;
        for (int k = 0; k <= 2 * kRadius; ++k) s += g[k] * src[x - kRadius + k];
        dst[x] = s;
      }
      for (; x < width; ++x) clipped(x);
    }
  };

  // Pass 2, vertical, one output row at a time from a ring of the 11 horizontally filtered rows it
  // needs (small enough to stay in cache, unlike six full-image planes), then the SSIM formula at the
  // scored pixels of that row.
  constexpr int kTaps = 2 * kRadius + 1;
  std::vector<double> ring(std::size_t(kTaps) * kFields * w);
  auto ringRow = [&](int y) { return ring.data() + std::size_t(y % kTaps) * kFields * w; };
  int filteredUpTo = -1;
  std::vector<double> acc(kFields * w);
  for (int y = 0; y < height; ++y) {
    const int k0 = std::max(-kRadius, -y), k1 = std::min(kRadius, height - 1 - y);
    while (filteredUpTo < y + k1) {
      ++filteredUpTo;
      filterRow(filteredUpTo, ringRow(filteredUpTo));
    }
    std::fill(acc.begin(), acc.end(), 0.0);
    for (int k = k0; k <= k1; ++k) {
      const double gk = g[k + kRadius];
      const double* src = ringRow(y + k);
      for (std::size_t i = 0; i < kFields * w; ++i) acc[i] += gk * src[i];
    }
    const std::size_t row = std::size_t(y) * w;
    for (std::size_t x = 0; x < w; ++x) {
      if (!scored[row + x]) continue;
      // The pixel itself is scored, so the weight sum is at least the centre weight: no division by 0.
      const double inv = 1.0 / acc[0 * w + x];
      const double muA = acc[1 * w + x] * inv, muB = acc[2 * w + x] * inv;
      // Weighted (biased) moments, as in Wang et al. 2004, eqs. (14)-(16) with weights summing to 1.
      const double varA = acc[3 * w + x] * inv - muA * muA;
      const double varB = acc[4 * w + x] * inv - muB * muB;
      const double cov = acc[5 * w + x] * inv - muA * muB;
      // Wang et al. 2004, eq. (13):
      //   SSIM = (2 mu_x mu_y + C1)(2 sigma_xy + C2) / ((mu_x^2 + mu_y^2 + C1)(sigma_x^2 + sigma_y^2 + C2)).
      map[row + x] = ((2.0 * muA * muB + kC1) * (2.0 * cov + kC2)) /
                     ((muA * muA + muB * muB + kC1) * (varA + varB + kC2));
    }
  }
  return map;
}

Scores compareImages(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& scored) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("compareImages: image sizes differ: " + describe(a) + " vs " + describe(b));
  if (a.channels < 3 || b.channels < 3 || a.channels > 4 || b.channels > 4)
    throw std::invalid_argument("compareImages: need RGB or RGBA images, got " + describe(a) + " and " +
                                describe(b));
  const std::size_t n = std::size_t(a.width) * a.height;
  if (scored.size() != n)
    throw std::invalid_argument("compareImages: mask has " + std::to_string(scored.size()) +
                                " bytes for a " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                " image");

  Scores s;
  s.scoredPixels = countScored(scored);
  if (s.scoredPixels == 0) {
    s.psnr = s.ssim = std::numeric_limits<double>::quiet_NaN();
    return s;
  }

  // Integer accumulation: exact, so identical images give MSE 0 (infinite PSNR) and a constant
  // offset d gives MSE d^2 exactly.
  std::uint64_t sse = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!scored[i]) continue;
    const std::uint8_t* pa = a.data.data() + i * a.channels;
    const std::uint8_t* pb = b.data.data() + i * b.channels;
    for (int c = 0; c < 3; ++c) {
      const int d = int(pa[c]) - int(pb[c]);
      sse += std::uint64_t(d * d);
    }
  }
  s.psnr = psnrFromMse(double(sse) / (3.0 * double(s.scoredPixels)));

  const std::vector<double> map = ssimMap(luma(a), luma(b), a.width, a.height, scored);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    if (scored[i]) sum += map[i];
  s.ssim = sum / double(s.scoredPixels);
  return s;
}

}  // namespace hv::eval

namespace hv::eval {

BorderSeams borderSeams(const Image8& render, const Image8& truth, const Image16& counts,
                        const std::vector<std::uint8_t>& scored) {
  const int w = render.width, h = render.height;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  if (truth.width != w || truth.height != h || counts.width != w || counts.height != h || scored.size() != n ||
      counts.channels < 1)
    throw std::invalid_argument("borderSeams: the render (" + std::to_string(w) + "x" + std::to_string(h) +
                                "), truth (" + std::to_string(truth.width) + "x" + std::to_string(truth.height) +
                                "), counts (" + std::to_string(counts.width) + "x" + std::to_string(counts.height) +
                                ") and scored mask (" + std::to_string(scored.size()) + " bytes) differ in size");
  const std::vector<double> lr = luma(render), lt = luma(truth);
  auto count = [&](std::size_t i) { return counts.data[i * std::size_t(counts.channels)]; };
  BorderSeams out;
  double sumR = 0.0, sumT = 0.0;
  auto pair = [&](std::size_t p, std::size_t q) {
    if (!scored[p] || !scored[q] || count(p) == count(q)) return;
    sumR += std::abs(lr[p] - lr[q]);
    sumT += std::abs(lt[p] - lt[q]);
    ++out.pairs;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
      if (x + 1 < w) pair(p, p + 1);
      if (y + 1 < h) pair(p, p + std::size_t(w));
    }
  if (out.pairs == 0) {
    out.renderStep = out.truthStep = out.excess = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  out.renderStep = sumR / double(out.pairs);
  out.truthStep = sumT / double(out.pairs);
  out.excess = out.renderStep - out.truthStep;
  return out;
}

double meanFrameDifference(const std::vector<Image8>& frames) {
  double sum = 0.0;
  std::size_t pixels = 0;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    const Image8& a = frames[k - 1];
    const Image8& b = frames[k];
    if (a.width != b.width || a.height != b.height)
      throw std::invalid_argument("meanFrameDifference: frame " + std::to_string(k) + " is " +
                                  std::to_string(b.width) + "x" + std::to_string(b.height) + ", frame " +
                                  std::to_string(k - 1) + " " + std::to_string(a.width) + "x" +
                                  std::to_string(a.height));
    const std::vector<double> la = luma(a), lb = luma(b);
    for (std::size_t i = 0; i < la.size(); ++i) {
      const bool covered = (a.channels < 4 || a.data[4 * i + 3] > 0) && (b.channels < 4 || b.data[4 * i + 3] > 0);
      if (!covered) continue;
      sum += std::abs(la[i] - lb[i]);
      ++pixels;
    }
  }
  return pixels > 0 ? sum / double(pixels) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace hv::eval
