#include "hv/scene/heightfield.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hv {

namespace {

// Continuous sample coordinates of a world point: sample (i, j) sits at (i, j) exactly, so the
// raster's outer edge is at -0.5 and cols - 0.5 (cell centres, see the header).
glm::dvec2 sampleFromWorld(const Heightfield& f, double x, double y) {
  return {(x - f.originX) / f.cellX - 0.5, (y - f.originY) / f.cellY - 0.5};
}

// Even-odd rule (W. R. Franklin, "PNPOLY", 1970s; Haines, "Point in Polygon Strategies", Graphics
// Gems IV, 1994): count the ring edges crossed by the ray from p towards +x.
bool insideRing(const std::vector<glm::dvec2>& ring, const glm::dvec2& p) {
  bool inside = false;
  for (size_t a = 0, b = ring.size() - 1; a < ring.size(); b = a++) {
    const glm::dvec2& pa = ring[a];
    const glm::dvec2& pb = ring[b];
    if ((pa.y > p.y) != (pb.y > p.y) && p.x < (pb.x - pa.x) * (p.y - pa.y) / (pb.y - pa.y) + pa.x)
      inside = !inside;
  }
  return inside;
}

}  // namespace

glm::dvec2 Heightfield::samplePosition(int i, int j) const {
  return {originX + (i + 0.5) * cellX, originY + (j + 0.5) * cellY};
}

std::optional<double> Heightfield::elevation(double x, double y) const {
  if (empty() || cols <= 0 || rows <= 0) return std::nullopt;
  glm::dvec2 s = sampleFromWorld(*this, x, y);
  // Inside the raster's extent but in the half cell beyond the outermost sample centres, the
  // elevation is extended flat from the border samples: a building on the raster's edge still
  // gets a base. Outside the extent there is no answer.
  if (!(s.x >= -0.5 && s.x <= cols - 0.5 && s.y >= -0.5 && s.y <= rows - 0.5)) return std::nullopt;
  s.x = std::clamp(s.x, 0.0, double(cols - 1));
  s.y = std::clamp(s.y, 0.0, double(rows - 1));
  const int i0 = std::min(int(std::floor(s.x)), std::max(cols - 2, 0));
  const int j0 = std::min(int(std::floor(s.y)), std::max(rows - 2, 0));
  const double tx = s.x - i0, ty = s.y - j0;
  // Bilinear interpolation over the cell's four samples; a sample with zero weight may be
  // missing without spoiling the result (so a point exactly on valid samples keeps its value).
  double sum = 0.0;
  const int di[4] = {0, 1, 0, 1}, dj[4] = {0, 0, 1, 1};
  const double w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
  for (int k = 0; k < 4; ++k) {
    if (w[k] == 0.0) continue;
    const float v = at(i0 + di[k], j0 + dj[k]);
    if (std::isnan(v)) return std::nullopt;
    sum += w[k] * v;
  }
  return sum;
}

std::optional<double> Heightfield::minUnder(const std::vector<glm::dvec2>& ring) const {
  if (empty() || ring.empty()) return std::nullopt;
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& p : ring)
    if (const auto z = elevation(p.x, p.y)) lowest = std::min(lowest, *z);

  if (ring.size() >= 3) {
    // Only samples within the ring's bounding box can be inside it.
    double iLo = std::numeric_limits<double>::infinity(), iHi = -iLo, jLo = iLo, jHi = -iLo;
    for (const auto& p : ring) {
      const glm::dvec2 s = sampleFromWorld(*this, p.x, p.y);
      iLo = std::min(iLo, s.x), iHi = std::max(iHi, s.x);
      jLo = std::min(jLo, s.y), jHi = std::max(jHi, s.y);
    }
    const int i0 = std::max(0, int(std::ceil(iLo))), i1 = std::min(cols - 1, int(std::floor(iHi)));
    const int j0 = std::max(0, int(std::ceil(jLo))), j1 = std::min(rows - 1, int(std::floor(jHi)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const float v = at(i, j);
        if (!std::isnan(v) && v < lowest && insideRing(ring, samplePosition(i, j))) lowest = v;
      }
  }
  if (std::isinf(lowest)) return std::nullopt;
  return lowest;
}

Mesh Heightfield::toMesh(int stride) const {
  Mesh mesh;
  if (empty() || cols < 2 || rows < 2) return mesh;
  stride = std::max(stride, 1);
  // Decimated sample indices; the last row and column are always kept so the mesh covers the
  // same extent at every stride.
  auto pick = [stride](int n) {
    std::vector<int> idx;
    for (int k = 0; k < n - 1; k += stride) idx.push_back(k);
    idx.push_back(n - 1);
    return idx;
  };
  const std::vector<int> is = pick(cols), js = pick(rows);
  const int nc = int(is.size()), nr = int(js.size());

  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> vertex(size_t(nc) * nr, kNone);
  // Reserved up front: growing by doubling held the old and the new arrays at once. Peak RSS of
  // `histoview info` on a 6000 x 6000 DTM: 2.80 GB before, 2.02 GB after (80 and 58 bytes a cell;
  // the mesh itself is 48: a dvec3 per vertex, two uvec3 per cell).
  size_t withData = 0;
  for (int b = 0; b < nr; ++b)
    for (int a = 0; a < nc; ++a) withData += std::isnan(at(is[a], js[b])) ? 0 : 1;
  mesh.positions.reserve(withData);
  mesh.triangles.reserve(2 * size_t(nc - 1) * size_t(nr - 1));
  for (int b = 0; b < nr; ++b)
    for (int a = 0; a < nc; ++a) {
      const float v = at(is[a], js[b]);
      if (std::isnan(v)) continue;
      vertex[size_t(b) * nc + a] = std::uint32_t(mesh.positions.size());
      const glm::dvec2 xy = samplePosition(is[a], js[b]);
      mesh.positions.emplace_back(xy.x, xy.y, double(v));
    }

  // The grid's handedness depends on the signs of cellX and cellY; wind each triangle so that it
  // is counter-clockwise seen from above (up-facing, hv/scene/mesh.h).
  const bool flip = (cellX * cellY) < 0.0;  // north-up rasters: x east, rows southwards
  auto emit = [&](std::uint32_t p, std::uint32_t q, std::uint32_t r) {
    mesh.triangles.push_back(flip ? glm::uvec3(p, r, q) : glm::uvec3(p, q, r));
  };
  for (int b = 0; b + 1 < nr; ++b)
    for (int a = 0; a + 1 < nc; ++a) {
      const std::uint32_t v00 = vertex[size_t(b) * nc + a], v10 = vertex[size_t(b) * nc + a + 1];
      const std::uint32_t v01 = vertex[size_t(b + 1) * nc + a], v11 = vertex[size_t(b + 1) * nc + a + 1];
      if (v00 == kNone || v10 == kNone || v01 == kNone || v11 == kNone) continue;
      // In (column, row) index space (a right-handed frame when cellX * cellY > 0) these are CCW.
      emit(v00, v10, v11);
      emit(v00, v11, v01);
    }
  return mesh;
}

}  // namespace hv
