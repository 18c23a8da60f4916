#include "hv/eval/seams.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>

namespace hv::eval {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void checkPhoto(const SeamPhoto& p, const char* which) {
  if (!p.camera) throw std::invalid_argument(std::string("seams: photograph ") + which + " has no camera");
  const Camera& c = *p.camera;
  if (!p.grey || p.grey->empty())
    throw std::invalid_argument("seams: camera '" + c.id + "': no grey image");
  if (p.grey->channels != 1 || p.grey->width != c.width || p.grey->height != c.height)
    throw std::invalid_argument("seams: camera '" + c.id + "': the grey image is " + std::to_string(p.grey->width) +
                                "x" + std::to_string(p.grey->height) + "x" + std::to_string(p.grey->channels) +
                                ", expected " + std::to_string(c.width) + "x" + std::to_string(c.height) + "x1");
}

// Bilinear lookup at a pixel position (texel centres at i + 0.5), clamped to the edge texels.
float sampleBilinear(const ImageF& im, glm::dvec2 px) {
  const double u = std::clamp(px.x - 0.5, 0.0, double(im.width - 1));
  const double v = std::clamp(px.y - 0.5, 0.0, double(im.height - 1));
  const int x0 = std::min(int(u), im.width - 2 < 0 ? 0 : im.width - 2);
  const int y0 = std::min(int(v), im.height - 2 < 0 ? 0 : im.height - 2);
  const int x1 = std::min(x0 + 1, im.width - 1), y1 = std::min(y0 + 1, im.height - 1);
  const float fx = float(u - x0), fy = float(v - y0);
  const float top = im.at(x0, y0, 0) * (1.0f - fx) + im.at(x1, y0, 0) * fx;
  const float bottom = im.at(x0, y1, 0) * (1.0f - fx) + im.at(x1, y1, 0) * fx;
  return top * (1.0f - fy) + bottom * fy;
}

glm::dvec3 opticalAxis(const Camera& c) { return glm::transpose(c.camFromWorld)[2]; }

// Where photograph `cam` sees the sphere point in direction `dir` from `centre`.
Projection onSphere(const Camera& cam, const glm::dvec3& centre, double radius, const glm::dvec3& dir) {
  return cam.project(centre + radius * glm::normalize(dir));
}

// Pixels of photograph `cam` per radian of the sphere, as the square root of the Jacobian's
// determinant of direction -> distorted pixel at `dir` (x, y: two directions orthogonal to it).
double localScale(const Camera& cam, const glm::dvec3& centre, double radius, const glm::dvec3& dir,
                  const glm::dvec3& x, const glm::dvec3& y) {
  constexpr double kEps = 1e-4;  // radians: ~0.1 px at these focal lengths, far above rounding
  const glm::dvec2 dx = onSphere(cam, centre, radius, dir + kEps * x).pxDistorted -
                        onSphere(cam, centre, radius, dir - kEps * x).pxDistorted;
  const glm::dvec2 dy = onSphere(cam, centre, radius, dir + kEps * y).pxDistorted -
                        onSphere(cam, centre, radius, dir - kEps * y).pxDistorted;
  return std::sqrt(std::abs(dx.x * dy.y - dx.y * dy.x)) / (2.0 * kEps);
}

// The NCC loops read shifts in blocks of kBlock, up to kBlock - 1 past the last pixel of a plane.
constexpr int kBlock = 8;

// A patch image with its mask folded in, as the NCC sums need them: w in {0, 1}, v = w * grey,
// vv = w * grey^2, in float so that four shifts fit in one SSE register. Grey levels are centred on
// 128: the sums of squares of a 15 x 41 window stay below 1e7, where float's rounding adds at most
// ~300 grey levels^2 over a window, 1.4 % of the variance of the flattest template kept (standard
// deviation 6) and typically far less.
struct Plane {
  int width = 0, height = 0;
  std::vector<float> w, v, vv;  // width * height + kBlock (the padding stays 0)
  size_t at(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
};

Plane makePlane(const ImageF& grey, const Image8& mask) {
  Plane p;
  p.width = grey.width;
  p.height = grey.height;
  const size_t n = size_t(p.width) * size_t(p.height);
  p.w.assign(n + kBlock, 0.0f);
  p.v.assign(n + kBlock, 0.0f);
  p.vv.assign(n + kBlock, 0.0f);
  for (size_t i = 0; i < n; ++i)
    if (mask.data[i]) {
      const float g = grey.data[i] - 128.0f;
      p.w[i] = 1.0f;
      p.v[i] = g;
      p.vv[i] = g * g;
    }
  return p;
}

// Half resolution: 2x2 averages, kept only where all four pixels are.
Plane halve(const Plane& p) {
  Plane h;
  h.width = p.width / 2;
  h.height = p.height / 2;
  const size_t n = size_t(h.width) * size_t(h.height);
  h.w.assign(n + kBlock, 0.0f);
  h.v.assign(n + kBlock, 0.0f);
  h.vv.assign(n + kBlock, 0.0f);
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x) {
      const size_t i00 = p.at(2 * x, 2 * y), i10 = i00 + 1, i01 = p.at(2 * x, 2 * y + 1), i11 = i01 + 1;
      if (p.w[i00] * p.w[i10] * p.w[i01] * p.w[i11] == 0.0f) continue;
      const float g = 0.25f * (p.v[i00] + p.v[i10] + p.v[i01] + p.v[i11]);
      const size_t o = h.at(x, y);
      h.w[o] = 1.0f;
      h.v[o] = g;
      h.vv[o] = g * g;
    }
  return h;
}

// NCC of the window of `a` centred on (cx, cy) (half sizes hx, hy) with the window of `b` shifted by
// (sx, sy), for sx in [sx0, sx1] at once, over the pixels both keep (Lewis 1995, eq. 2, with the
// means and norms taken over those pixels). out[sx - sx0]: NaN when fewer than minCount pixels are
// shared, one side is flat, or the shifted window leaves `b`. One row of shifts at a time so that the
// innermost loop runs over shifts: independent sums the compiler can vectorise.
void maskedNccRow(const Plane& a, const Plane& b, int cx, int cy, int hx, int hy, int sy, int sx0, int sx1,
                  double minCount, double* out) {
  const int count = sx1 - sx0 + 1;
  std::fill(out, out + count, kNaN);
  const int x0 = cx - hx, x1 = cx + hx, y0 = cy - hy, y1 = cy + hy;
  if (x0 < 0 || y0 < 0 || x1 >= a.width || y1 >= a.height) return;
  if (y0 + sy < 0 || y1 + sy >= b.height) return;
  // The shifts that keep the window inside b.
  const int lo = std::max(sx0, -x0), hi = std::min(sx1, b.width - 1 - x1);
  if (lo > hi) return;
  const int len = hi - lo + 1;
  // Blocks of kBlock shifts: the six sums of a block stay in registers over the whole window, and
  // the fixed-size inner loop vectorises without a remainder loop (the sums past `len` are unused).
  for (int k0 = 0; k0 < len; k0 += kBlock) {
    float n[kBlock] = {}, sa[kBlock] = {}, sb[kBlock] = {}, saa[kBlock] = {}, sbb[kBlock] = {}, sab[kBlock] = {};
    for (int y = y0; y <= y1; ++y) {
      const size_t rowB = b.at(0, y + sy) + size_t(lo + k0);
      for (int x = x0; x <= x1; ++x) {
        const size_t ia = a.at(x, y);
        if (a.w[ia] == 0.0f) continue;  // a does not see this pixel: it adds nothing to any sum
        const float va = a.v[ia], vva = a.vv[ia];
        const float* bw = b.w.data() + rowB + size_t(x);
        const float* bv = b.v.data() + rowB + size_t(x);
        const float* bvv = b.vv.data() + rowB + size_t(x);
        for (int j = 0; j < kBlock; ++j) {
          n[j] += bw[j];
          sa[j] += va * bw[j];
          sb[j] += bv[j];
          saa[j] += vva * bw[j];
          sbb[j] += bvv[j];
          sab[j] += va * bv[j];
        }
      }
    }
    for (int j = 0; j < kBlock && k0 + j < len; ++j) {
      const double nj = n[j];
      if (nj < minCount) continue;
      const double varA = saa[j] - double(sa[j]) * sa[j] / nj, varB = sbb[j] - double(sb[j]) * sb[j] / nj;
      const double cov = sab[j] - double(sa[j]) * sb[j] / nj;
      // A flat window (standard deviation below 1/4 grey level) has no defined correlation.
      if (varA < nj / 16.0 || varB < nj / 16.0) continue;
      out[lo - sx0 + k0 + j] = cov / std::sqrt(varA * varB);
    }
  }
}

// Sub-pixel offset of a peak from the parabola through (-1, l), (0, c), (1, r); NaN when c is not a
// strict maximum of the three.
double parabolaPeak(double l, double c, double r) {
  const double denom = l - 2.0 * c + r;
  if (!(denom < 0.0)) return kNaN;
  return std::clamp(0.5 * (l - r) / denom, -0.5, 0.5);
}

// Where the ray from `origin` (inside the sphere) along `dir` leaves the sphere.
std::optional<glm::dvec3> sphereHit(const glm::dvec3& origin, const glm::dvec3& dir, const glm::dvec3& centre,
                                    double radius) {
  const glm::dvec3 d = glm::normalize(dir), o = origin - centre;
  const double b = glm::dot(o, d), c = glm::dot(o, o) - radius * radius;
  if (c > 0.0) return std::nullopt;  // outside: a sphere smaller than the rig
  return origin + (-b + std::sqrt(b * b - c)) * d;
}

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
  if (v.size() % 2) return v[mid];
  const double hi = v[mid];
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(mid)));
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const double pos = q * double(v.size() - 1);
  const size_t i = size_t(pos);
  const double f = pos - double(i);
  return i + 1 < v.size() ? v[i] * (1.0 - f) + v[i + 1] * f : v[i];
}

