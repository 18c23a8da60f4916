#include "hv/ibr/colour_correction.h"

#include "hv/ibr/reference_blend.h"

#include <algorithm>
#include <cmath>

namespace hv::ibr {

namespace {

// The straight colour of a premultiplied RGBA8 texture at `uv` (bilinear, as the shader samples),
// and its alpha.
glm::dvec4 straightColour(const Image8& texels, glm::dvec2 uv) {
  const glm::dvec4 t = sampleBilinear(texels, uv);
  if (t.a <= 0.0) return glm::dvec4(0.0);
  return {glm::dvec3(t) / t.a, t.a};
}

bool saturated(const glm::dvec3& c, double limit) { return c.r >= limit || c.g >= limit || c.b >= limit; }

double huberWeight(double r, double delta) {
  const double a = std::abs(r);
  return a <= delta ? 1.0 : delta / a;
}

// Solves A x = b for a symmetric positive definite A (n x n, row-major) by Cholesky; A is
// overwritten. Returns false when A is not positive definite.
bool solveSpd(std::vector<double>& A, std::vector<double>& b, size_t n) {
  for (size_t j = 0; j < n; ++j) {
    double d = A[j * n + j];
    for (size_t k = 0; k < j; ++k) d -= A[j * n + k] * A[j * n + k];
    if (!(d > 0.0)) return false;
    const double l = std::sqrt(d);
    A[j * n + j] = l;
    for (size_t i = j + 1; i < n; ++i) {
      double s = A[i * n + j];
      for (size_t k = 0; k < j; ++k) s -= A[i * n + k] * A[j * n + k];
      A[i * n + j] = s / l;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    double s = b[i];
    for (size_t k = 0; k < i; ++k) s -= A[i * n + k] * b[k];
    b[i] = s / A[i * n + i];
  }
  for (size_t i = n; i-- > 0;) {
    double s = b[i];
    for (size_t k = i + 1; k < n; ++k) s -= A[k * n + i] * b[k];
    b[i] = s / A[i * n + i];
  }
  return true;
}

// A typical colour: scales the gain's deviation from 1 into colour units for its prior.
constexpr double kTypicalColour = 0.5;
// The gauge penalty's weight, relative to a photograph's mean pair weight.
constexpr double kGaugeStiffness = 1e4;
// The least spread (standard deviation) of a photograph's colours in its pairs, per channel, for
// its gain to be left to the overlaps alone.
constexpr double kMinSpread = 0.05;

// The median (the mean of the two middle values for an even count); 0 when empty.
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + long(m), v.end());
  const double hi = v[m];
  if (v.size() % 2 == 1) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + long(m)));
}

}  // namespace

std::vector<ColourPair> collectColourPairs(const std::vector<OverlapImage>& images, const RayQuery& geometry,
                                           const HarmonizeSettings& s) {
  std::vector<ColourPair> pairs;
  for (size_t a = 0; a < images.size(); ++a) {
    const OverlapImage& A = images[a];
    if (!A.texels || A.texels->empty() || A.camera.width <= 0 || A.camera.height <= 0) continue;
    const Camera& ca = A.camera;
    const double step = std::max(1.0, std::sqrt(double(ca.width) * ca.height / double(std::max(s.samplesPerImage, 1))));
    for (double y = 0.5 * step; y < ca.height; y += step) {
      for (double x = 0.5 * step; x < ca.width; x += step) {
        const glm::dvec2 pxDistorted(x, y);
        const glm::dvec4 colourA = straightColour(*A.texels, pxDistorted * A.uvScale);
        if (colourA.a < s.minAlpha || saturated(glm::dvec3(colourA), s.saturated)) continue;
        const auto pxIdeal = ca.undistort(pxDistorted);
        if (!pxIdeal) continue;
        const glm::dvec3 dirA = glm::normalize(ca.rayDirection(*pxIdeal));
        const auto hit = geometry.intersect(ca.center, dirA);
        if (!hit) continue;
        if (std::abs(glm::dot(hit->normal, dirA)) < s.minCosine) continue;
        const glm::dvec3 P = hit->position;
        for (size_t b = 0; b < images.size(); ++b) {
          const OverlapImage& B = images[b];
          if (b == a || !B.texels || B.texels->empty()) continue;
          const Projection pb = B.camera.project(P);
          if (!pb.inImage) continue;
          const glm::dvec3 toP = P - B.camera.center;
          const double distance = glm::length(toP);
          if (distance <= 0.0) continue;
          const glm::dvec3 dirB = toP / distance;
          if (std::abs(glm::dot(hit->normal, dirB)) < s.minCosine) continue;
          const double tMax = distance * (1.0 - s.occlusionTolerance) - 0.01;
          if (tMax > 0.0 && geometry.occluded(B.camera.center, dirB, 0.0, tMax)) continue;
          const glm::dvec4 colourB = straightColour(*B.texels, pb.pxDistorted * B.uvScale);
          if (colourB.a < s.minAlpha || saturated(glm::dvec3(colourB), s.saturated)) continue;
          pairs.push_back({int(a), int(b), glm::dvec3(colourA), glm::dvec3(colourB)});
        }
      }
    }
  }
  return pairs;
}

