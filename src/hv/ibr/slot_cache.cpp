#include "hv/ibr/slot_cache.h"

#include <stdexcept>
#include <string>

namespace hv::ibr {

SlotCache::SlotCache(int slots) {
  if (slots < 0) throw std::invalid_argument("SlotCache: negative slot count " + std::to_string(slots));
  photoIn_.assign(std::size_t(slots), -1);
  pinned_.assign(std::size_t(slots), false);
  prev_.assign(std::size_t(slots), -1);
  next_.assign(std::size_t(slots), -1);
  for (int s = 0; s < slots; ++s) free_.insert(s);
}

void SlotCache::unlink(int slot) {
  const int p = prev_[std::size_t(slot)], n = next_[std::size_t(slot)];
  (p >= 0 ? next_[std::size_t(p)] : head_) = n;
  (n >= 0 ? prev_[std::size_t(n)] : tail_) = p;
  prev_[std::size_t(slot)] = next_[std::size_t(slot)] = -1;
}

void SlotCache::pushMostRecent(int slot) {
  prev_[std::size_t(slot)] = tail_;
  next_[std::size_t(slot)] = -1;
  (tail_ >= 0 ? next_[std::size_t(tail_)] : head_) = slot;
  tail_ = slot;
}

SlotCache::Grant SlotCache::acquire(int photo, bool pin) {
  Grant g;
  if (auto it = slotOf_.find(photo); it != slotOf_.end()) {
    g.slot = it->second;
    unlink(g.slot);
    pushMostRecent(g.slot);
  } else {
    if (!free_.empty()) {
      g.slot = *free_.begin();
      free_.erase(free_.begin());
    } else {
      int victim = head_;
      while (victim >= 0 && pinned_[std::size_t(victim)]) victim = next_[std::size_t(victim)];
      if (victim < 0) return g;  // every slot pinned by the current frame
      g.slot = victim;
      g.evicted = photoIn_[std::size_t(victim)];
      slotOf_.erase(g.evicted);
      unlink(victim);
    }
    g.isNew = true;
    photoIn_[std::size_t(g.slot)] = photo;
    slotOf_[photo] = g.slot;
    pushMostRecent(g.slot);
  }
  if (pin) pinned_[std::size_t(g.slot)] = true;
  return g;
}

bool SlotCache::touch(int photo) {
  const int slot = slotOf(photo);
  if (slot < 0) return false;
  unlink(slot);
  pushMostRecent(slot);
  return true;
}

bool SlotCache::pin(int photo) {
  if (!touch(photo)) return false;
  pinned_[std::size_t(slotOf_.at(photo))] = true;
  return true;
}

void SlotCache::unpinAll() { pinned_.assign(pinned_.size(), false); }

bool SlotCache::evict(int photo) {
  const auto it = slotOf_.find(photo);
  if (it == slotOf_.end()) return false;
  const int slot = it->second;
  slotOf_.erase(it);
  unlink(slot);
  photoIn_[std::size_t(slot)] = -1;
  pinned_[std::size_t(slot)] = false;
  free_.insert(slot);
  return true;
}

void SlotCache::clear() { *this = SlotCache(slots()); }

int SlotCache::slotOf(int photo) const {
  const auto it = slotOf_.find(photo);
  return it == slotOf_.end() ? -1 : it->second;
}

std::vector<int> SlotCache::lruOrder() const {
  std::vector<int> out;
  for (int s = head_; s >= 0; s = next_[std::size_t(s)]) out.push_back(photoIn_[std::size_t(s)]);
  return out;
}

}  // namespace hv::ibr
