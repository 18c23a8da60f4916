// Per-region candidates (docs/design.md, step 1): the photographs a frame makes resident when
// every region of a wide view is to be textured by the photographs nearest to the view that see
// it, not only the K nearest to the view centre. The view is cut into a coarse grid of screen
// cells; each cell's rays, clipped to the geometry bounds, are sampled; each cell ranks the
// photographs whose frustum contains one of its samples by distance to the view centre; the
// rankings are merged round-robin (every cell's first, then every cell's second, ...). The shader
// then picks, per pixel, the K nearest of them that pass its tests (Buehler et al. 2001, ULR: the
// best k per pixel; weights of Brédif 2013 eq. 1-2 with the pixel's own K+1-th).
//
// A FrustumIndex, built once per scene and geometry bounds, keeps the cost of a frame following
// the photographs that can be seen, not the size of the collection.
#pragma once

#include "hv/camera/camera.h"
#include "hv/math/aabb.h"

#include <glm/glm.hpp>

#include <functional>
#include <vector>

namespace hv::ibr {

// A uniform grid over the geometry bounds; each cell lists the photographs whose pinhole frustum
// (the ideal rectangle covering the image, in front of the camera) may meet it.
class FrustumIndex {
 public:
  FrustumIndex() = default;
  // `targetCells`: about how many grid cells (cubic cells, fewer along thin axes).
  FrustumIndex(const std::vector<Camera>& cameras, const Aabb& bounds, int targetCells = 16384);

  const Aabb& bounds() const { return bounds_; }
  bool empty() const { return bounds_.empty() || cameras_.empty(); }
  size_t size() const { return cameras_.size(); }
  // The photographs whose frustum may contain P (a superset); empty outside the bounds.
  const std::vector<int>& at(const glm::dvec3& P) const;
  // Exact: P is in front of photograph i and projects into the ideal rectangle covering its image.
  bool contains(int photo, const glm::dvec3& P) const;
  const glm::dvec3& center(int photo) const { return cameras_[size_t(photo)].center; }
  glm::ivec3 cells() const { return n_; }

 private:
  struct Frustum {
    glm::dvec3 center{0.0};
    // n . (P - center) >= 0 for all five: left, right, top, bottom, in front.
    glm::dvec3 planes[5];
  };
  Aabb bounds_;
  glm::ivec3 n_{0};
  glm::dvec3 cellSize_{1.0};
  std::vector<Frustum> cameras_;
  std::vector<std::vector<int>> grid_;
  std::vector<int> none_;
};

struct RegionGrid {
  int cells = 12;          // screen cells along the view's longer side (the other side in proportion)
  int raysPerCell = 2;     // rays per cell side (raysPerCell^2 rays per cell)
  int samplesPerRay = 16;  // points along a ray's stretch inside the bounds, geometric in depth
};

struct RegionCandidate {
  int photo = -1;
  double distance = 0.0;  // |C_view - C_i|
};

// Up to `count` photographs that pass `keep`, merged round-robin from the cells' rankings, sorted
// ascending by distance to the view centre (ties by index). Needs a non-empty index.
std::vector<RegionCandidate> regionCandidates(const FrustumIndex& index, const Camera& view, int count,
                                              const RegionGrid& grid, const std::function<bool(int)>& keep);

// The stretch [t0, t1] of the ray origin + t dir (t >= 0) inside `box`; false when it misses it.
bool clipRayToBox(const glm::dvec3& origin, const glm::dvec3& dir, const Aabb& box, double& t0, double& t1);

}  // namespace hv::ibr
