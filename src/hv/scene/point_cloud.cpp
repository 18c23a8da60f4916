#include "hv/scene/point_cloud.h"

#include "hv/scene/point_normals.h"

#include <cassert>

namespace hv {

std::string PointFields::describe() const {
  std::string s = "xyz";
  if (intensity) s += " intensity";
  if (classification) s += " classification";
  if (rgb) s += " rgb";
  if (normals) s += " normals";
  return s;
}

PointFields PointCloud::fields() const {
  return {.intensity = !intensity.empty(),
          .classification = !classification.empty(),
          .rgb = !rgb.empty(),
          .normals = !normals.empty()};
}

Aabb PointCloud::bounds() const {
  Aabb b;
  for (const glm::dvec3& p : positions) b.extend(p);
  return b;
}

std::array<std::size_t, 256> PointCloud::classHistogram() const {
  std::array<std::size_t, 256> h{};
  for (std::uint8_t c : classification) ++h[c];
  return h;
}

void PointCloud::resize(std::size_t n, const PointFields& f) {
  positions.resize(n);
  intensity.resize(f.intensity ? n : 0);
  classification.resize(f.classification ? n : 0);
  rgb.resize(f.rgb ? n : 0);
  normals.resize(f.normals ? n : 0);
  pendingNormals.reset();  // other points: nothing is pending for them
}

namespace {

template <typename T>
void permuteVector(std::vector<T>& v, const std::vector<std::uint32_t>& order) {
  if (v.empty()) return;
  std::vector<T> out(v.size());
  for (std::size_t i = 0; i < order.size(); ++i) out[i] = v[order[i]];
  v.swap(out);
}

}  // namespace

void PointCloud::append(const PointCloud& add) {
  if (add.empty()) return;
  if (empty()) {
    const std::string keepCrs = crs, keepSource = sourcePath;
    *this = add;
    if (!keepCrs.empty()) crs = keepCrs;
    if (!keepSource.empty()) sourcePath = keepSource;
    return;
  }
  const PointFields a = fields(), b = add.fields();
  auto join = [](auto& x, const auto& y, bool both) {
    if (both)
      x.insert(x.end(), y.begin(), y.end());
    else
      x.clear();
  };
  positions.insert(positions.end(), add.positions.begin(), add.positions.end());
  join(rgb, add.rgb, a.rgb && b.rgb);
  join(normals, add.normals, a.normals && b.normals);
  join(intensity, add.intensity, a.intensity && b.intensity);
  join(classification, add.classification, a.classification && b.classification);
}

void PointCloud::permute(const std::vector<std::uint32_t>& order) {
  assert(order.size() == size() && "PointCloud::permute: order must be a permutation of the points");
  resolveNormals(*this);  // estimated over the positions they were deferred with
  permuteVector(positions, order);
  permuteVector(intensity, order);
  permuteVector(classification, order);
  permuteVector(rgb, order);
  permuteVector(normals, order);
  chunks.clear();
}

bool PointCloud::consistent() const {
  const std::size_t n = size();
  auto ok = [n](std::size_t m) { return m == 0 || m == n; };
  return ok(intensity.size()) && ok(classification.size()) && ok(rgb.size()) && ok(normals.size());
}

}  // namespace hv