// Step 3-4 for one template; false when it does not give a confident match.
bool matchTemplate(const Plane& a, const Plane& b, const Plane& a2, const Plane& b2, int cx, int cy,
                   const SeamSettings& s, glm::dvec2& shift, double& ncc) {
  // Coarse: the whole range at half resolution.
  const int hx = s.windowAcross / 2, hy = s.windowAlong / 2;
  const int hx2 = std::max(2, hx / 2), hy2 = std::max(2, hy / 2);
  const int range2 = (s.searchPx + 1) / 2;
  const int side2 = 2 * range2 + 1;
  const double minCount2 = s.minSupport * double((2 * hx2 + 1) * (2 * hy2 + 1));
  std::vector<double> coarse(size_t(side2) * size_t(side2), kNaN);
  int best = -1;
  for (int sy = -range2; sy <= range2; ++sy)
    maskedNccRow(a2, b2, cx / 2, cy / 2, hx2, hy2, sy, -range2, range2, minCount2,
                 coarse.data() + size_t(sy + range2) * size_t(side2));
  for (size_t i = 0; i < coarse.size(); ++i)
    if (!std::isnan(coarse[i]) && (best < 0 || coarse[i] > coarse[size_t(best)])) best = int(i);
  if (best < 0) return false;
  const int bx = best % side2 - range2, by = best / side2 - range2;
  if (std::abs(bx) == range2 || std::abs(by) == range2) return false;  // the peak may lie beyond the range
  // Distinctness: the highest other local maximum farther than peakExclusionPx.
  const int exclusion2 = std::max(1, s.peakExclusionPx / 2);
  double second = -1.0;
  for (int y = 0; y < side2; ++y)
    for (int x = 0; x < side2; ++x) {
      const double c = coarse[size_t(y) * size_t(side2) + size_t(x)];
      if (std::isnan(c) || c <= second) continue;
      if (std::max(std::abs(x - range2 - bx), std::abs(y - range2 - by)) <= exclusion2) continue;
      bool isMax = true;
      for (int dy = -1; dy <= 1 && isMax; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx || dy) && nx >= 0 && ny >= 0 && nx < side2 && ny < side2) {
            const double o = coarse[size_t(ny) * size_t(side2) + size_t(nx)];
            if (!std::isnan(o) && o > c) {
              isMax = false;
              break;
            }
          }
        }
      if (isMax) second = c;
    }
  if (coarse[size_t(best)] - second < s.peakMargin) return false;

  // Fine: full resolution around twice the coarse peak.
  constexpr int kRefine = 3;
  constexpr int kSide = 2 * kRefine + 1;
  const double minCount = s.minSupport * double((2 * hx + 1) * (2 * hy + 1));
  double fine[kSide][kSide];
  int fx = 0, fy = 0;
  double fineBest = -2.0;
  for (int dy = -kRefine; dy <= kRefine; ++dy) {
    maskedNccRow(a, b, cx, cy, hx, hy, 2 * by + dy, 2 * bx - kRefine, 2 * bx + kRefine, minCount, fine[dy + kRefine]);
    for (int dx = -kRefine; dx <= kRefine; ++dx) {
      const double c = fine[dy + kRefine][dx + kRefine];
      if (!std::isnan(c) && c > fineBest) {
        fineBest = c;
        fx = dx;
        fy = dy;
      }
    }
  }
  if (fineBest < s.minNcc) return false;
  if (std::abs(fx) == kRefine || std::abs(fy) == kRefine) return false;
  const int sx = 2 * bx + fx, sy = 2 * by + fy;
  if (std::abs(sx) > s.searchPx || std::abs(sy) > s.searchPx) return false;
  const int ix = fx + kRefine, iy = fy + kRefine;
  const double ox = parabolaPeak(fine[iy][ix - 1], fineBest, fine[iy][ix + 1]);
  const double oy = parabolaPeak(fine[iy - 1][ix], fineBest, fine[iy + 1][ix]);
  if (std::isnan(ox) || std::isnan(oy)) return false;
  shift = glm::dvec2(sx + ox, sy + oy);
  ncc = fineBest;
  return true;
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

