#include "hv/ibr/depth_scheduler.h"

#include <gtest/gtest.h>

#include <numeric>

namespace hv::ibr {
namespace {

// Runs frames until converged; returns the number of frames and checks each frame's budget.
int simulate(DepthMapScheduler& s, const std::vector<int>& wanted, const std::vector<double>& prio, int dmax) {
  int frames = 0;
  while (!s.converged()) {
    const auto batch = s.next(wanted, prio, dmax);
    EXPECT_LE(int(batch.size()), dmax);
    EXPECT_FALSE(batch.empty());
    if (batch.empty()) break;
    for (int slot : batch) s.done(slot);
    ++frames;
  }
  return frames;
}

TEST(DepthMapScheduler, ConvergesInCeilTOverDmaxFrames) {
  for (int t : {1, 7, 8, 9, 64, 100}) {
    for (int dmax : {1, 3, 8, 50}) {
      DepthMapScheduler s(t);
      std::vector<int> wanted(static_cast<std::size_t>(t));
      std::iota(wanted.begin(), wanted.end(), 0);
      std::vector<double> prio(wanted.begin(), wanted.end());
      const int expected = (t + dmax - 1) / dmax;  // independent: integer ceiling
      EXPECT_EQ(simulate(s, wanted, prio, dmax), expected) << "T=" << t << " Dmax=" << dmax;
      EXPECT_EQ(framesToConverge(t, dmax), expected);
    }
  }
}

TEST(DepthMapScheduler, NearestFirstThenBySlot) {
  DepthMapScheduler s(6);
  s.done(2);
  // Slots 0..5 with distances; slot 2 is clean, slot 4 appears twice.
  const std::vector<int> wanted = {0, 1, 2, 3, 4, 5, 4};
  const std::vector<double> dist = {9.0, 1.0, 0.5, 4.0, 2.0, 4.0, 2.0};
  EXPECT_EQ(s.next(wanted, dist, 3), (std::vector<int>{1, 4, 3}));  // 3 before 5: tie broken by slot
  EXPECT_EQ(s.next(wanted, dist, 0), (std::vector<int>{1, 4, 3, 5, 0}));
}

TEST(DepthMapScheduler, InvalidationAndNewSlots) {
  DepthMapScheduler s(4);
  for (int i = 0; i < 4; ++i) s.done(i);
  EXPECT_TRUE(s.converged());
  s.markDirty(std::vector<int>{1, 3});  // a tile loaded where cameras 1 and 3 look
  EXPECT_EQ(s.dirtyCount(), 2);
  EXPECT_EQ(s.next({0, 1, 2, 3}, {0, 0, 0, 0}, 10), (std::vector<int>{1, 3}));
  s.markAllDirty();  // geometry everywhere changed
  EXPECT_EQ(s.dirtyCount(), 4);
  s.resize(6);
  EXPECT_EQ(s.dirtyCount(), 6);
  // Only slots the frame wants are scheduled.
  EXPECT_EQ(s.next({5}, {1.0}, 10), (std::vector<int>{5}));
}

}  // namespace
}  // namespace hv::ibr
