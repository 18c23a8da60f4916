// The timeline's arithmetic (viewer/timeline.h), against day numbers counted by hand:
// 1971-01-01 = 365, 1972-01-01 = 730, 1973-01-01 = 1096 (1972 is a leap year), 1976-01-01 = 2191.
#include "hv/viewer/timeline.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::viewer {
namespace {

const std::vector<std::string> kDates{"1972-03-01", "", "1975", "not a date", "1971-06"};

TEST(Timeline, ReadsDatedAndUndatedPhotographs) {
  const PhotoDates d = readPhotoDates(kDates);
  EXPECT_EQ(d.dated, (std::vector<int>{0, 2, 4}));
  EXPECT_EQ(d.undated, (std::vector<int>{1, 3}));
  ASSERT_TRUE(d.when[0]);
  EXPECT_EQ(*d.when[0], (DateInterval{790, 790}));  // 730 + 31 + 29
  EXPECT_FALSE(d.when[3]);
  // 1971-06-01 = 365 + 151 (Jan..May) .. 1975-12-31 = 2191 - 1.
  EXPECT_EQ(d.span, (DateInterval{516, 2190}));
}

TEST(Timeline, YearBinsForAShortSpan) {
  const DateHistogram h = dateHistogram(readPhotoDates(kDates));
  EXPECT_EQ(h.yearsPerBin, 1);
  EXPECT_EQ(h.firstYear, 1971);
  EXPECT_EQ(h.counts, (std::vector<int>{1, 1, 0, 0, 1}));
  EXPECT_EQ(h.binDays(1), (DateInterval{730, 1095}));
  EXPECT_EQ(h.days(), (DateInterval{365, 2190}));
  EXPECT_EQ(h.binOf(729), 0);
  EXPECT_EQ(h.binOf(730), 1);
  EXPECT_EQ(h.binOf(364), -1);
  EXPECT_EQ(h.binOf(2191), -1);
}

TEST(Timeline, DecadesThenCenturiesAsTheSpanGrows) {
  // 1890 .. 1960: 71 years. Decades 1890s .. 1960s are 8 bins; at most 7 bins, centuries (1800s, 1900s).
  const PhotoDates d = readPhotoDates({"1890-05-01", "1899-12-31", "1900-01-01", "1960"});
  const DateHistogram years = dateHistogram(d, 71);
  EXPECT_EQ(years.yearsPerBin, 1);
  EXPECT_EQ(years.counts.size(), 71u);
  const DateHistogram decades = dateHistogram(d, 60);
  EXPECT_EQ(decades.yearsPerBin, 10);
  EXPECT_EQ(decades.firstYear, 1890);
  EXPECT_EQ(decades.counts, (std::vector<int>{2, 1, 0, 0, 0, 0, 0, 1}));
  EXPECT_EQ(dateHistogram(d, 8).yearsPerBin, 10);
  const DateHistogram centuries = dateHistogram(d, 7);
  EXPECT_EQ(centuries.yearsPerBin, 100);
  EXPECT_EQ(centuries.firstYear, 1800);
  EXPECT_EQ(centuries.counts, (std::vector<int>{2, 2}));
  // The 1960s end on 1969-12-31, day -1.
  EXPECT_EQ(decades.days().last, -1);
  EXPECT_EQ(decades.binDays(7), (DateInterval{-3653, -1}));  // 1960-01-01: 10 years, 3 leap days before 1970
}

TEST(Timeline, NoDatedPhotographsGiveAnEmptyHistogram) {
  const PhotoDates d = readPhotoDates({"", "someday"});
  EXPECT_TRUE(d.dated.empty());
  EXPECT_EQ(d.undated.size(), 2u);
  const DateHistogram h = dateHistogram(d);
  EXPECT_TRUE(h.counts.empty());
  EXPECT_EQ(h.binOf(0), -1);
  EXPECT_EQ(h.days(), (DateInterval{0, 364}));
}

TEST(Timeline, SliderPositionsAndDays) {
  const TimelineAxis axis{100, 200};
  EXPECT_EQ(axis.dayAt(0.0), 100);
  EXPECT_EQ(axis.dayAt(1.0), 200);
  EXPECT_EQ(axis.dayAt(0.5), 150);
  EXPECT_EQ(axis.dayAt(0.255), 126);  // 125.5 rounds away from zero
  EXPECT_EQ(axis.dayAt(-1.0), 100);
  EXPECT_EQ(axis.dayAt(2.0), 200);
  EXPECT_EQ(axis.dayAt(std::nan("")), 100);
  EXPECT_DOUBLE_EQ(axis.positionOf(150), 0.5);
  EXPECT_DOUBLE_EQ(axis.positionOf(125), 0.25);
  EXPECT_DOUBLE_EQ(axis.positionOf(50), 0.0);
  EXPECT_DOUBLE_EQ(axis.positionOf(300), 1.0);
  EXPECT_DOUBLE_EQ((TimelineAxis{7, 7}).positionOf(7), 0.0);
  for (std::int64_t day = 100; day <= 200; ++day) EXPECT_EQ(axis.dayAt(axis.positionOf(day)), day);
}

TEST(Timeline, ParsesSliderPositionsAndSaysWhatWasExpected) {
  EXPECT_EQ(parseTimelinePositions("0:1"), std::make_pair(0.0, 1.0));
  EXPECT_EQ(parseTimelinePositions("0.25:0.5"), std::make_pair(0.25, 0.5));
  EXPECT_EQ(parseTimelinePositions("1:1"), std::make_pair(1.0, 1.0));
  for (const char* bad : {"", "0.5", "0.6:0.4", "-0.1:0.5", "0:1.5", "0:1x", "a:b", "nan:1"}) {
    try {
      parseTimelinePositions(bad);
      ADD_FAILURE() << "'" << bad << "' was accepted";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("--timeline: expected FROM:TO"), std::string::npos) << what;
      EXPECT_NE(what.find(std::string("got '") + bad + "'"), std::string::npos) << what;
    }
  }
}