ImageF greyImage(const Image8& image) {
  if (image.empty() || image.channels < 1) throw std::invalid_argument("greyImage: empty image");
  ImageF out(image.width, image.height, 1);
  const size_t n = size_t(image.width) * size_t(image.height);
  const std::uint8_t* p = image.data.data();
  for (size_t i = 0; i < n; ++i, p += image.channels)
    out.data[i] = image.channels >= 3 ? float(0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]) : float(p[0]);
  return out;
}

SeamPatch seamPatch(const SeamPhoto& pa, const SeamPhoto& pb, const glm::dvec3& centre, const SeamSettings& s) {
  checkPhoto(pa, "a");
  checkPhoto(pb, "b");
  if (!(s.sphereRadius > 0.0) || s.latticePoints < 1)
    throw std::invalid_argument("seams: the sphere radius and the lattice size must be positive");
  const Camera &a = *pa.camera, &b = *pb.camera;
  const double r = s.sphereRadius;
  SeamPatch out;

  // 1. Overlap on the Fibonacci lattice: z = 1 - (2i + 1) / n, longitude 2 pi i / golden ratio.
  std::vector<glm::dvec3> both;
  const int n = s.latticePoints;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double lon = 2.0 * std::numbers::pi * i / std::numbers::phi;
    const glm::dvec3 d(rho * std::cos(lon), rho * std::sin(lon), z);
    if (a.project(centre + r * d).inImage && b.project(centre + r * d).inImage) both.push_back(d);
  }
  out.overlapPoints = int(both.size());
  if (out.overlapPoints < s.minOverlapPoints) return out;

  // 2. The patch: looking at the overlap point nearest the mean direction (the mean itself may fall
  // outside a curved overlap), x from a's axis towards b's.
  glm::dvec3 mean(0.0);
  for (const auto& d : both) mean += d;
  glm::dvec3 forward = both[0];
  for (const auto& d : both)
    if (glm::dot(d, mean) > glm::dot(forward, mean)) forward = d;
  glm::dvec3 across = opticalAxis(b) - opticalAxis(a);
  across -= forward * glm::dot(forward, across);
  if (glm::length(across) < 1e-9) {  // same axes: any direction orthogonal to forward
    across = glm::cross(forward, std::abs(forward.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0));
  }
  across = glm::normalize(across);
  const glm::dvec3 along = glm::cross(forward, across);  // camera y = z x x (x right, y down, z forward)
  const double focal = std::sqrt(localScale(a, centre, r, forward, across, along) *
                                 localScale(b, centre, r, forward, across, along));

  Camera& patch = out.camera;
  patch.id = "seam " + a.id + " | " + b.id;
  patch.center = centre;
  patch.camFromWorld = glm::transpose(glm::dmat3(across, along, forward));  // rows: the camera axes
  patch.focal = glm::dvec2(focal);
  // The overlap's extent in the patch, plus room for the search and the windows, plus one lattice
  // spacing (the lattice only samples the overlap's outline).
  const double spacing = std::sqrt(4.0 * std::numbers::pi / n);
  const double margin = s.searchPx + 0.5 * std::max(s.windowAcross, s.windowAlong) + 2.0 + focal * spacing;
  glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const auto& d : both) {
    const double depth = glm::dot(d, forward);
    if (depth < 0.2) continue;  // beyond ~78 deg the gnomonic patch would be huge; such seams are cut
    const glm::dvec2 p = focal * glm::dvec2(glm::dot(d, across), glm::dot(d, along)) / depth;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double half = 0.5 * s.maxPatchPx;
  lo = glm::max(lo - margin, glm::dvec2(-half));
  hi = glm::min(hi + margin, glm::dvec2(half));
  patch.width = int(std::ceil(hi.x - lo.x));
  patch.height = int(std::ceil(hi.y - lo.y));
  patch.principal = -lo;

  // Both photographs resampled into the patch.
  out.a = ImageF(patch.width, patch.height, 1);
  out.b = ImageF(patch.width, patch.height, 1);
  out.maskA = Image8(patch.width, patch.height, 1);
  out.maskB = Image8(patch.width, patch.height, 1);
  for (int y = 0; y < patch.height; ++y)
    for (int x = 0; x < patch.width; ++x) {
      const glm::dvec3 dir = patch.rayDirection(glm::dvec2(x + 0.5, y + 0.5));
      const Projection qa = onSphere(a, centre, r, dir), qb = onSphere(b, centre, r, dir);
      if (qa.inImage) {
        out.a.at(x, y, 0) = sampleBilinear(*pa.grey, qa.pxDistorted);
        out.maskA.at(x, y, 0) = 255;
      }
      if (qb.inImage) {
        out.b.at(x, y, 0) = sampleBilinear(*pb.grey, qb.pxDistorted);
        out.maskB.at(x, y, 0) = 255;
      }
    }
  return out;
}

