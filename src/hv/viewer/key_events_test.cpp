#include "hv/viewer/key_events.h"

#include <gtest/gtest.h>

#include <set>

namespace hv::viewer {
namespace {

constexpr int kH = 72, kW = 87;

TEST(KeyEvents, ATapShorterThanAFrameTogglesOnce) {
  KeyEvents k;
  k.event(kH, true);
  k.event(kH, false);  // released before the frame looked: polling would have missed it
  EXPECT_TRUE(k.pressed(kH));
  EXPECT_EQ(k.presses(kH), 1);
  k.endFrame();
  EXPECT_FALSE(k.pressed(kH));  // consumed: the next frame does not toggle again
}

TEST(KeyEvents, TwoTapsInOneFrameAreTwoPresses) {
  KeyEvents k;
  k.event(kH, true), k.event(kH, false), k.event(kH, true), k.event(kH, false);
  EXPECT_EQ(k.presses(kH), 2);
}

TEST(KeyEvents, ATappedMovementKeyMovesForOneFrame) {
  KeyEvents k;
  k.event(kW, true);
  k.event(kW, false);
  EXPECT_TRUE(k.held(kW));
  k.endFrame();
  EXPECT_FALSE(k.held(kW));
}

TEST(KeyEvents, AHeldKeyStaysHeldAndRepeatsAreNotPresses) {
  KeyEvents k;
  k.event(kW, true);
  k.endFrame();
  k.event(kW, true);  // auto-repeat
  EXPECT_TRUE(k.held(kW));
  EXPECT_EQ(k.presses(kW), 0);
  k.endFrame();
  EXPECT_TRUE(k.held(kW));
  k.releaseAll();
  EXPECT_FALSE(k.held(kW));
}

TEST(KeyEvents, OtherKeysAreUntouched) {
  KeyEvents k;
  k.event(kH, true);
  EXPECT_FALSE(k.pressed(kW));
  EXPECT_FALSE(k.held(kW));
}

TEST(NumberedName, SkipsTakenNamesAndKeepsTheExtension) {
  std::set<std::string> taken{"out/shot-001.png", "out/shot-002.png"};
  auto exists = [&](const std::string& n) { return taken.count(n) > 0; };
  EXPECT_EQ(nextNumberedName("out/shot.png", exists), "out/shot-003.png");
  EXPECT_EQ(nextNumberedName("shot", exists), "shot-001");
  EXPECT_EQ(nextNumberedName("a.b/shot", exists), "a.b/shot-001");
  EXPECT_EQ(nextNumberedName(".hidden", exists), ".hidden-001");
}

}  // namespace
}  // namespace hv::viewer
