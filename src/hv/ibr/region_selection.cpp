#include "hv/ibr/region_selection.h"

#include "hv/camera/frustum.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace hv::ibr {

bool clipRayToBox(const glm::dvec3& o, const glm::dvec3& d, const Aabb& box, double& t0, double& t1) {
  t0 = 0.0;
  t1 = std::numeric_limits<double>::infinity();
  if (box.empty()) return false;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < box.lo[a] || o[a] > box.hi[a]) return false;
      continue;
    }
    double ta = (box.lo[a] - o[a]) / d[a], tb = (box.hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

FrustumIndex::FrustumIndex(const std::vector<Camera>& cameras, const Aabb& bounds, int targetCells) : bounds_(bounds) {
  if (bounds.empty()) return;
  // Cubic cells of about bounds volume / targetCells; a thin axis (a flat city's height) gets few.
  const glm::dvec3 ext = glm::max(bounds.size(), glm::dvec3(1e-9 * (glm::length(bounds.size()) + 1.0)));
  const double side = std::cbrt(ext.x * ext.y * ext.z / double(std::max(targetCells, 1)));
  for (int a = 0; a < 3; ++a) {
    n_[a] = std::clamp(int(std::ceil(ext[a] / side)), 1, std::max(targetCells, 1));
    cellSize_[a] = ext[a] / n_[a];
  }
  grid_.assign(size_t(n_.x) * n_.y * n_.z, {});
  cameras_.reserve(cameras.size());
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Camera& cam = cameras[i];
    const PinholeFrustum rect = idealRectCoveringImage(cam, 1.0);
    const glm::dmat3 M = cam.pixFromWorld();
    auto row = [&](int r) { return glm::dvec3(M[0][r], M[1][r], M[2][r]); };  // glm is column-major
    const glm::dvec3 r0 = row(0), r1 = row(1), r2 = row(2);
    Frustum f;
    f.center = cam.center;
    // ph = M (P - C): inside when pxMin.x <= ph.x / ph.z <= pxMax.x (same in y) and ph.z > 0.
    f.planes[0] = r0 - rect.pxMin.x * r2;
    f.planes[1] = rect.pxMax.x * r2 - r0;
    f.planes[2] = r1 - rect.pxMin.y * r2;
    f.planes[3] = rect.pxMax.y * r2 - r1;
    f.planes[4] = r2;
    cameras_.push_back(f);
    // The cells of the frustum's box (truncated at the bounds' depth range) that no plane rejects:
    // a cell is outside a plane when its corner farthest along the plane's normal is.
    Aabb box;
    for (const auto& c : sceneFrustum(cam, bounds)) box.extend(c);
    box.lo = glm::max(box.lo, bounds.lo);
    box.hi = glm::min(box.hi, bounds.hi);
    if (box.empty()) continue;
    glm::ivec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::clamp(int(std::floor((box.lo[a] - bounds.lo[a]) / cellSize_[a])), 0, n_[a] - 1);
      hi[a] = std::clamp(int(std::floor((box.hi[a] - bounds.lo[a]) / cellSize_[a])), 0, n_[a] - 1);
    }
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          const glm::dvec3 cLo = bounds.lo + glm::dvec3(x, y, z) * cellSize_, cHi = cLo + cellSize_;
          bool outside = false;
          for (const glm::dvec3& n : f.planes) {
            const glm::dvec3 far(n.x > 0 ? cHi.x : cLo.x, n.y > 0 ? cHi.y : cLo.y, n.z > 0 ? cHi.z : cLo.z);
            if (glm::dot(n, far - f.center) < 0.0) {
              outside = true;
              break;
            }
          }
          if (!outside) grid_[(size_t(z) * n_.y + y) * n_.x + x].push_back(int(i));
        }
  }
}

const std::vector<int>& FrustumIndex::at(const glm::dvec3& P) const {
  if (grid_.empty()) return none_;
  glm::ivec3 c;
  for (int a = 0; a < 3; ++a) {
    const double u = (P[a] - bounds_.lo[a]) / cellSize_[a];
    if (!(u >= 0.0) || u > double(n_[a])) return none_;
    c[a] = std::min(int(u), n_[a] - 1);
  }
  return grid_[(size_t(c.z) * n_.y + c.y) * n_.x + c.x];
}