SeamResult measureSeam(const SeamPhoto& pa, const SeamPhoto& pb, const glm::dvec3& centre, const SeamSettings& s) {
  if (s.windowAcross < 3 || s.windowAlong < 3 || s.searchPx < 2 || s.searchPx > 500 || s.stepAcross < 1 ||
      s.stepAlong < 1)
    throw std::invalid_argument("seams: windows of at least 3 px, a search of 2 to 500 px, steps of at least 1 px");
  const SeamPatch patch = seamPatch(pa, pb, centre, s);
  SeamResult res;
  res.a = pa.camera->id;
  res.b = pb.camera->id;
  res.sphereRadius = s.sphereRadius;
  res.medianPx = res.maxPx = res.medianOffEpipolarPx = kNaN;
  res.medianShift = glm::dvec2(kNaN);
  res.overlaps = patch.overlapPoints >= s.minOverlapPoints;
  if (!res.overlaps) return res;
  const int w = patch.camera.width, h = patch.camera.height;

  std::vector<double> widths;
  for (int y = 0; y < h; ++y) {
    int count = 0;
    for (int x = 0; x < w; ++x) count += patch.maskA.at(x, y, 0) && patch.maskB.at(x, y, 0);
    if (count > 0) widths.push_back(count);
  }
  res.overlapWidthPx = median(widths);

  const Plane a = makePlane(patch.a, patch.maskA), b = makePlane(patch.b, patch.maskB);
  const Plane a2 = halve(a), b2 = halve(b);
  const int hx = s.windowAcross / 2, hy = s.windowAlong / 2;
  const double area = double((2 * hx + 1) * (2 * hy + 1));
  const Camera& camA = *pa.camera;
  // Even centres, so that the half-resolution window sits on the same pixels.
  const int stepX = s.stepAcross + s.stepAcross % 2, stepY = s.stepAlong + s.stepAlong % 2;
  for (int cy = hy + hy % 2; cy + hy < h; cy += stepY)
    for (int cx = hx + hx % 2; cx + hx < w; cx += stepX) {
      if (!patch.maskA.at(cx, cy, 0) || !patch.maskB.at(cx, cy, 0)) continue;
      // The template: enough of it seen by a, and textured.
      double n = 0, sum = 0, sum2 = 0;
      for (int y = cy - hy; y <= cy + hy; ++y)
        for (int x = cx - hx; x <= cx + hx; ++x) {
          const size_t i = a.at(x, y);
          n += a.w[i];
          sum += a.v[i];
          sum2 += a.vv[i];
        }
      if (n < s.minSupport * area) continue;
      if (std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n))) < s.minContrast) continue;
      ++res.templates;
      SeamMatch m;
      if (!matchTemplate(a, b, a2, b2, cx, cy, s, m.shift, m.ncc)) continue;
      // Left-right consistency: b's window at the match, searched in a, must come back. A template
      // whose true match hangs over b's edge can otherwise settle on a chance peak among the shifts
      // still scored.
      glm::dvec2 back(0.0);
      double nccBack = 0.0;
      const int bx = cx + int(std::lround(m.shift.x)), by = cy + int(std::lround(m.shift.y));
      if (!matchTemplate(b, a, b2, a2, bx, by, s, back, nccBack)) continue;
      const glm::dvec2 roundTrip = glm::dvec2(bx - cx, by - cy) + back;
      if (glm::length(roundTrip) > s.maxRoundTripPx) continue;
      m.patchPx = glm::dvec2(cx + 0.5, cy + 0.5);
      // Into photograph a's pixels through the local Jacobian of patch -> photograph a.
      const auto photoA = [&](glm::dvec2 q) {
        return onSphere(camA, centre, s.sphereRadius, patch.camera.rayDirection(q)).pxDistorted;
      };
      const glm::dvec2 jx = photoA(m.patchPx + glm::dvec2(0.5, 0.0)) - photoA(m.patchPx - glm::dvec2(0.5, 0.0));
      const glm::dvec2 jy = photoA(m.patchPx + glm::dvec2(0.0, 0.5)) - photoA(m.patchPx - glm::dvec2(0.0, 0.5));
      m.shiftPhotoPx = glm::length(jx * m.shift.x + jy * m.shift.y);
      // The epipolar direction: the content under the template taken a little farther along a's
      // ray, seen by b on the sphere, moves in the patch along it.
      const glm::dvec3 onA = centre + s.sphereRadius * glm::normalize(patch.camera.rayDirection(m.patchPx));
      const glm::dvec3 farther = onA + 0.01 * s.sphereRadius * glm::normalize(onA - camA.center);
      glm::dvec2 epipolar(0.0);
      if (const auto hitB = sphereHit(pb.camera->center, farther - pb.camera->center, centre, s.sphereRadius))
        epipolar = patch.camera.project(*hitB).pxIdeal - m.patchPx;
      glm::dvec2 off = m.shift;
      if (glm::length(epipolar) > 1e-6) {
        const glm::dvec2 e = glm::normalize(epipolar);
        off -= e * glm::dot(e, m.shift);
      }
      m.offEpipolarPhotoPx = glm::length(jx * off.x + jy * off.y);
      res.matches.push_back(m);
    }

  if (!res.matches.empty()) {
    std::vector<double> len, off, sx, sy;
    for (const auto& m : res.matches) {
      len.push_back(m.shiftPhotoPx);
      off.push_back(m.offEpipolarPhotoPx);
      sx.push_back(m.shift.x);
      sy.push_back(m.shift.y);
    }
    res.medianPx = median(len);
    res.medianOffEpipolarPx = median(off);
    res.maxPx = *std::max_element(len.begin(), len.end());
    res.medianShift = glm::dvec2(median(sx), median(sy));
  }
  return res;
}

