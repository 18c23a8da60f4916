// Calendar dates as closed intervals of days, for the photographs' `date` field and the
// --from/--to time window.
//
// A date is read as the interval it names: `1905` is 1905-01-01..1905-12-31, `1905-06` is
// 1905-06-01..1905-06-30, `1905-06-01` (with or without a time of day) is that one day. Two dates
// match when their intervals overlap. Days are counted in the proleptic Gregorian calendar
// (the Gregorian rules extended before 1582, as ISO 8601 does), day 0 = 1970-01-01.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace hv {

// Closed interval of day numbers [first, last]. The open ends of a window use the extreme values.
struct DateInterval {
  std::int64_t first = std::numeric_limits<std::int64_t>::min();
  std::int64_t last = std::numeric_limits<std::int64_t>::max();

  bool operator==(const DateInterval&) const = default;
};

// Day number of a proleptic Gregorian date (1970-01-01 = 0; negative before). Howard Hinnant's
// days_from_civil ("chrono-Compatible Low-Level Date Algorithms",
// https://howardhinnant.github.io/date_algorithms.html). `month` 1..12, `day` 1..31; no check.
std::int64_t daysFromCivil(std::int64_t year, unsigned month, unsigned day);

struct CivilDate {
  std::int64_t year = 1970;
  unsigned month = 1, day = 1;
  bool operator==(const CivilDate&) const = default;
};
// The inverse (Hinnant's civil_from_days).
CivilDate civilFromDays(std::int64_t days);

bool isLeapYear(std::int64_t year);
unsigned daysInMonth(std::int64_t year, unsigned month);

// ISO 8601 calendar dates in the extended form: `YYYY`, `YYYY-MM`, `YYYY-MM-DD`, optionally
// followed by a time of day (`THH:MM`, `THH:MM:SS`, `THH:MM:SS.fff`; a space may replace `T`)
// and a zone (`Z`, `+HH`, `+HH:MM`, `-HHMM`). The time and zone are checked but ignored: the
// interval is the day as written. Years 0000..9999. nullopt for anything else (including
// impossible days such as 1900-02-29).
std::optional<DateInterval> parseDate(std::string_view text);

// "YYYY-MM-DD" of a day number (years outside 0..9999 are written with a sign).
std::string formatDay(std::int64_t days);

// True when the two closed intervals share at least one day.
inline bool overlaps(const DateInterval& a, const DateInterval& b) {
  return a.first <= b.last && b.first <= a.last;
}

}  // namespace hv
