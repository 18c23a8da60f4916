// Residency (de Castro & Brédif 2022 §2.1): which photograph lives in which slice ("slot") of the image and
// depth-map texture arrays. A scene may hold far more photographs than there are slots, so slots
// are recycled least recently used first; the slots the current frame samples are pinned and never
// recycled while the frame is being built. Plain C++, single-threaded, no GL, deterministic (the
// same calls give the same slots), so batch renders are reproducible and the tests need no GPU.
//
// Use per frame: unpinAll(); pin() every planned photo that is resident; acquire() the others
// (upload the image and redraw the depth map when the grant says isNew); a photo that cannot get a
// slot (every slot pinned) is left out of the frame.
#pragma once

#include <cstdint>
#include <set>
#include <unordered_map>
#include <vector>

namespace hv::ibr {

class SlotCache {
 public:
  struct Grant {
    int slot = -1;       // -1: every slot is pinned, the photo cannot be made resident now
    bool isNew = false;  // the photo was not resident: upload its image, its depth map is dirty
    int evicted = -1;    // the photo that lost this slot, -1 when the slot was free
    explicit operator bool() const { return slot >= 0; }
  };

  explicit SlotCache(int slots = 0);

  int slots() const { return int(photoIn_.size()); }
  int residentCount() const { return int(slotOf_.size()); }

  // The slot holding `photo`, marked most recently used; or, when it is not resident, a slot for
  // it: the free slot with the lowest index, else the least recently used unpinned slot (whose
  // photo is evicted). With `pin` the granted slot is pinned for the current frame.
  Grant acquire(int photo, bool pin = true);

  // Marks the photo's slot most recently used. False when the photo is not resident.
  bool touch(int photo);
  // Marks most recently used and pins for the current frame. False when the photo is not resident.
  bool pin(int photo);
  // A new frame: nothing is pinned (recency is kept).
  void unpinAll();
  bool pinned(int slot) const { return pinned_.at(std::size_t(slot)); }
  // Frees the photo's slot (a broken image, a cancelled upload). False when it was not resident.
  bool evict(int photo);
  void clear();

  int slotOf(int photo) const;                                            // -1 when not resident
  int photoIn(int slot) const { return photoIn_.at(std::size_t(slot)); }  // -1 when free

  // Resident photos, least recently used first (tests, debugging).
  std::vector<int> lruOrder() const;

 private:
  void unlink(int slot);
  void pushMostRecent(int slot);

  std::vector<int> photoIn_;
  std::vector<bool> pinned_;
  std::unordered_map<int, int> slotOf_;
  std::set<int> free_;
  // Occupied slots in a doubly linked list through prev_/next_, head_ the least recently used:
  // touching and evicting are O(1); finding a victim skips only pinned slots.
  std::vector<int> prev_, next_;
  int head_ = -1, tail_ = -1;
};

}  // namespace hv::ibr
