#include "hv/ibr/selection.h"

#include <nanoflann.hpp>

#include <algorithm>

namespace hv::ibr {

struct CameraIndex::Impl {
  // nanoflann dataset adaptor over the centres.
  struct Cloud {
    std::vector<glm::dvec3> pts;
    size_t kdtree_get_point_count() const { return pts.size(); }
    double kdtree_get_pt(size_t i, size_t dim) const { return pts[i][int(dim)]; }
    template <class B>
    bool kdtree_get_bbox(B&) const { return false; }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, size_t>;

  Cloud cloud;
  std::unique_ptr<Tree> tree;
};

CameraIndex::CameraIndex(std::vector<glm::dvec3> centers) : impl_(std::make_unique<Impl>()) {
  impl_->cloud.pts = std::move(centers);
  impl_->tree = std::make_unique<Impl::Tree>(3, impl_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  impl_->tree->buildIndex();
}

CameraIndex::~CameraIndex() = default;
CameraIndex::CameraIndex(CameraIndex&&) noexcept = default;
CameraIndex& CameraIndex::operator=(CameraIndex&&) noexcept = default;

size_t CameraIndex::size() const { return impl_->cloud.pts.size(); }

std::vector<Candidate> CameraIndex::nearest(const glm::dvec3& q, size_t count,
                                            const std::function<bool(int)>& keep) const {
  std::vector<Candidate> out;
  const size_t n = size();
  if (count == 0 || n == 0) return out;
  // Ask for more than needed and widen until enough candidates pass the filter.
  size_t ask = std::min(n, keep ? count * 2 + 8 : count);
  const double query[3] = {q.x, q.y, q.z};
  while (true) {
    std::vector<size_t> idx(ask);
    std::vector<double> d2(ask);
    const size_t found = impl_->tree->knnSearch(query, ask, idx.data(), d2.data());
    out.clear();
    std::vector<std::pair<double, size_t>> sorted;
    for (size_t i = 0; i < found; ++i) sorted.emplace_back(d2[i], idx[i]);
    std::sort(sorted.begin(), sorted.end());
    for (const auto& [dist2, i] : sorted) {
      if (keep && !keep(int(i))) continue;
      out.push_back({int(i), std::sqrt(dist2)});
      if (out.size() == count) return out;
    }
    if (ask == n) return out;
    ask = std::min(n, ask * 4);
  }
}

}  // namespace hv::ibr
