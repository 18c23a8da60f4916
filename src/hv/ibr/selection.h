// Image selection (docs/design.md, step 1): the K+1 nearest camera centres to the view centre,
// through a kd-tree (nanoflann) over the camera centres, after a filter.
#pragma once

#include <glm/glm.hpp>

#include <functional>
#include <memory>
#include <vector>

namespace hv::ibr {

struct Candidate {
  int photo = -1;       // index into Scene::photos
  double distance = 0;  // |C_view - C_i|
};

class CameraIndex {
 public:
  explicit CameraIndex(std::vector<glm::dvec3> centers);
  ~CameraIndex();
  CameraIndex(CameraIndex&&) noexcept;
  CameraIndex& operator=(CameraIndex&&) noexcept;

  size_t size() const;
  // The `count` nearest centres that pass `keep` (all when keep is empty), ascending distance;
  // ties broken by index so the result is deterministic.
  std::vector<Candidate> nearest(const glm::dvec3& query, size_t count,
                                 const std::function<bool(int)>& keep = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hv::ibr