bool FrustumIndex::contains(int photo, const glm::dvec3& P) const {
  const Frustum& f = cameras_[size_t(photo)];
  const glm::dvec3 v = P - f.center;
  if (glm::dot(f.planes[4], v) <= 0.0) return false;
  for (int k = 0; k < 4; ++k)
    if (glm::dot(f.planes[k], v) < 0.0) return false;
  return true;
}

std::vector<RegionCandidate> regionCandidates(const FrustumIndex& index, const Camera& view, int count,
                                              const RegionGrid& grid, const std::function<bool(int)>& keep) {
  std::vector<RegionCandidate> out;
  if (count <= 0 || index.empty()) return out;
  const PinholeFrustum rect = idealRectCoveringImage(view, 0.0);
  const glm::dvec2 size = rect.pxMax - rect.pxMin;
  const int longSide = std::max(grid.cells, 1);
  const glm::ivec2 cells = size.x >= size.y
                               ? glm::ivec2(longSide, std::max(1, int(std::lround(longSide * size.y / size.x))))
                               : glm::ivec2(std::max(1, int(std::lround(longSide * size.x / size.y))), longSide);
  const int rays = std::max(grid.raysPerCell, 1), samples = std::max(grid.samplesPerRay, 2);
  const Aabb& bounds = index.bounds();
  // The nearest sample: a thousandth of the bounds' diagonal (the ray starts at the view centre).
  const double tNearest = 1e-3 * glm::length(bounds.size());

  // Per photograph: whether `keep` passed (0 unknown, 1 yes, 2 no) and the last cell it was listed
  // in. Plain arrays over the collection: a memset per frame, the rest follows what is seen.
  std::vector<std::uint8_t> kept(index.size(), 0);
  std::vector<int> listedIn(index.size(), -1);
  std::vector<std::vector<RegionCandidate>> ranking;
  for (int cy = 0; cy < cells.y; ++cy) {
    for (int cx = 0; cx < cells.x; ++cx) {
      const int cell = cy * cells.x + cx;
      std::vector<RegionCandidate> list;
      for (int ry = 0; ry < rays; ++ry) {
        for (int rx = 0; rx < rays; ++rx) {
          const glm::dvec2 px =
              rect.pxMin + (glm::dvec2(cx, cy) + (glm::dvec2(rx, ry) + 0.5) / double(rays)) / glm::dvec2(cells) * size;
          const glm::dvec3 dir = view.rayDirection(px);
          double t0, t1;
          if (!clipRayToBox(view.center, dir, bounds, t0, t1)) continue;
          // t is depth along the view axis (dir has camera z = 1).
          const double step = glm::length(dir);
          t0 = std::max(t0, tNearest / step);
          if (t1 <= t0) continue;
          const double ratio = t1 / t0;
          for (int s = 0; s < samples; ++s) {
            const double t = t0 * std::pow(ratio, double(s) / double(samples - 1));
            const glm::dvec3 P = view.center + t * dir;
            for (int photo : index.at(P)) {
              if (listedIn[size_t(photo)] == cell) continue;
              if (kept[size_t(photo)] == 0) kept[size_t(photo)] = !keep || keep(photo) ? 1 : 2;
              if (kept[size_t(photo)] != 1 || !index.contains(photo, P)) continue;
              listedIn[size_t(photo)] = cell;
              list.push_back({photo, glm::length(index.center(photo) - view.center)});
            }
          }
        }
      }
      auto nearer = [](const RegionCandidate& a, const RegionCandidate& b) {
        return a.distance != b.distance ? a.distance < b.distance : a.photo < b.photo;
      };
      std::sort(list.begin(), list.end(), nearer);
      if (!list.empty()) ranking.push_back(std::move(list));
    }
  }
  // Round robin: rank 1 of every cell, then rank 2, ... (a photograph already chosen is skipped).
  std::vector<std::uint8_t> chosen(index.size(), 0);
  for (size_t rank = 0; int(out.size()) < count; ++rank) {
    bool any = false;
    for (const auto& list : ranking) {
      if (rank >= list.size()) continue;
      any = true;
      const RegionCandidate& c = list[rank];
      if (chosen[size_t(c.photo)]) continue;
      chosen[size_t(c.photo)] = 1;
      out.push_back(c);
      if (int(out.size()) == count) break;
    }
    if (!any) break;
  }
  std::sort(out.begin(), out.end(), [](const RegionCandidate& a, const RegionCandidate& b) {
    return a.distance != b.distance ? a.distance < b.distance : a.photo < b.photo;
  });
  return out;
}

}  // namespace hv::ibr
