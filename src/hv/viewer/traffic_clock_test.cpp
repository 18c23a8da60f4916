#include "hv/viewer/traffic_clock.h"

#include <gtest/gtest.h>

#include <limits>

namespace hv::viewer {
namespace {

TEST(TrafficClock, StartsPausedAtTheBeginningAndClampsSeeks) {
  TrafficClock c(10.0, 70.0);
  EXPECT_FALSE(c.playing());
  EXPECT_DOUBLE_EQ(c.time(), 10.0);
  c.seek(100.0);
  EXPECT_DOUBLE_EQ(c.time(), 70.0);
  c.seek(-5.0);
  EXPECT_DOUBLE_EQ(c.time(), 10.0);
  c.seek(std::numeric_limits<double>::quiet_NaN());
  EXPECT_DOUBLE_EQ(c.time(), 10.0);
  c.seekPosition(0.25);  // 10 + 0.25 * 60
  EXPECT_DOUBLE_EQ(c.time(), 25.0);
  EXPECT_DOUBLE_EQ(c.position(), 0.25);
  c.seekPosition(2.0);
  EXPECT_DOUBLE_EQ(c.time(), 70.0);
  TrafficClock reversed(70.0, 10.0);
  EXPECT_DOUBLE_EQ(reversed.begin(), 10.0);
  EXPECT_DOUBLE_EQ(reversed.end(), 70.0);
}

TEST(TrafficClock, PlaysAtItsRateOnlyWhenPlaying) {
  TrafficClock c(0.0, 60.0);
  TrafficPlaySettings s;
  s.rate = 2.0;
  EXPECT_FALSE(c.step(1.0, s));  // paused
  EXPECT_DOUBLE_EQ(c.time(), 0.0);
  c.play();
  EXPECT_TRUE(c.step(1.5, s));
  EXPECT_DOUBLE_EQ(c.time(), 3.0);
  // Many small steps add up to the same as one: the speed does not depend on the frame rate.
  for (int i = 0; i < 100; ++i) c.step(0.01, s);
  EXPECT_NEAR(c.time(), 5.0, 1e-9);
  c.pause();
  EXPECT_FALSE(c.step(1.0, s));
  EXPECT_NEAR(c.time(), 5.0, 1e-9);
  c.toggle();
  EXPECT_TRUE(c.playing());
  EXPECT_FALSE(c.step(0.0, s));
  EXPECT_FALSE(c.step(-1.0, s));
}

TEST(TrafficClock, StopsAtTheEndOrLoopsWithTheOvershootKept) {
  TrafficPlaySettings once;
  once.loop = false;
  TrafficClock c(10.0, 20.0);
  c.seek(18.0);
  c.play();
  EXPECT_TRUE(c.step(5.0, once));
  EXPECT_DOUBLE_EQ(c.time(), 20.0);
  EXPECT_FALSE(c.playing());
  c.play();  // at the end: from the beginning again
  EXPECT_DOUBLE_EQ(c.time(), 10.0);
  EXPECT_TRUE(c.playing());

  TrafficPlaySettings loop;
  c.seek(18.0);
  EXPECT_TRUE(c.step(5.0, loop));  // 23 -> 10 + 3
  EXPECT_DOUBLE_EQ(c.time(), 13.0);
  EXPECT_TRUE(c.playing());
  EXPECT_TRUE(c.step(25.0, loop));  // 13 + 25 = 38: 10 + (28 mod 10)
  EXPECT_DOUBLE_EQ(c.time(), 18.0);
}

TEST(TrafficClock, AnInstantHasNothingToPlay) {
  TrafficClock c(5.0, 5.0);
  c.play();
  EXPECT_FALSE(c.playing());
  EXPECT_DOUBLE_EQ(c.position(), 0.0);
  TrafficClock none;
  none.play();
  EXPECT_FALSE(none.step(1.0, {}));
}

}  // namespace
}  // namespace hv::viewer
