#include "hv/ibr/depth_scheduler.h"

#include <algorithm>
#include <cassert>
#include <numeric>

namespace hv::ibr {

DepthMapScheduler::DepthMapScheduler(int slots) : dirty_(size_t(std::max(slots, 0)), true) {}

void DepthMapScheduler::resize(int slots) { dirty_.resize(size_t(std::max(slots, 0)), true); }

void DepthMapScheduler::markDirty(int slot) { dirty_.at(size_t(slot)) = true; }

void DepthMapScheduler::markAllDirty() { std::fill(dirty_.begin(), dirty_.end(), true); }

void DepthMapScheduler::markDirty(const std::vector<int>& slots) {
  for (int s : slots) markDirty(s);
}

int DepthMapScheduler::dirtyCount() const { return int(std::count(dirty_.begin(), dirty_.end(), true)); }

std::vector<int> DepthMapScheduler::next(const std::vector<int>& wanted, const std::vector<double>& priority,
                                         int dmax) const {
  assert(wanted.size() == priority.size());
  std::vector<size_t> order(wanted.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return priority[a] != priority[b] ? priority[a] < priority[b] : wanted[a] < wanted[b];
  });
  std::vector<int> out;
  for (size_t i : order) {
    const int slot = wanted[i];
    if (!dirty_.at(size_t(slot)) || std::find(out.begin(), out.end(), slot) != out.end()) continue;
    if (dmax > 0 && int(out.size()) >= dmax) break;
    out.push_back(slot);
  }
  return out;
}

void DepthMapScheduler::done(int slot) { dirty_.at(size_t(slot)) = false; }

int framesToConverge(int dirtyMaps, int dmax) {
  if (dirtyMaps <= 0) return 0;
  if (dmax <= 0) return 1;
  return (dirtyMaps + dmax - 1) / dmax;
}

}  // namespace hv::ibr
