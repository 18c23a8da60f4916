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

// The local colour gradient of a texture at `uv`, per channel, in colour per texel (central
// differences one texel either side, straight colours).
glm::dvec3 gradient(const Image8& texels, glm::dvec2 uv) {
  const glm::dvec2 du(1.0 / texels.width, 0.0), dv(0.0, 1.0 / texels.height);
  const glm::dvec3 gx =
      0.5 * (glm::dvec3(straightColour(texels, uv + du)) - glm::dvec3(straightColour(texels, uv - du)));
  const glm::dvec3 gy =
      0.5 * (glm::dvec3(straightColour(texels, uv + dv)) - glm::dvec3(straightColour(texels, uv - dv)));
  return glm::sqrt(gx * gx + gy * gy);
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
        const glm::dvec3 textureA = gradient(*A.texels, pxDistorted * A.uvScale);
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
          const glm::dvec3 texture = glm::max(textureA, gradient(*B.texels, pb.pxDistorted * B.uvScale));
          pairs.push_back({int(a), int(b), glm::dvec3(colourA), glm::dvec3(colourB), texture});
        }
      }
    }
  }
  return pairs;
}

namespace {

// Tukey's biweight: (1 - (r/c)^2)^2 within c, 0 beyond.
double tukeyWeight(double r, double c) {
  const double u = r / c;
  return std::abs(u) < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
}

// How the pair residuals are weighted in one run of iteratively reweighted least squares.
struct Robust {
  bool tukey = false;  // false: Huber's
  double scale = 0.05;
  double operator()(double r) const { return tukey ? tukeyWeight(r, scale) : huberWeight(r, scale); }
};

// The residual of pair p in channel ch under x (x = (dg_0, o_0, dg_1, o_1, ...)).
double residual(const ColourPair& p, int ch, const std::vector<double>& x) {
  const size_t ia = 2 * size_t(p.a), ib = 2 * size_t(p.b);
  return (p.ca[ch] - p.cb[ch]) + x[ia] * p.ca[ch] + x[ia + 1] - x[ib] * p.cb[ch] - x[ib + 1];
}

// One channel, by iteratively reweighted least squares from `x` (the weights are those of the
// residuals under it, times each pair's base weight): sum_pairs w rho(r) + prior + gauge penalty.
// `held` adds to a gain's prior what its photograph's colours lack of spread (see the caller).
std::vector<double> solveChannel(size_t photos, const std::vector<ColourPair>& pairs, const std::vector<double>& base,
                                 int ch, const std::vector<std::vector<size_t>>& gauges,
                                 const std::vector<double>& held, double prior, Robust robust, int iterations,
                                 std::vector<double> x) {
  const size_t n = 2 * photos;
  for (int it = 0; it < iterations; ++it) {
    std::vector<double> H(n * n, 0.0), g(n, 0.0), weightOf(photos, 0.0);
    for (size_t k = 0; k < pairs.size(); ++k) {
      const ColourPair& p = pairs[k];
      const double w = base[k] * robust(residual(p, ch, x));
      if (w <= 0.0) continue;
      const double ca = p.ca[ch], cb = p.cb[ch];
      const size_t ia = 2 * size_t(p.a), ib = 2 * size_t(p.b);
      // J = d r / d x: +ca at dg_a, +1 at o_a, -cb at dg_b, -1 at o_b.
      const size_t idx[4] = {ia, ia + 1, ib, ib + 1};
      const double J[4] = {ca, 1.0, -cb, -1.0};
      const double r0 = ca - cb;
      for (int u = 0; u < 4; ++u) {
        g[idx[u]] -= w * J[u] * r0;
        for (int v = 0; v < 4; ++v) H[idx[u] * n + idx[v]] += w * J[u] * J[v];
      }
      weightOf[size_t(p.a)] += w;
      weightOf[size_t(p.b)] += w;
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
      const double lambda = prior * std::max(weightOf[i], 1.0);
      H[(2 * i) * n + 2 * i] += lambda * kTypicalColour * kTypicalColour + std::max(weightOf[i], 1.0) * held[i];
      H[(2 * i + 1) * n + 2 * i + 1] += lambda;
    }
    std::vector<double> sol = g;
    if (!solveSpd(H, sol, n)) break;
    x = sol;
  }
  return x;
}

// The mean and covariance of each photograph's own colours in its pairs; a photograph is
// monochrome when its colours spread (total standard deviation at least kMinSpread) but lie on a
// line: the rms distance to their principal axis, sqrt(trace - largest eigenvalue), is at most
// `spread`.
std::vector<bool> findMonochrome(size_t photos, const std::vector<ColourPair>& pairs, double spread) {
  std::vector<bool> mono(photos, false);
  if (spread <= 0.0) return mono;
  std::vector<glm::dvec3> sum(photos, glm::dvec3(0.0));
  std::vector<glm::dmat3> sum2(photos, glm::dmat3(0.0));
  std::vector<double> count(photos, 0.0);
  for (const ColourPair& p : pairs)
    for (const auto& [i, c] : {std::pair{size_t(p.a), p.ca}, std::pair{size_t(p.b), p.cb}}) {
      sum[i] += c;
      sum2[i] += glm::outerProduct(c, c);
      count[i] += 1.0;
    }
  size_t withPairs = 0, monochrome = 0;
  for (size_t i = 0; i < photos; ++i) {
    if (count[i] < 2.0) continue;
    ++withPairs;
    const glm::dvec3 mean = sum[i] / count[i];
    const glm::dmat3 cov = sum2[i] / count[i] - glm::outerProduct(mean, mean);
    const double trace = cov[0][0] + cov[1][1] + cov[2][2];
    if (trace < kMinSpread * kMinSpread) continue;
    glm::dvec3 v(1.0);  // the largest eigenvalue, by power iteration (cov is symmetric, >= 0)
    double largest = 0.0;
    for (int it = 0; it < 100; ++it) {
      const glm::dvec3 u = cov * v;
      const double len = glm::length(u);
      if (len <= 0.0) break;
      v = u / len;
      largest = glm::dot(v, cov * v);
    }
    if (std::sqrt(std::max(0.0, trace - largest)) <= spread) {
      mono[i] = true;
      ++monochrome;
    }
  }
  // A collection of monochrome photographs only: they are the reference for one another.
  if (monochrome == withPairs) mono.assign(photos, false);
  return mono;
}

// A small deterministic generator (xorshift64*) for the consensus below: the same pairs give the
// same corrections.
struct Rng {
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  size_t below(size_t n) {
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return size_t((state * 0x2545F4914F6CDD1Dull) >> 33) % std::max<size_t>(n, 1);
  }
};

// The affine map t = g c + o that most samples agree with (within `tol`, each counted with its
// weight), by random sampling of two samples (Fischler and Bolles 1981, RANSAC), then refitted by
// weighted least squares on the samples that agree. The identity is the default: another map is
// taken only where kIdentityMargin times as many samples agree with it (a photograph that agrees
// with the others, whose colours cluster, is not carried off by a line through its densest
// cluster). Returns false when no two samples span enough colours.
bool consensusMap(const std::vector<glm::dvec3>& samples, double tol, Rng& rng, double& gain, double& offset) {
  // samples: (c, t, weight)
  constexpr int kHypotheses = 300;
  constexpr double kIdentityMargin = 2.0;
  constexpr double kMinSpan = 0.05;
  auto score = [&](double g, double o) {
    double total = 0.0;
    for (const glm::dvec3& q : samples)
      if (std::abs(g * q.x + o - q.y) <= tol) total += q.z;
    return total;
  };
  double bestG = 1.0, bestO = 0.0, best = score(1.0, 0.0);
  bool found = false;
  for (int h = 0; h < kHypotheses && samples.size() >= 2; ++h) {
    const glm::dvec3& p = samples[rng.below(samples.size())];
    const glm::dvec3& q = samples[rng.below(samples.size())];
    if (std::abs(p.x - q.x) < kMinSpan) continue;
    found = true;
    const double g = (p.y - q.y) / (p.x - q.x), o = p.y - g * p.x;
    if (!(g > 0.2 && g < 5.0)) continue;
    const double sc = score(g, o);
    if (sc > best) best = sc, bestG = g, bestO = o;
  }
  if (best < kIdentityMargin * score(1.0, 0.0)) bestG = 1.0, bestO = 0.0;
  // Least squares on the samples that agree with the best candidate.
  double a00 = 0.0, a01 = 0.0, a11 = 0.0, b0 = 0.0, b1 = 0.0;
  for (const glm::dvec3& q : samples)
    if (std::abs(bestG * q.x + bestO - q.y) <= tol) {
      a00 += q.z * q.x * q.x;
      a01 += q.z * q.x;
      a11 += q.z;
      b0 += q.z * q.x * q.y;
      b1 += q.z * q.y;
    }
  const double det = a00 * a11 - a01 * a01;
  if (det > 1e-12 * std::max(a00 * a11, 1e-300)) {
    const double g = (a11 * b0 - a01 * b1) / det;
    if (g > 0.2 && g < 5.0) bestG = g, bestO = (b1 - g * a01) / a11;
  }
  gain = bestG;
  offset = bestO;
  return found;
}

// A start for the refinement, photograph by photograph: each one's map onto the others' current
// colours that most of its pairs agree with (consensusMap), in a few sweeps (the first against the
// others as they are). Unlike a least-squares start, it does not depend on how far the pairs that
// disagree are: a cast photograph meets the photographs that agree with one another.
std::vector<double> consensusStart(size_t photos, const std::vector<ColourPair>& pairs, const std::vector<double>& base,
                                   int ch, double tol, std::vector<double> x) {
  constexpr size_t kMaxSamples = 4000;
  constexpr int kSweeps = 3;
  std::vector<std::vector<size_t>> of(photos);
  for (size_t k = 0; k < pairs.size(); ++k) {
    of[size_t(pairs[k].a)].push_back(k);
    of[size_t(pairs[k].b)].push_back(k);
  }
  Rng rng;
  for (int sweep = 0; sweep < kSweeps; ++sweep)
    for (size_t i = 0; i < photos; ++i) {
      if (of[i].size() < 2) continue;
      const size_t stride = std::max<size_t>(1, of[i].size() / kMaxSamples);
      std::vector<glm::dvec3> samples;
      for (size_t u = 0; u < of[i].size(); u += stride) {
        const ColourPair& p = pairs[of[i][u]];
        const bool isA = size_t(p.a) == i;
        const size_t j = size_t(isA ? p.b : p.a);
        const double c = isA ? p.ca[ch] : p.cb[ch], cj = isA ? p.cb[ch] : p.ca[ch];
        samples.push_back({c, (1.0 + x[2 * j]) * cj + x[2 * j + 1], base[of[i][u]]});
      }
      double g = 1.0, o = 0.0;
      if (consensusMap(samples, tol, rng, g, o)) {
        x[2 * i] = g - 1.0;
        x[2 * i + 1] = o;
      }
    }
  return x;
}
}  // namespace

