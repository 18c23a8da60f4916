#include "hv/viewer/timeline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace hv::viewer {

namespace {

// Division rounding towards minus infinity (years before 0 fall in the bin below).
std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

}  // namespace

PhotoDates readPhotoDates(const std::vector<std::string>& dates) {
  PhotoDates d;
  d.when.reserve(dates.size());
  for (size_t i = 0; i < dates.size(); ++i) {
    const std::optional<DateInterval> when = dates[i].empty() ? std::nullopt : parseDate(dates[i]);
    d.when.push_back(when);
    if (!when) {
      d.undated.push_back(int(i));
      continue;
    }
    if (d.dated.empty()) d.span = *when;
    d.span.first = std::min(d.span.first, when->first);
    d.span.last = std::max(d.span.last, when->last);
    d.dated.push_back(int(i));
  }
  return d;
}

DateInterval DateHistogram::binDays(int bin) const {
  const std::int64_t y0 = firstYear + std::int64_t(bin) * yearsPerBin;
  return {daysFromCivil(y0, 1, 1), daysFromCivil(y0 + yearsPerBin, 1, 1) - 1};
}

int DateHistogram::binOf(std::int64_t day) const {
  if (counts.empty()) return -1;
  const std::int64_t bin = floorDiv(civilFromDays(day).year - firstYear, yearsPerBin);
  return bin >= 0 && bin < std::int64_t(counts.size()) ? int(bin) : -1;
}

DateInterval DateHistogram::days() const {
  if (counts.empty()) return {daysFromCivil(1970, 1, 1), daysFromCivil(1970, 12, 31)};
  return {binDays(0).first, binDays(int(counts.size()) - 1).last};
}

DateHistogram dateHistogram(const PhotoDates& dates, int maxBins) {
  DateHistogram h;
  if (dates.dated.empty()) return h;
  maxBins = std::max(maxBins, 1);
  const std::int64_t y0 = civilFromDays(dates.span.first).year, y1 = civilFromDays(dates.span.last).year;
  for (;; h.yearsPerBin *= 10) {
    const std::int64_t bins = floorDiv(y1, h.yearsPerBin) - floorDiv(y0, h.yearsPerBin) + 1;
    if (bins <= maxBins) {
      h.firstYear = floorDiv(y0, h.yearsPerBin) * h.yearsPerBin;
      h.counts.assign(size_t(bins), 0);
      break;
    }
  }
  for (int i : dates.dated) ++h.counts[size_t(h.binOf(dates.when[size_t(i)]->first))];
  return h;
}

std::int64_t TimelineAxis::dayAt(double position) const {
  const double t = std::clamp(std::isfinite(position) ? position : 0.0, 0.0, 1.0);
  return first + std::int64_t(std::llround(t * double(last - first)));
}

double TimelineAxis::positionOf(std::int64_t day) const {
  if (last <= first) return 0.0;
  return std::clamp(double(day - first) / double(last - first), 0.0, 1.0);
}

DateInterval windowOnAxis(const std::optional<DateInterval>& window, const TimelineAxis& axis) {
  if (!window) return {axis.first, axis.last};
  return {std::clamp(window->first, axis.first, axis.last), std::clamp(window->last, axis.first, axis.last)};
}

DateInterval moveWindowStart(DateInterval window, std::int64_t day, const TimelineAxis& axis) {
  window = windowOnAxis(window, axis);
  window.first = std::clamp(day, axis.first, window.last);
  return window;
}

DateInterval moveWindowEnd(DateInterval window, std::int64_t day, const TimelineAxis& axis) {
  window = windowOnAxis(window, axis);
  window.last = std::clamp(day, window.first, axis.last);
  return window;
}

DateInterval shiftWindow(DateInterval window, std::int64_t days, const TimelineAxis& axis) {
  const std::int64_t width = std::min(window.last - window.first, axis.last - axis.first);
  const std::int64_t first = std::clamp(window.first + days, axis.first, axis.last - width);
  return {first, first + width};
}

std::pair<double, double> parseTimelinePositions(const std::string& text, const std::string& what) {
  double a = 0.0, b = 0.0;
  char rest = 0;
  if (std::sscanf(text.c_str(), "%lf:%lf%c", &a, &b, &rest) != 2 || !(a >= 0.0) || !(b <= 1.0) || !(a <= b))
    throw std::invalid_argument(what +
                                ": expected FROM:TO, two positions along the timeline (0 its first day, 1 its "
                                "last, FROM <= TO), got '" +
                                text + "'");
  return {a, b};
}

int countInWindow(const PhotoDates& dates, const DateInterval& window) {
  int n = 0;
  for (int i : dates.dated) n += overlaps(*dates.when[size_t(i)], window);
  return n;
}

void TimelinePlayer::start(DateInterval& window, const TimelineAxis& axis, std::int64_t wholeAxisWidthDays) {
  window = windowOnAxis(window, axis);
  if (window.first <= axis.first && window.last >= axis.last)
    window = {axis.first, std::min(axis.last, axis.first + std::max<std::int64_t>(wholeAxisWidthDays, 1) - 1)};
  if (window.last >= axis.last) window = shiftWindow(window, axis.first - window.first, axis);
  carryDays_ = 0.0;
  playing_ = true;
}

bool TimelinePlayer::step(DateInterval& window, const TimelineAxis& axis, double seconds, const PlaySettings& s) {
  if (!playing_ || !(seconds > 0.0) || !std::isfinite(s.yearsPerSecond)) return false;
  carryDays_ += seconds * s.yearsPerSecond * kDaysPerYear;
  const double whole = std::floor(carryDays_);
  carryDays_ -= whole;
  if (whole < 1.0) return false;
  const std::int64_t width = std::min(window.last - window.first, axis.last - axis.first);
  // Past the end: clamped there and stopped, or back to the start (the overshoot dropped).
  if (double(window.last) + whole >= double(axis.last)) {
    if (s.loop && window.last >= axis.last) {
      window = {axis.first, axis.first + width};
      carryDays_ = 0.0;
      return true;
    }
    const DateInterval before = window;
    window = {axis.last - width, axis.last};
    if (!s.loop) playing_ = false;
    return window != before;
  }
  window = {window.first + std::int64_t(whole), window.last + std::int64_t(whole)};
  return true;
}

}  // namespace hv::viewer
