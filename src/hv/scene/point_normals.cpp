#include "hv/scene/point_normals.h"

#include <Eigen/Eigenvalues>
#include <nanoflann.hpp>

#include <algorithm>
#include <optional>
#include <thread>

namespace hv {
namespace {

// nanoflann dataset adaptor over the positions, relative to their centre (float-free, but small
// numbers keep the covariance well conditioned).
struct Positions {
  std::vector<glm::dvec3> pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const { return pts[i][int(dim)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Positions>, Positions, 3, size_t>;

// A neighbourhood is planar enough when its second spread is not negligible next to its first:
// neighbours along one scan line (a mobile-mapping scan samples each turn far more densely than
// it spaces the turns) define a line, and any direction across it would pass as the normal.
constexpr double kMinPlanarity = 0.05;  // lambda_mid / lambda_max

// The least-variance direction of the neighbours; nullopt when they do not span a plane.
std::optional<glm::vec3> normalOf(const Positions& p, const size_t* idx, size_t n) {
  if (n < 3) return std::nullopt;
  glm::dvec3 mean(0.0);
  for (size_t k = 0; k < n; ++k) mean += p.pts[idx[k]];
  mean /= double(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < n; ++k) {
    const glm::dvec3 d = p.pts[idx[k]] - mean;
    const Eigen::Vector3d v(d.x, d.y, d.z);
    cov += v * v.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  if (eig.info() != Eigen::Success) return std::nullopt;
  const Eigen::Vector3d values = eig.eigenvalues();  // ascending
  if (!(values(2) > 0.0) || values(1) < kMinPlanarity * values(2)) return std::nullopt;
  const Eigen::Vector3d v = eig.eigenvectors().col(0);
  glm::dvec3 nrm(v.x(), v.y(), v.z());
  if (nrm.z < 0.0) nrm = -nrm;
  return glm::vec3(glm::normalize(nrm));
}

std::vector<glm::vec3> estimatedNormals(const PointCloud& cloud, const NormalEstimation& settings);

}  // namespace

void estimateNormals(PointCloud& cloud, const NormalEstimation& settings) {
  cloud.pendingNormals.reset();
  cloud.normals = estimatedNormals(cloud, settings);
}

void deferNormals(PointCloud& cloud, const NormalEstimation& settings) {
  cloud.normals.clear();
  cloud.pendingNormals = std::make_shared<PendingNormals>();
  cloud.pendingNormals->settings = settings;
}

bool hasNormals(const PointCloud& cloud) { return !cloud.normals.empty() || cloud.pendingNormals != nullptr; }

const std::vector<glm::vec3>& pointNormals(const PointCloud& cloud) {
  if (!cloud.normals.empty() || !cloud.pendingNormals) return cloud.normals;
  PendingNormals& p = *cloud.pendingNormals;
  std::call_once(p.once, [&] { p.normals = estimatedNormals(cloud, p.settings); });
  return p.normals;
}

void resolveNormals(PointCloud& cloud) {
  if (!cloud.pendingNormals) return;
  // Copied, not moved: copies of the cloud may share the pending estimate.
  if (cloud.normals.empty()) cloud.normals = pointNormals(cloud);
  cloud.pendingNormals.reset();
}

namespace {

std::vector<glm::vec3> estimatedNormals(const PointCloud& cloud, const NormalEstimation& settings) {
  const size_t n = cloud.size();
  std::vector<glm::vec3> result(n, glm::vec3(0.0f));
  if (n == 0) return result;
  // Each distinct position once: a kd-tree search among many equal points visits every one of
  // them (none is farther than the k-th), so a cloud of a million identical points (a scanner
  // standing still) would take hours. Duplicates add nothing to the plane fit's directions; they
  // get the normal of their position.
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  const auto& pos = cloud.positions;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const glm::dvec3 &pa = pos[a], &pb = pos[b];
    if (pa.x != pb.x) return pa.x < pb.x;
    if (pa.y != pb.y) return pa.y < pb.y;
    return pa.z < pb.z;
  });
  std::vector<size_t> uniqueOf(n);  // point -> its distinct position
  Positions p;
  const glm::dvec3 centre = cloud.bounds().center();
  for (size_t r = 0; r < n; ++r) {
    if (r == 0 || pos[order[r]] != pos[order[r - 1]]) p.pts.push_back(pos[order[r]] - centre);
    uniqueOf[order[r]] = p.pts.size() - 1;
  }
  const size_t m = p.pts.size();
  Tree tree(3, p, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  const size_t k = size_t(std::clamp(settings.neighbours, 3, 256));
  const size_t wide = size_t(std::clamp(settings.wideNeighbours, int(k), 1024));
  std::vector<glm::vec3> normals(m, glm::vec3(0.0f));
  auto work = [&](size_t begin, size_t end) {
    std::vector<size_t> idx(wide);
    std::vector<double> dist(wide);
    for (size_t i = begin; i < end; ++i) {
      const double q[3] = {p.pts[i].x, p.pts[i].y, p.pts[i].z};
      std::optional<glm::vec3> nrm = normalOf(p, idx.data(), tree.knnSearch(q, k, idx.data(), dist.data()));
      if (!nrm && wide > k) nrm = normalOf(p, idx.data(), tree.knnSearch(q, wide, idx.data(), dist.data()));
      normals[i] = nrm.value_or(glm::vec3(0.0f));
    }
  };
  const size_t threads = size_t(std::max(settings.threads, 0));
  if (threads <= 1 || m < 10000) {
    work(0, m);
  } else {
    std::vector<std::thread> pool;
    for (size_t t = 0; t < threads; ++t) pool.emplace_back(work, m * t / threads, m * (t + 1) / threads);
    for (std::thread& t : pool) t.join();
  }
  for (size_t i = 0; i < n; ++i) result[i] = normals[uniqueOf[i]];
  return result;
}

}  // namespace

}  // namespace hv