HarmonizeResult solveColourCorrections(size_t photos, const std::vector<ColourPair>& pairs,
                                       const HarmonizeSettings& s) {
  HarmonizeResult out;
  out.corrections.assign(photos, ColourCorrection{});
  out.pairsPerPhoto.assign(photos, 0);
  out.monochrome.assign(photos, false);
  std::vector<ColourPair> valid;
  valid.reserve(pairs.size());
  for (const ColourPair& p : pairs)
    if (p.a >= 0 && p.b >= 0 && size_t(p.a) < photos && size_t(p.b) < photos && p.a != p.b) {
      valid.push_back(p);
      ++out.pairsPerPhoto[size_t(p.a)];
      ++out.pairsPerPhoto[size_t(p.b)];
    }
  if (photos == 0) return out;
  out.monochrome = findMonochrome(photos, valid, s.monochromeSpread);
  const std::vector<bool>& mono = out.monochrome;

  // The joint solve takes the pairs between photographs that are not monochrome.
  std::vector<ColourPair> joint;
  std::vector<int> jointPairs(photos, 0);
  for (const ColourPair& p : valid)
    if (!mono[size_t(p.a)] && !mono[size_t(p.b)]) {
      joint.push_back(p);
      ++jointPairs[size_t(p.a)];
      ++jointPairs[size_t(p.b)];
    }

  // The connected sets of photographs (linked by pairs): each has its own gauge.
  std::vector<size_t> parent(photos);
  for (size_t i = 0; i < photos; ++i) parent[i] = i;
  auto root = [&](size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const ColourPair& p : joint) parent[root(size_t(p.a))] = root(size_t(p.b));
  std::vector<std::vector<size_t>> sets;
  {
    std::vector<long> setOf(photos, -1);
    for (size_t i = 0; i < photos; ++i) {
      if (jointPairs[i] == 0) continue;  // no pairs: stays the identity (or is monochrome)
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
    // The base weight of each pair: its texture (a misregistered pair on a flat patch agrees).
    std::vector<double> base(joint.size(), 1.0);
    if (s.textureScale > 0.0)
      for (size_t k = 0; k < joint.size(); ++k) {
        const double t = joint[k].texture[ch] / s.textureScale;
        base[k] = 1.0 / (1.0 + t * t);
      }
    // The spread of each photograph's own colours in its pairs: with little spread, its gain and
    // offset trade against each other (only g c + o at that colour is seen). Such a gain is held
    // towards 1 as if its colours spread at least kMinSpread, and it takes no part in the gauge
    // (a free gain there would carry the gauge anywhere).
    std::vector<double> sum(photos, 0.0), sum2(photos, 0.0), count(photos, 0.0), variance(photos, 0.0);
    for (const ColourPair& p : joint) {
      for (const auto& [i, c] : {std::pair{size_t(p.a), p.ca[ch]}, std::pair{size_t(p.b), p.cb[ch]}}) {
        sum[i] += c;
        sum2[i] += c * c;
        count[i] += 1.0;
      }
    }
    for (size_t i = 0; i < photos; ++i)
      if (count[i] > 0.0) variance[i] = std::max(0.0, sum2[i] / count[i] - (sum[i] / count[i]) * (sum[i] / count[i]));
    const double minVariance = kMinSpread * kMinSpread;
    std::vector<double> held(photos, 0.0);
    for (size_t i = 0; i < photos; ++i) held[i] = std::max(0.0, minVariance - variance[i]);
    std::vector<std::vector<size_t>> gauges;
    for (const std::vector<size_t>& set : sets) {
      std::vector<size_t> spread;
      for (size_t i : set)
        if (variance[i] >= minVariance) spread.push_back(i);
      gauges.push_back(spread.empty() ? set : spread);
    }
    // The first solve (Huber, the prior) starts from the identity with every pair at its base
    // weight. The refinement replaces it: its consensus start does not depend on a least-squares
    // solve (see HarmonizeSettings::refineScale).
    std::vector<double> x(n, 0.0);
    if (s.refineScale > 0.0) {
      x = consensusStart(photos, joint, base, ch, s.consensusTolerance, x);
      if (s.refineIterations > 0)
        x = solveChannel(photos, joint, base, ch, gauges, held, s.refinePrior, Robust{true, s.refineScale},
                         s.refineIterations, x);
    } else {
      const std::vector<double> first =
          solveChannel(photos, joint, base, ch, gauges, held, s.prior, Robust{false, 1e30}, 1, x);
      x = s.iterations > 1 ? solveChannel(photos, joint, base, ch, gauges, held, s.prior, Robust{false, s.huber},
                                          s.iterations - 1, first)
                           : first;
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

  // Each monochrome photograph alone, against the others' corrected colours. Its one luma per
  // pixel is matched to theirs: the pairs whose luma agree with the consensus map of its luma onto
  // theirs (consensusMap) are kept, then, with the same weights in every channel, each channel's
  // least-squares map of its colour onto theirs (the others' colours hold the noise, so theirs are
  // regressed on its own), reweighted by Tukey's biweight of the luma residual. With one weight per
  // pair for the three channels, the corrected luma is the least-squares fit of theirs (luma is
  // linear in the channels); the chroma is only each channel's best guess from the luma.
  constexpr glm::dvec3 kLuma(0.299, 0.587, 0.114);  // Rec. 601
  for (size_t m = 0; m < photos; ++m) {
    if (!mono[m]) continue;
    std::vector<glm::dvec3> own, target, lumas;  // lumas: (its luma, theirs, base weight)
    for (const ColourPair& p : valid) {
      const bool isA = size_t(p.a) == m, isB = size_t(p.b) == m;
      if (!isA && !isB) continue;
      const size_t other = size_t(isA ? p.b : p.a);
      if (mono[other]) continue;
      const ColourCorrection& h = out.corrections[other];
      own.push_back(isA ? p.ca : p.cb);
      target.push_back(h.gain * (isA ? p.cb : p.ca) + h.offset);
      const double t = s.textureScale > 0.0 ? std::max({p.texture.r, p.texture.g, p.texture.b}) / s.textureScale : 0.0;
      lumas.push_back({glm::dot(kLuma, own.back()), glm::dot(kLuma, target.back()), 1.0 / (1.0 + t * t)});
    }
    if (own.size() < 2) continue;
    Rng rng;
    double alpha = 1.0, beta = 0.0;
    consensusMap(lumas, s.consensusTolerance, rng, alpha, beta);
    std::vector<double> w(own.size());
    for (size_t k = 0; k < own.size(); ++k)
      w[k] = std::abs(alpha * lumas[k].x + beta - lumas[k].y) <= s.consensusTolerance ? lumas[k].z : 0.0;
    ColourCorrection h;
    for (int it = 0; it < 1 + (s.refineScale > 0.0 ? s.refineIterations : 0); ++it) {
      if (it > 0)
        for (size_t k = 0; k < own.size(); ++k)
          w[k] = lumas[k].z * tukeyWeight(glm::dot(kLuma, h.gain * own[k] + h.offset - target[k]), s.refineScale);
      for (int ch = 0; ch < 3; ++ch) {
        double a00 = 0.0, a01 = 0.0, a11 = 0.0, b0 = 0.0, b1 = 0.0;
        for (size_t k = 0; k < own.size(); ++k) {
          const double c = own[k][ch], t = target[k][ch];
          a00 += w[k] * c * c;
          a01 += w[k] * c;
          a11 += w[k];
          b0 += w[k] * c * (t - c);
          b1 += w[k] * (t - c);
        }
        const double lambda = s.refinePrior * std::max(a11, 1.0);
        a00 += lambda * kTypicalColour * kTypicalColour;
        a11 += lambda;
        const double det = a00 * a11 - a01 * a01;
        if (!(det > 0.0)) continue;
        h.gain[ch] = 1.0 + (a11 * b0 - a01 * b1) / det;
        h.offset[ch] = (a00 * b1 - a01 * b0) / det;
      }
    }
    out.corrections[m] = h;
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
