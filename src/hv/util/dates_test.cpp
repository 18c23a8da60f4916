#include "hv/util/dates.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace hv {
namespace {

// Day numbers computed by hand, 1970-01-01 = 0:
// - 2000-01-01: 30 years of which 7 leap (1972 ... 1996): 30 * 365 + 7 = 10957.
// - 1900-01-01: 70 years back, 17 leap (1904 ... 1968; 1900 is not): -(70 * 365 + 17) = -25567
//   (the NTP/Unix epoch difference, 2208988800 s / 86400).
// - 1905-01-01: 1900-01-01 + 5 * 365 + 1 (1904) = -23741.
TEST(Dates, DaysFromCivilMatchesHandComputedDays) {
  EXPECT_EQ(daysFromCivil(1970, 1, 1), 0);
  EXPECT_EQ(daysFromCivil(1970, 1, 2), 1);
  EXPECT_EQ(daysFromCivil(1969, 12, 31), -1);
  EXPECT_EQ(daysFromCivil(2000, 1, 1), 10957);
  EXPECT_EQ(daysFromCivil(1900, 1, 1), -25567);
  EXPECT_EQ(daysFromCivil(1905, 1, 1), -23741);
  // 1905-06-01: Jan 31 + Feb 28 + Mar 31 + Apr 30 + May 31 = 151 days after Jan 1.
  EXPECT_EQ(daysFromCivil(1905, 6, 1), -23741 + 151);
  // The algorithm's own anchor: 0000-03-01 is 719468 days before 1970-01-01.
  EXPECT_EQ(daysFromCivil(0, 3, 1), -719468);
}

TEST(Dates, LeapYearsFollowTheGregorianRules) {
  EXPECT_FALSE(isLeapYear(1900));
  EXPECT_TRUE(isLeapYear(2000));
  EXPECT_TRUE(isLeapYear(1904));
  EXPECT_FALSE(isLeapYear(1905));
  EXPECT_FALSE(isLeapYear(2100));
  // February 29 exists in 2000, not in 1900: March 1 is 60 resp. 59 days after January 1.
  EXPECT_EQ(daysFromCivil(2000, 3, 1) - daysFromCivil(2000, 1, 1), 60);
  EXPECT_EQ(daysFromCivil(1900, 3, 1) - daysFromCivil(1900, 1, 1), 59);
  EXPECT_EQ(daysFromCivil(1901, 1, 1) - daysFromCivil(1900, 1, 1), 365);
  EXPECT_EQ(daysFromCivil(2001, 1, 1) - daysFromCivil(2000, 1, 1), 366);
  EXPECT_TRUE(parseDate("2000-02-29").has_value());
  EXPECT_FALSE(parseDate("1900-02-29").has_value());
  EXPECT_EQ(parseDate("1900-02")->last - parseDate("1900-02")->first, 27);
  EXPECT_EQ(parseDate("2000-02")->last - parseDate("2000-02")->first, 28);
}

TEST(Dates, CivilFromDaysInvertsDaysFromCivil) {
  for (std::int64_t d = -800000; d <= 800000; d += 997) {
    const CivilDate c = civilFromDays(d);
    EXPECT_EQ(daysFromCivil(c.year, c.month, c.day), d);
  }
  EXPECT_EQ(civilFromDays(-25567), (CivilDate{1900, 1, 1}));
  EXPECT_EQ(formatDay(10957 + 59), "2000-02-29");
  EXPECT_EQ(formatDay(-23741), "1905-01-01");
}

TEST(Dates, PartialDatesAreTheIntervalTheyName) {
  const auto year = parseDate("1905");
  ASSERT_TRUE(year);
  EXPECT_EQ(year->first, -23741);
  EXPECT_EQ(year->last, -23741 + 364);  // 1905-12-31
  const auto month = parseDate("1905-06");
  ASSERT_TRUE(month);
  EXPECT_EQ(month->first, -23590);
  EXPECT_EQ(month->last, -23590 + 29);  // June has 30 days
  EXPECT_EQ(parseDate("1905-06-01"), (DateInterval{-23590, -23590}));
  EXPECT_EQ(parseDate("1905-12")->last, year->last);
}

TEST(Dates, TimeAndZoneAreCheckedButIgnored) {
  const DateInterval day{-23590, -23590};
  for (const char* s : {"1905-06-01T14:43:07", "1905-06-01T14:43", "1905-06-01 14:43:07",
                        "1905-06-01T14:43:07Z", "1905-06-01T14:43:07.25+02:00", "1905-06-01T23:59:60-0500",
                        "1905-06-01T00:00+01", "1905-06-01T24:00"})
    EXPECT_EQ(parseDate(s), day) << s;
}

TEST(Dates, InvalidTextIsRejected) {
  for (const char* s : {"",
                        "190",
                        "19050",
                        "1905-",
                        "1905-6",
                        "1905-13",
                        "1905-00",
                        "1905-06-31",
                        "1905-06-00",
                        "1905/06/01",
                        "1905-06-01T",
                        "1905-06-01T25:00",
                        "1905-06-01T14:60",
                        "1905-06-01T24:01",
                        "1905-06-01T14:43:07+2",
                        "1905-06-01T14:43:07 junk",
                        "1905-06-01x",
                        "c. 1905",
                        " 1905",
                        "1905 ",
                        "+1905",
                        "abcd"})
    EXPECT_FALSE(parseDate(s).has_value()) << "'" << s << "'";
}

TEST(Dates, IntervalsOverlapWhenTheyShareADay) {
  const DateInterval y1905 = *parseDate("1905"), y1906 = *parseDate("1906");
  EXPECT_FALSE(overlaps(y1905, y1906));
  EXPECT_TRUE(overlaps(y1905, *parseDate("1905-12-31")));
  EXPECT_TRUE(overlaps(*parseDate("1905-06"), y1905));  // containment
  EXPECT_TRUE(overlaps(y1905, *parseDate("1905-06")));
  EXPECT_FALSE(overlaps(y1906, *parseDate("1905-12-31")));
  // Open ends (the default interval) overlap everything.
  EXPECT_TRUE(overlaps(DateInterval{}, y1905));
  DateInterval from1906;
  from1906.first = y1906.first;
  EXPECT_FALSE(overlaps(from1906, y1905));
  EXPECT_TRUE(overlaps(from1906, *parseDate("1906-01-01T00:00")));
}

}  // namespace
}  // namespace hv
