#include "hv/ibr/slot_cache.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <set>

namespace hv::ibr {
namespace {

// An independent model of the policy: last-use ticks and a linear scan.
struct ModelCache {
  std::vector<int> photo;
  std::vector<std::uint64_t> lastUse;
  std::vector<bool> pinned;
  std::uint64_t tick = 0;

  explicit ModelCache(int n)
      : photo(std::size_t(n), -1), lastUse(std::size_t(n), 0), pinned(std::size_t(n)) {}

  SlotCache::Grant acquire(int p, bool pin) {
    SlotCache::Grant g;
    for (std::size_t s = 0; s < photo.size(); ++s)
      if (photo[s] == p) g.slot = int(s);
    if (g.slot < 0) {
      for (std::size_t s = 0; s < photo.size() && g.slot < 0; ++s)
        if (photo[s] < 0) g.slot = int(s);
      if (g.slot < 0) {
        for (std::size_t s = 0; s < photo.size(); ++s)
          if (!pinned[s] && (g.slot < 0 || lastUse[s] < lastUse[std::size_t(g.slot)])) g.slot = int(s);
        if (g.slot < 0) return g;
        g.evicted = photo[std::size_t(g.slot)];
      }
      g.isNew = true;
      photo[std::size_t(g.slot)] = p;
    }
    lastUse[std::size_t(g.slot)] = ++tick;
    if (pin) pinned[std::size_t(g.slot)] = true;
    return g;
  }
};

void expectConsistent(const SlotCache& c) {
  std::set<int> seen;
  int resident = 0;
  for (int s = 0; s < c.slots(); ++s) {
    const int p = c.photoIn(s);
    if (p < 0) continue;
    ++resident;
    EXPECT_TRUE(seen.insert(p).second) << "photo " << p << " in two slots";
    EXPECT_EQ(c.slotOf(p), s);
  }
  EXPECT_EQ(resident, c.residentCount());
  EXPECT_EQ(int(c.lruOrder().size()), resident);
}

TEST(SlotCache, FreeSlotsFirstThenLeastRecentlyUsed) {
  SlotCache c(3);
  EXPECT_EQ(c.acquire(10, false).slot, 0);
  EXPECT_EQ(c.acquire(11, false).slot, 1);
  EXPECT_EQ(c.acquire(12, false).slot, 2);
  EXPECT_EQ(c.lruOrder(), (std::vector<int>{10, 11, 12}));
  const auto again = c.acquire(10, false);  // resident: same slot, not new, now most recent
  EXPECT_EQ(again.slot, 0);
  EXPECT_FALSE(again.isNew);
  EXPECT_EQ(c.lruOrder(), (std::vector<int>{11, 12, 10}));
  const auto g = c.acquire(13, false);
  EXPECT_TRUE(g.isNew);
  EXPECT_EQ(g.slot, 1);  // photo 11's slot: the least recently used
  EXPECT_EQ(g.evicted, 11);
  EXPECT_EQ(c.slotOf(11), -1);
  EXPECT_TRUE(c.touch(12));
  EXPECT_FALSE(c.touch(11));
  EXPECT_EQ(c.acquire(14, false).evicted, 10);  // 12 was touched, so 10 goes
  expectConsistent(c);
}

TEST(SlotCache, PinnedSlotsAreNeverEvicted) {
  SlotCache c(3);
  for (int p = 0; p < 3; ++p) c.acquire(p);  // a frame pins what it acquires
  EXPECT_FALSE(c.acquire(3));                // every slot pinned: no slot, nothing evicted
  EXPECT_EQ(c.residentCount(), 3);
  c.unpinAll();
  EXPECT_TRUE(c.pin(0));  // the next frame uses photo 0 again
  EXPECT_FALSE(c.pin(7));
  const auto g = c.acquire(3);
  EXPECT_EQ(g.evicted, 1);  // 0 is pinned although least recently used before pin() touched it
  EXPECT_TRUE(c.pinned(c.slotOf(0)));
  EXPECT_TRUE(c.pinned(g.slot));
  EXPECT_FALSE(c.pinned(c.slotOf(2)));
  EXPECT_EQ(c.acquire(4).evicted, 2);
  EXPECT_FALSE(c.acquire(5));  // 0, 3, 4 pinned
  expectConsistent(c);
}

TEST(SlotCache, EvictFreesTheSlotAndEvictedPhotosComeBack) {
  SlotCache c(2);
  c.acquire(1, false);
  c.acquire(2, false);
  EXPECT_TRUE(c.evict(1));
  EXPECT_FALSE(c.evict(1));
  EXPECT_EQ(c.photoIn(0), -1);
  const auto g = c.acquire(3, false);
  EXPECT_EQ(g.slot, 0);  // the freed slot, nothing evicted
  EXPECT_EQ(g.evicted, -1);
  const auto back = c.acquire(1, false);  // needed again: reloaded into the LRU slot (photo 2's)
  EXPECT_TRUE(back.isNew);
  EXPECT_EQ(back.slot, 1);
  EXPECT_EQ(back.evicted, 2);
  c.clear();
  EXPECT_EQ(c.residentCount(), 0);
  EXPECT_EQ(c.acquire(9, false).slot, 0);
}

TEST(SlotCache, ManyPhotosThroughFewSlotsMatchesModel) {
  // 4096 photos through 64 slots: frames of up to 64 photos drawn near a moving position, so
  // photos leave, are evicted and come back. Every grant must equal the model's.
  constexpr int kPhotos = 4096, kSlots = 64;
  SlotCache c(kSlots);
  ModelCache m(kSlots);
  std::mt19937 rng(7);
  int reloads = 0, evictions = 0;
  std::set<int> everEvicted;
  for (int frame = 0; frame < 400; ++frame) {
    c.unpinAll();
    m.pinned.assign(m.pinned.size(), false);
    const int centre = (frame * 37) % kPhotos;
    const int count = 1 + int(rng() % kSlots);
    std::vector<int> wanted;
    for (int i = 0; i < count; ++i) wanted.push_back((centre + int(rng() % 96)) % kPhotos);
    for (int p : wanted) {
      const auto g = c.acquire(p);
      const auto e = m.acquire(p, true);
      ASSERT_EQ(g.slot, e.slot) << "frame " << frame << " photo " << p;
      ASSERT_EQ(g.isNew, e.isNew);
      ASSERT_EQ(g.evicted, e.evicted);
      ASSERT_GE(g.slot, 0);  // at most 64 distinct photos per frame: always a slot
      if (g.evicted >= 0) {
        ++evictions;
        everEvicted.insert(g.evicted);
      }
      if (g.isNew && everEvicted.count(p)) ++reloads;
    }
    for (int p : wanted) EXPECT_EQ(c.photoIn(c.slotOf(p)), p) << "a photo of this frame was evicted";
  }
  expectConsistent(c);
  EXPECT_GT(evictions, 1000);
  EXPECT_GT(reloads, 100);
}

}  // namespace
}  // namespace hv::ibr
