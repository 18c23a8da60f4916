#include "hv/util/dates.h"

#include <cstdio>

namespace hv {

std::int64_t daysFromCivil(std::int64_t y, unsigned m, unsigned d) {
  // Hinnant, days_from_civil: shift the year to start in March so the leap day is the year's last
  // day, then count whole 400-year eras (146097 days each) and days within the era.
  y -= m <= 2;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = unsigned(y - era * 400);                              // [0, 399]
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;  // [0, 365]
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;            // [0, 146096]
  return era * 146097 + std::int64_t(doe) - 719468;
}

CivilDate civilFromDays(std::int64_t z) {
  // Hinnant, civil_from_days (the inverse of the above).
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = unsigned(z - era * 146097);                                 // [0, 146096]
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;  // [0, 399]
  const std::int64_t y = std::int64_t(yoe) + era * 400;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);  // [0, 365]
  const unsigned mp = (5 * doy + 2) / 153;                       // [0, 11]
  const unsigned d = doy - (153 * mp + 2) / 5 + 1;               // [1, 31]
  const unsigned m = mp < 10 ? mp + 3 : mp - 9;                  // [1, 12]
  return {y + (m <= 2), m, d};
}

bool isLeapYear(std::int64_t y) { return y % 4 == 0 && (y % 100 != 0 || y % 400 == 0); }

unsigned daysInMonth(std::int64_t y, unsigned m) {
  static constexpr unsigned kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (m < 1 || m > 12) return 0;
  return m == 2 && isLeapYear(y) ? 29u : kDays[m - 1];
}

namespace {

// Reads exactly `n` decimal digits at `pos`; advances `pos`.
bool digits(std::string_view s, size_t& pos, int n, int& value) {
  if (pos + size_t(n) > s.size()) return false;
  value = 0;
  for (int i = 0; i < n; ++i) {
    const char c = s[pos + size_t(i)];
    if (c < '0' || c > '9') return false;
    value = value * 10 + (c - '0');
  }
  pos += size_t(n);
  return true;
}

bool consume(std::string_view s, size_t& pos, char c) {
  if (pos < s.size() && s[pos] == c) {
    ++pos;
    return true;
  }
  return false;
}

// The time of day and zone after the date: validated so that a typo is not silently accepted,
// then ignored (the interval is the day as written).
bool timeAndZone(std::string_view s, size_t pos) {
  int hh = 0, mm = 0, ss = 0;
  if (!digits(s, pos, 2, hh) || !consume(s, pos, ':') || !digits(s, pos, 2, mm)) return false;
  if (consume(s, pos, ':')) {
    if (!digits(s, pos, 2, ss)) return false;
    if (consume(s, pos, '.') || consume(s, pos, ',')) {
      size_t start = pos;
      while (pos < s.size() && s[pos] >= '0' && s[pos] <= '9') ++pos;
      if (pos == start) return false;
    }
  }
  // 24:00 is the end of the day in ISO 8601; 60 seconds allows a leap second.
  if (hh > 24 || mm > 59 || ss > 60 || (hh == 24 && (mm != 0 || ss != 0))) return false;
  if (pos == s.size()) return true;
  if (consume(s, pos, 'Z')) return pos == s.size();
  if (!consume(s, pos, '+') && !consume(s, pos, '-')) return false;
  int zh = 0, zm = 0;
  if (!digits(s, pos, 2, zh)) return false;
  if (pos < s.size()) {
    consume(s, pos, ':');
    if (!digits(s, pos, 2, zm)) return false;
  }
  return pos == s.size() && zh <= 14 && zm <= 59;
}

}  // namespace

std::optional<DateInterval> parseDate(std::string_view s) {
  size_t pos = 0;
  int year = 0, month = 0, day = 0;
  if (!digits(s, pos, 4, year)) return std::nullopt;
  if (pos == s.size()) return DateInterval{daysFromCivil(year, 1, 1), daysFromCivil(year, 12, 31)};
  if (!consume(s, pos, '-') || !digits(s, pos, 2, month) || month < 1 || month > 12) return std::nullopt;
  if (pos == s.size())
    return DateInterval{daysFromCivil(year, unsigned(month), 1),
                        daysFromCivil(year, unsigned(month), daysInMonth(year, unsigned(month)))};
  if (!consume(s, pos, '-') || !digits(s, pos, 2, day) || day < 1 ||
      unsigned(day) > daysInMonth(year, unsigned(month)))
    return std::nullopt;
  const std::int64_t d = daysFromCivil(year, unsigned(month), unsigned(day));
  if (pos == s.size()) return DateInterval{d, d};
  if (!consume(s, pos, 'T') && !consume(s, pos, 't') && !consume(s, pos, ' ')) return std::nullopt;
  if (!timeAndZone(s, pos)) return std::nullopt;
  return DateInterval{d, d};
}

std::string formatDay(std::int64_t days) {
  const CivilDate c = civilFromDays(days);
  char buf[40];
  if (c.year >= 0 && c.year <= 9999)
    std::snprintf(buf, sizeof buf, "%04lld-%02u-%02u", static_cast<long long>(c.year), c.month, c.day);
  else
    std::snprintf(buf, sizeof buf, "%+lld-%02u-%02u", static_cast<long long>(c.year), c.month, c.day);
  return buf;
}

}  // namespace hv