HarmonizeResult solveColourCorrections(size_t photos, const std::vector<ColourPair>& pairs,
                                       const HarmonizeSettings& s) {
  HarmonizeResult out;
  out.corrections.assign(photos, ColourCorrection{});
  out.pairsPerPhoto.assign(photos, 0);
  std::vector<ColourPair> valid;
  valid.reserve(pairs.size());
  for (const ColourPair& p : pairs)
    if (p.a >= 0 && p.b >= 0 && size_t(p.a) < photos && size_t(p.b) < photos && p.a != p.b) {
      valid.push_back(p);
      ++out.pairsPerPhoto[size_t(p.a)];
      ++out.pairsPerPhoto[size_t(p.b)];
    }
  if (photos == 0) return out;

  // The connected sets of photographs (linked by pairs): each has its own gauge.
  std::vector<size_t> parent(photos);
  for (size_t i = 0; i < photos; ++i) parent[i] = i;
  auto root = [&](size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const ColourPair& p : valid) parent[root(size_t(p.a))] = root(size_t(p.b));
  std::vector<std::vector<size_t>> sets;
  {
    std::vector<long> setOf(photos, -1);
    for (size_t i = 0; i < photos; ++i) {
      if (out.pairsPerPhoto[i] == 0) continue;  // no pairs: stays the identity
      const size_t r = root(i);
      if (setOf[r] < 0) {
        setOf[r] = long(sets.size());
        sets.emplace_back();
      }
      sets[size_t(setOf[r])].push_back(i);
    }
  }

  // Unknowns per channel: x = (dg_0, o_0, dg_1, o_1, ...), gain g_i = 1 + dg_i. The residual of a
  // pair is r = (c_a - c_b) + dg_a c_a + o_a - dg_b c_b - o_b, linear in x.
  const size_t n = 2 * photos;
  for (int ch = 0; ch < 3; ++ch) {
    // The spread of each photograph's own colours in its pairs: with little spread, its gain and
    // offset trade against each other (only g c + o at that colour is seen). Such a gain is held
    // towards 1 as if its colours spread at least kMinSpread, and it takes no part in the gauge
    // (a free gain there would carry the gauge anywhere).
    std::vector<double> sum(photos, 0.0), sum2(photos, 0.0), count(photos, 0.0), variance(photos, 0.0);
    for (const ColourPair& p : valid) {
      for (const auto& [i, c] : {std::pair{size_t(p.a), p.ca[ch]}, std::pair{size_t(p.b), p.cb[ch]}}) {
        sum[i] += c;
        sum2[i] += c * c;
        count[i] += 1.0;
      }
    }
    for (size_t i = 0; i < photos; ++i)
      if (count[i] > 0.0) variance[i] = std::max(0.0, sum2[i] / count[i] - (sum[i] / count[i]) * (sum[i] / count[i]));
    const double minVariance = kMinSpread * kMinSpread;
    std::vector<std::vector<size_t>> gauges;
    for (const std::vector<size_t>& set : sets) {
      std::vector<size_t> spread;
      for (size_t i : set)
        if (variance[i] >= minVariance) spread.push_back(i);
      gauges.push_back(spread.empty() ? set : spread);
    }
    std::vector<double> x(n, 0.0);
    std::vector<double> w(valid.size(), 1.0);
    for (int it = 0; it < std::max(s.iterations, 1); ++it) {
      std::vector<double> H(n * n, 0.0), g(n, 0.0), weightOf(photos, 0.0);
      for (size_t k = 0; k < valid.size(); ++k) {
        const ColourPair& p = valid[k];
        const double ca = p.ca[ch], cb = p.cb[ch];
        const size_t ia = 2 * size_t(p.a), ib = 2 * size_t(p.b);
        // J = d r / d x: +ca at dg_a, +1 at o_a, -cb at dg_b, -1 at o_b.
        const size_t idx[4] = {ia, ia + 1, ib, ib + 1};
        const double J[4] = {ca, 1.0, -cb, -1.0};
        const double r0 = ca - cb;
        for (int u = 0; u < 4; ++u) {
          g[idx[u]] -= w[k] * J[u] * r0;
          for (int v = 0; v < 4; ++v) H[idx[u] * n + idx[v]] += w[k] * J[u] * J[v];
        }
        weightOf[size_t(p.a)] += w[k];
        weightOf[size_t(p.b)] += w[k];
      }
      // The gauge while solving: in each connected set, mean gain 1 and mean offset 0, held by a
      // stiff penalty mu ((sum dg_i) t)^2 + mu (sum o_i)^2 (without it the overlaps are as well
      // met by shrinking every gain towards 0, which makes all colours agree).
      for (const std::vector<size_t>& set : gauges) {
        double total = 0.0;
        for (size_t i : set) total += weightOf[i];
        const double mu = kGaugeStiffness * std::max(total, 1.0) / double(set.size());
        for (size_t i : set)
          for (size_t j : set) {
            H[(2 * i) * n + 2 * j] += mu * kTypicalColour * kTypicalColour;
            H[(2 * i + 1) * n + 2 * j + 1] += mu;
          }
      }
      // The prior: lambda_i ((dg_i t)^2 + o_i^2), relative to the photograph's pair weight (at
      // least one pair's worth, so that a photograph without pairs stays the identity).
      for (size_t i = 0; i < photos; ++i) {
        const double lambda = s.prior * std::max(weightOf[i], 1.0);
        H[(2 * i) * n + 2 * i] += lambda * kTypicalColour * kTypicalColour +
                                  std::max(weightOf[i], 1.0) * std::max(0.0, minVariance - variance[i]);
        H[(2 * i + 1) * n + 2 * i + 1] += lambda;
      }
      std::vector<double> sol = g;
      if (!solveSpd(H, sol, n)) break;
      x = sol;
      for (size_t k = 0; k < valid.size(); ++k) {
        const ColourPair& p = valid[k];
        const size_t ia = 2 * size_t(p.a), ib = 2 * size_t(p.b);
        const double r = (p.ca[ch] - p.cb[ch]) + x[ia] * p.ca[ch] + x[ia + 1] - x[ib] * p.cb[ch] - x[ib + 1];
        w[k] = huberWeight(r, s.huber);
      }
    }
    // The gauge kept: in each connected set, the common affine map c -> a c + b that brings the
    // median gain to 1 and the median offset to 0 (the overlaps do not change under it). So the
    // photographs that agree define the reference, and a few cast ones do not shift it.
    for (size_t k = 0; k < sets.size(); ++k) {
      std::vector<double> gains, offsets;
      for (size_t i : gauges[k]) gains.push_back(1.0 + x[2 * i]);
      const double mg = median(gains);
      const double a = mg > 0.0 ? 1.0 / mg : 1.0;
      for (size_t i : gauges[k]) offsets.push_back(a * x[2 * i + 1]);
      const double b = -median(offsets);
      for (size_t i : sets[k]) {
        out.corrections[i].gain[ch] = a * (1.0 + x[2 * i]);
        out.corrections[i].offset[ch] = a * x[2 * i + 1] + b;
      }
    }
  }

  // Statistics over the pairs (the three channels together).
  double before = 0.0, after = 0.0, inBefore = 0.0, inAfter = 0.0;
  size_t inliers = 0;
  for (const ColourPair& p : valid) {
    const glm::dvec3 d0 = p.ca - p.cb;
    const glm::dvec3 d1 = (out.corrections[size_t(p.a)].gain * p.ca + out.corrections[size_t(p.a)].offset) -
                          (out.corrections[size_t(p.b)].gain * p.cb + out.corrections[size_t(p.b)].offset);
    before += glm::dot(d0, d0);
    after += glm::dot(d1, d1);
    if (std::max({std::abs(d1.r), std::abs(d1.g), std::abs(d1.b)}) <= s.huber) {
      inBefore += glm::dot(d0, d0);
      inAfter += glm::dot(d1, d1);
      ++inliers;
    }
  }
  if (!valid.empty()) {
    out.rmsBefore = std::sqrt(before / (3.0 * double(valid.size())));
    out.rmsAfter = std::sqrt(after / (3.0 * double(valid.size())));
  }
  if (inliers > 0) {
    out.inlierRmsBefore = std::sqrt(inBefore / (3.0 * double(inliers)));
    out.inlierRmsAfter = std::sqrt(inAfter / (3.0 * double(inliers)));
  }
  return out;
}

}  // namespace hv::ibr
