// Progressive depth maps (docs/design.md, step 3; de Castro & Brédif 2022 §2.2). A slot's depth map is
// dirty when the slot gets a new photograph or when the geometry that photograph sees changes. Each
// frame renders at most `dmax` dirty depth maps, highest priority first (the caller gives the
// priority: the renderer uses the camera's distance to the view, nearest first), so a static scene
// with T dirty maps converges in exactly ceil(T / dmax) frames. Plain C++: no GL.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hv::ibr {

class DepthMapScheduler {
 public:
  explicit DepthMapScheduler(int slots = 0);

  void resize(int slots);            // new slots start dirty
  int slots() const { return int(dirty_.size()); }

  void markDirty(int slot);
  // The geometry changed (a tile loaded or unloaded): every slot must be redrawn.
  void markAllDirty();
  // The geometry changed where only some slots look.
  void markDirty(const std::vector<int>& slots);
  bool isDirty(int slot) const { return dirty_[std::size_t(slot)]; }
  int dirtyCount() const;
  bool converged() const { return dirtyCount() == 0; }

  // The dirty slots to render this frame among `wanted` (the slots the frame uses): at most `dmax`
  // (dmax <= 0: all), ordered by ascending `priority[i]` (same length as `wanted`), ties by slot.
  // Does not clear them: call done() for each one actually rendered.
  std::vector<int> next(const std::vector<int>& wanted, const std::vector<double>& priority, int dmax) const;
  void done(int slot);

 private:
  std::vector<bool> dirty_;
};

// Frames needed to converge T dirty maps at dmax per frame: ceil(T / dmax).
int framesToConverge(int dirtyMaps, int dmax);

}  // namespace hv::ibr
