// The viewer's timeline: a histogram of the photographs' dates, a slider over them and a time
// window [first, last] (the render settings `from`/`to`, BlendSettings::window) that is dragged by
// either end or as a whole, and played through time. Plain data and arithmetic; the panel
// (viewer/desktop/) only draws it.
//
// Conventions: days are hv/util/dates.h's day numbers (1970-01-01 = 0), windows closed
// intervals of days. A photograph's date is the interval it names (`1905` is the whole year); it
// is binned by its first day and is in a window when the two intervals overlap (as the renderer's
// time window, ibr::planFrame). A slider position is a fraction of the axis: 0 its first day, 1
// its last.
#pragma once

#include "hv/util/dates.h"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hv::viewer {

// The photographs' dates, read once: each photograph dated (the interval its date names) or not
// (no date, or one parseDate refuses: the renderer treats both as undated).
struct PhotoDates {
  std::vector<std::optional<DateInterval>> when;  // per photograph
  std::vector<int> dated, undated;                // photograph indices, in input order
  DateInterval span;                              // earliest first day .. latest last day (dated non-empty)
};
PhotoDates readPhotoDates(const std::vector<std::string>& dates);

// Photographs per bin of whole calendar years: each bin holds `yearsPerBin` years from 1 January
// of firstYear + i * yearsPerBin. yearsPerBin is the smallest of 1, 10, 100, 1000 … (years,
// decades, centuries) that covers the dates' span in at most `maxBins` bins, bins aligned on
// multiples of it (decades start in years ending in 0).
struct DateHistogram {
  std::int64_t firstYear = 0;
  std::int64_t yearsPerBin = 1;
  std::vector<int> counts;

  // The days of bin `bin` (a closed interval).
  DateInterval binDays(int bin) const;
  // The bin holding `day`; -1 outside the histogram.
  int binOf(std::int64_t day) const;
  // First day of the first bin .. last day of the last (the slider's axis); empty histogram: 1970.
  DateInterval days() const;
};
DateHistogram dateHistogram(const PhotoDates& dates, int maxBins = 60);

// The slider: positions in [0, 1] over the closed interval of days [first, last].
struct TimelineAxis {
  std::int64_t first = 0, last = 0;

  // The day at `position`, rounded to the nearest; positions outside [0, 1] are clamped.
  std::int64_t dayAt(double position) const;
  // The position of `day`, clamped to [0, 1] (0 for a one-day axis).
  double positionOf(std::int64_t day) const;
};

// The window shown on the axis: the open window (no `from`/`to`) is the whole axis; a window is
// clamped to the axis (one wholly outside it collapses onto the nearer end).
DateInterval windowOnAxis(const std::optional<DateInterval>& window, const TimelineAxis& axis);
// Dragging one end to `day`: it stays on the axis and on its side of the other end.
DateInterval moveWindowStart(DateInterval window, std::int64_t day, const TimelineAxis& axis);
DateInterval moveWindowEnd(DateInterval window, std::int64_t day, const TimelineAxis& axis);
// Dragging the whole window by `days`: its width is kept and it stops at the axis's ends (a window
// wider than the axis becomes the axis).
DateInterval shiftWindow(DateInterval window, std::int64_t days, const TimelineAxis& axis);

// Two slider positions "A:B" (as the viewer's --timeline gives them): 0 <= A <= B <= 1. Throws
// std::invalid_argument naming `what` (the option) and what was expected.
std::pair<double, double> parseTimelinePositions(const std::string& text, const std::string& what = "--timeline");

// Dated photographs whose date overlaps `window`.
int countInWindow(const PhotoDates& dates, const DateInterval& window);

// Days per year for play speeds: the mean Gregorian year (146097 days in 400 years).
inline constexpr double kDaysPerYear = 365.2425;

struct PlaySettings {
  double yearsPerSecond = 5.0;
  bool loop = false;  // at the axis's end: start again from its start (else stop there)
};

// "Play": walks the window forward through time, width kept, `yearsPerSecond` years per second
// of wall time. Whole days move; the fraction is carried to the next step, so the speed is exact
// at any frame rate.
class TimelinePlayer {
 public:
  // Starts playing `window`, rewound to the axis's start when it already touches the end; a window
  // over the whole axis (nothing to walk) becomes its first `wholeAxisWidthDays` days.
  void start(DateInterval& window, const TimelineAxis& axis, std::int64_t wholeAxisWidthDays = 3653);
  void stop() { playing_ = false; }
  bool playing() const { return playing_; }
  // Advances by `seconds`; returns true when the window moved. Reaching the end stops the player
  // with the window against the end, or (loop) moves it back to the start.
  bool step(DateInterval& window, const TimelineAxis& axis, double seconds, const PlaySettings& s);

 private:
  bool playing_ = false;
  double carryDays_ = 0.0;
};

}  // namespace hv::viewer