TEST(Timeline, DraggingTheEndsKeepsThemOrderedOnTheAxis) {
  const TimelineAxis axis{100, 200};
  const DateInterval w{120, 180};
  EXPECT_EQ(moveWindowStart(w, 90, axis), (DateInterval{100, 180}));
  EXPECT_EQ(moveWindowStart(w, 130, axis), (DateInterval{130, 180}));
  EXPECT_EQ(moveWindowStart(w, 190, axis), (DateInterval{180, 180}));
  EXPECT_EQ(moveWindowEnd(w, 110, axis), (DateInterval{120, 120}));
  EXPECT_EQ(moveWindowEnd(w, 250, axis), (DateInterval{120, 200}));
  EXPECT_EQ(windowOnAxis(std::nullopt, axis), (DateInterval{100, 200}));
  EXPECT_EQ(windowOnAxis(DateInterval{0, 150}, axis), (DateInterval{100, 150}));
  EXPECT_EQ(windowOnAxis(DateInterval{250, 300}, axis), (DateInterval{200, 200}));
  // The open window dragged by one end: the other stays at the axis's end.
  EXPECT_EQ(moveWindowStart(DateInterval{}, 150, axis), (DateInterval{150, 200}));
}

TEST(Timeline, DraggingTheWholeWindowKeepsItsWidth) {
  const TimelineAxis axis{100, 200};
  const DateInterval w{120, 180};
  EXPECT_EQ(shiftWindow(w, -5, axis), (DateInterval{115, 175}));
  EXPECT_EQ(shiftWindow(w, 50, axis), (DateInterval{140, 200}));
  EXPECT_EQ(shiftWindow(w, -30, axis), (DateInterval{100, 160}));
  EXPECT_EQ(shiftWindow(DateInterval{50, 300}, 0, axis), (DateInterval{100, 200}));
}

TEST(Timeline, CountsThePhotographsInTheWindow) {
  const PhotoDates d = readPhotoDates(kDates);
  EXPECT_EQ(countInWindow(d, {730, 1095}), 1);  // 1972
  EXPECT_EQ(countInWindow(d, {0, 800}), 2);     // 1971-06 and 1972-03-01
  EXPECT_EQ(countInWindow(d, {1500, 1600}), 0);
  EXPECT_EQ(countInWindow(d, {2190, 2190}), 1);  // 1975's last day
}

TEST(Timeline, PlayMovesWholeDaysAndCarriesTheFraction) {
  const TimelineAxis axis{0, 3652};
  const PlaySettings s{1.0, false};
  TimelinePlayer p;
  DateInterval w{0, 364};
  EXPECT_FALSE(p.step(w, axis, 0.5, s)) << "not started";
  p.start(w, axis);
  EXPECT_EQ(w, (DateInterval{0, 364}));
  ASSERT_TRUE(p.step(w, axis, 0.5, s));  // 182.62 days
  EXPECT_EQ(w, (DateInterval{182, 546}));
  ASSERT_TRUE(p.step(w, axis, 0.5, s));  // 0.62 + 182.62 = 183.24
  EXPECT_EQ(w, (DateInterval{365, 729}));
  // A hundred frames of 10 ms: one mean year, 365.2425 days, of which 365 whole.
  DateInterval v{0, 364};
  TimelinePlayer q;
  q.start(v, axis);
  for (int i = 0; i < 100; ++i) q.step(v, axis, 0.01, s);
  EXPECT_EQ(v, (DateInterval{365, 729}));
}

TEST(Timeline, PlayStopsAtTheEndOrLoops) {
  const TimelineAxis axis{0, 1000};
  TimelinePlayer p;
  DateInterval w{900, 950};
  p.start(w, axis);
  EXPECT_TRUE(p.step(w, axis, 1.0, {1.0, false}));  // 365 days would pass the end
  EXPECT_EQ(w, (DateInterval{950, 1000}));
  EXPECT_FALSE(p.playing());
  EXPECT_FALSE(p.step(w, axis, 1.0, {1.0, false}));

  // Started against the end: rewound to the start first.
  p.start(w, axis);
  EXPECT_EQ(w, (DateInterval{0, 50}));
  EXPECT_TRUE(p.playing());

  // The whole axis has nowhere to go: it becomes its first 100 days.
  DateInterval whole{0, 1000};
  p.start(whole, axis, 100);
  EXPECT_EQ(whole, (DateInterval{0, 99}));
  DateInterval open = windowOnAxis(std::nullopt, axis);
  p.start(open, axis, 5000);
  EXPECT_EQ(open, (DateInterval{0, 1000}));

  TimelinePlayer loop;
  DateInterval l{900, 950};
  loop.start(l, axis);
  EXPECT_TRUE(loop.step(l, axis, 1.0, {1.0, true}));
  EXPECT_EQ(l, (DateInterval{950, 1000}));  // the end is shown ...
  EXPECT_TRUE(loop.playing());
  EXPECT_TRUE(loop.step(l, axis, 1.0, {1.0, true}));
  EXPECT_EQ(l, (DateInterval{0, 50}));  // ... then back to the start
}

}  // namespace
}  // namespace hv::viewer