std::vector<SeamResult> measureRigSeams(const std::vector<SeamPhoto>& rig, const glm::dvec3& centre,
                                        const SeamSettings& s) {
  std::vector<SeamResult> out;
  for (size_t i = 0; i < rig.size(); ++i)
    for (size_t j = i + 1; j < rig.size(); ++j) {
      SeamResult r = measureSeam(rig[i], rig[j], centre, s);
      if (r.overlaps) out.push_back(std::move(r));
    }
  return out;
}

std::string formatSeamTable(const std::vector<SeamResult>& results) {
  std::string t;
  std::map<double, std::vector<double>> shifts, offs;
  std::map<double, int> pairs;
  for (const auto& r : results) {
    t += r.a + " | " + r.b + "  radius " + fmt("%6.0f", r.sphereRadius) + ": overlap " +
         fmt("%4.0f", r.overlapWidthPx) + " px, templates " + fmt("%4.0f", r.templates) + ", confident " +
         fmt("%4.0f", double(r.matches.size()));
    if (!r.matches.empty())
      t += ", median " + fmt("%5.1f", r.medianPx) + " px (off-epipolar " + fmt("%5.1f", r.medianOffEpipolarPx) +
           "), max " + fmt("%5.1f", r.maxPx) + " px, shift across " + fmt("%+6.1f", r.medianShift.x) + " along " +
           fmt("%+6.1f", r.medianShift.y) + " px";
    t += "\n";
    for (const auto& m : r.matches) {
      shifts[r.sphereRadius].push_back(m.shiftPhotoPx);
      offs[r.sphereRadius].push_back(m.offEpipolarPhotoPx);
    }
    ++pairs[r.sphereRadius];
  }
  double best = kNaN, bestMedian = kNaN;
  for (const auto& [radius, n] : pairs) {
    const std::vector<double>& all = shifts[radius];
    const double med = median(all);
    t += "radius " + fmt("%6.0f", radius) + ": " + std::to_string(n) + " pairs, " + std::to_string(all.size()) +
         " confident matches, |shift| median " + fmt("%.1f", med) + " px, 90 % " +
         fmt("%.1f", percentile(all, 0.9)) + " px; off-epipolar median " + fmt("%.1f", median(offs[radius])) +
         " px, 90 % " + fmt("%.1f", percentile(offs[radius], 0.9)) + " px\n";
    if (!std::isnan(med) && !(med >= bestMedian)) {
      best = radius;
      bestMedian = med;
    }
  }
  if (pairs.size() > 1 && !std::isnan(best)) t += "least median |shift| at radius " + fmt("%.0f", best) + "\n";
  return t;
}

}  // namespace hv::eval
