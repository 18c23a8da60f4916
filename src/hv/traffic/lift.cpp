#include "hv/traffic/lift.h"

#include <algorithm>
#include <cmath>

namespace hv {
namespace {

// Buckets: about this many triangles per cell on average, at most kMaxCells cells.
constexpr double kTrianglesPerCell = 4.0;
constexpr int kMaxCellsPerAxis = 1024;

}  // namespace

MeshTerrainHeight::MeshTerrainHeight(const Mesh& mesh) {
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  for (const glm::uvec3& t : mesh.triangles) {
    if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size()) continue;
    const Tri tri{mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
    // Seen edge-on from above (a skirt, a wall): no height to give.
    const double area2 = (tri.b.x - tri.a.x) * (tri.c.y - tri.a.y) - (tri.c.x - tri.a.x) * (tri.b.y - tri.a.y);
    if (!(std::abs(area2) > 1e-12)) continue;
    triangles_.push_back(tri);
    for (const glm::dvec3& p : {tri.a, tri.b, tri.c}) {
      lo = glm::min(lo, glm::dvec2(p));
      hi = glm::max(hi, glm::dvec2(p));
    }
  }
  if (triangles_.empty()) return;
  const glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1e-6));
  const double cells = std::max(1.0, double(triangles_.size()) / kTrianglesPerCell);
  const double side = std::sqrt(size.x * size.y / cells);
  nx_ = std::clamp(int(std::ceil(size.x / side)), 1, kMaxCellsPerAxis);
  ny_ = std::clamp(int(std::ceil(size.y / side)), 1, kMaxCellsPerAxis);
  lo_ = lo;
  cell_ = {size.x / nx_, size.y / ny_};
  const auto range = [&](const Tri& t, int& i0, int& i1, int& j0, int& j1) {
    const glm::dvec2 a = glm::min(glm::min(glm::dvec2(t.a), glm::dvec2(t.b)), glm::dvec2(t.c));
    const glm::dvec2 b = glm::max(glm::max(glm::dvec2(t.a), glm::dvec2(t.b)), glm::dvec2(t.c));
    i0 = std::clamp(int(std::floor((a.x - lo_.x) / cell_.x)), 0, nx_ - 1);
    i1 = std::clamp(int(std::floor((b.x - lo_.x) / cell_.x)), 0, nx_ - 1);
    j0 = std::clamp(int(std::floor((a.y - lo_.y) / cell_.y)), 0, ny_ - 1);
    j1 = std::clamp(int(std::floor((b.y - lo_.y) / cell_.y)), 0, ny_ - 1);
  };
  std::vector<std::uint32_t> count(std::size_t(nx_) * ny_ + 1, 0);
  for (const Tri& t : triangles_) {
    int i0, i1, j0, j1;
    range(t, i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) ++count[std::size_t(j) * nx_ + i];
  }
  start_.assign(count.size(), 0);
  for (std::size_t k = 1; k < count.size(); ++k) start_[k] = start_[k - 1] + count[k - 1];
  items_.resize(start_.back());
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::uint32_t k = 0; k < triangles_.size(); ++k) {
    int i0, i1, j0, j1;
    range(triangles_[k], i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) items_[fill[std::size_t(j) * nx_ + i]++] = k;
  }
}

std::optional<double> MeshTerrainHeight::heightAt(double x, double y) const {
  if (triangles_.empty() || !std::isfinite(x) || !std::isfinite(y)) return std::nullopt;
  const double fi = std::floor((x - lo_.x) / cell_.x), fj = std::floor((y - lo_.y) / cell_.y);
  // A point on the extent's far edge belongs to the last cell.
  const int i = fi == nx_ ? nx_ - 1 : int(std::max(-1.0, std::min(fi, double(nx_))));
  const int j = fj == ny_ ? ny_ - 1 : int(std::max(-1.0, std::min(fj, double(ny_))));
  if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return std::nullopt;
  const std::size_t c = std::size_t(j) * nx_ + i;
  std::optional<double> best;
  constexpr double kEps = 1e-9;  // barycentric slack: a point on a shared edge is in both triangles
  for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
    const Tri& t = triangles_[items_[k]];
    const double d = (t.b.x - t.a.x) * (t.c.y - t.a.y) - (t.c.x - t.a.x) * (t.b.y - t.a.y);
    const double u = ((x - t.a.x) * (t.c.y - t.a.y) - (t.c.x - t.a.x) * (y - t.a.y)) / d;
    const double v = ((t.b.x - t.a.x) * (y - t.a.y) - (x - t.a.x) * (t.b.y - t.a.y)) / d;
    if (u < -kEps || v < -kEps || u + v > 1.0 + kEps) continue;
    const double z = t.a.z + u * (t.b.z - t.a.z) + v * (t.c.z - t.a.z);
    if (!best || z > *best) best = z;
  }
  return best;
}

std::optional<VehiclePose> liftOntoTerrain(const GroundPose& ground, const VehicleSize& size,
                                           const TerrainHeight& terrain, const WheelLayout& wheels) {
  const std::optional<double> hc = terrain.heightAt(ground.xy.x, ground.xy.y);
  if (!hc) return std::nullopt;
  const glm::dvec2 f = forwardFromSumoAngle(ground.angleDeg);
  const glm::dvec2 r(f.y, -f.x);  // 90 degrees clockwise from forward, seen from above
  const double wb = size.length * wheels.wheelbaseFraction, tr = size.width * wheels.trackFraction;
  const auto h = [&](double along, double across) {
    const glm::dvec2 p = ground.xy + along * f + across * r;
    return terrain.heightAt(p.x, p.y).value_or(*hc);
  };
  const double fl = h(0.5 * wb, -0.5 * tr), fr = h(0.5 * wb, 0.5 * tr);
  const double bl = h(-0.5 * wb, -0.5 * tr), br = h(-0.5 * wb, 0.5 * tr);
  const glm::dvec3 forward = glm::normalize(glm::dvec3(f, (0.5 * (fl + fr) - 0.5 * (bl + br)) / wb));
  const glm::dvec3 rightRaw(r, (0.5 * (fr + br) - 0.5 * (fl + bl)) / tr);
  const glm::dvec3 up = glm::normalize(glm::cross(rightRaw, forward));
  const glm::dvec3 right = glm::cross(forward, up);
  VehiclePose pose;
  pose.position = glm::dvec3(ground.xy, 0.25 * (fl + fr + bl + br));
  pose.worldFromVehicle = glm::dmat3(right, forward, up);  // columns: the vehicle's axes in the world
  pose.headingDeg = ground.angleDeg;
  pose.pitch = std::asin(std::clamp(forward.z, -1.0, 1.0));
  pose.roll = std::asin(std::clamp(-right.z, -1.0, 1.0));
  return pose;
}

std::vector<glm::dvec3> wheelContacts(const VehiclePose& pose, const VehicleSize& size, const WheelLayout& wheels) {
  const double wb = size.length * wheels.wheelbaseFraction, tr = size.width * wheels.trackFraction;
  std::vector<glm::dvec3> out;
  for (const glm::dvec2 q : {glm::dvec2(-0.5 * tr, 0.5 * wb), glm::dvec2(0.5 * tr, 0.5 * wb),
                             glm::dvec2(-0.5 * tr, -0.5 * wb), glm::dvec2(0.5 * tr, -0.5 * wb)})
    out.push_back(pose.position + pose.worldFromVehicle * glm::dvec3(q, 0.0));
  return out;
}

}  // namespace hv
