#include "sunsky/civil_time.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "base/error.h"

namespace fly::sunsky {
namespace {

// The message and hint of the InputError that parseTime throws, or "" when it does not throw.
std::string parseError(const std::string& text, const std::string& zone) {
  try {
    parseTime(text, zone, "--time");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

void expectUtc(const UtcTime& t, int year, int month, int day, int hour, int minute, double second) {
  EXPECT_EQ(t.year, year);
  EXPECT_EQ(t.month, month);
  EXPECT_EQ(t.day, day);
  EXPECT_EQ(t.hour, hour);
  EXPECT_EQ(t.minute, minute);
  EXPECT_DOUBLE_EQ(t.second, second);
}

TEST(CivilTime, IanaZoneAppliesDaylightSaving) {
  // Helsinki is EEST (UTC+3) in June, EET (UTC+2) in January.
  expectUtc(parseTime("2026-06-21T12:00", "Europe/Helsinki"), 2026, 6, 21, 9, 0, 0.0);
  expectUtc(parseTime("2026-01-15T12:00:00", "Europe/Helsinki"), 2026, 1, 15, 10, 0, 0.0);
  expectUtc(parseTime("2003-10-17T12:30:30", "America/Phoenix"), 2003, 10, 17, 19, 30, 30.0);
  // A space may stand for the T; surrounding blanks are ignored.
  expectUtc(parseTime("  2026-06-21 12:00  ", "Europe/Helsinki"), 2026, 6, 21, 9, 0, 0.0);
  EXPECT_DOUBLE_EQ(utcOffsetHours("Europe/Helsinki", parseTime("2026-06-21T09:00Z", "")), 3.0);
  EXPECT_DOUBLE_EQ(utcOffsetHours("Europe/Helsinki", parseTime("2026-12-21T09:00Z", "")), 2.0);
  EXPECT_DOUBLE_EQ(utcOffsetHours("Asia/Kolkata", parseTime("2026-12-21T09:00Z", "")), 5.5);
}

TEST(CivilTime, DaylightSavingGapIsAnInputErrorNamingBothReadings) {
  // 2026-03-29: Helsinki's clocks jump from 03:00 EET to 04:00 EEST; 03:30 never happens.
  const std::string e = parseError("2026-03-29T03:30", "Europe/Helsinki");
  EXPECT_TRUE(contains(e, "--time: \"2026-03-29T03:30\" does not exist in Europe/Helsinki")) << e;
  EXPECT_TRUE(contains(e, "from 03:00 to 04:00")) << e;
  EXPECT_TRUE(contains(e, "2026-03-29T03:30+02:00 (EET, 2026-03-29T01:30:00Z)")) << e;
  EXPECT_TRUE(contains(e, "2026-03-29T03:30+03:00 (EEST, 2026-03-29T00:30:00Z)")) << e;
  // Either reading, given explicitly, is accepted.
  expectUtc(parseTime("2026-03-29T03:30+02:00", "Europe/Helsinki"), 2026, 3, 29, 1, 30, 0.0);
}

TEST(CivilTime, DaylightSavingOverlapIsAnInputErrorNamingBothReadings) {
  // 2026-10-25: Helsinki's clocks go back from 04:00 EEST to 03:00 EET; 03:30 happens twice.
  const std::string e = parseError("2026-10-25T03:30", "Europe/Helsinki");
  EXPECT_TRUE(contains(e, "\"2026-10-25T03:30\" occurs twice in Europe/Helsinki")) << e;
  EXPECT_TRUE(contains(e, "from 04:00 to 03:00")) << e;
  EXPECT_TRUE(contains(e, "2026-10-25T03:30+03:00 (EEST, 2026-10-25T00:30:00Z)")) << e;
  EXPECT_TRUE(contains(e, "2026-10-25T03:30+02:00 (EET, 2026-10-25T01:30:00Z)")) << e;
  expectUtc(parseTime("2026-10-25T03:30+02:00", ""), 2026, 10, 25, 1, 30, 0.0);
}

TEST(CivilTime, UnknownZoneIsAnInputErrorWithAHint) {
  const std::string e = parseError("2026-06-21T12:00", "Mars/Olympus");
  EXPECT_TRUE(contains(e, "--time: unknown time zone \"Mars/Olympus\"")) << e;
  EXPECT_TRUE(contains(e, "hint: use an IANA time-zone name such as Europe/Helsinki")) << e;
  // A name that differs only in case, or lacks its region, gets a suggestion.
  EXPECT_TRUE(contains(parseError("2026-06-21T12:00", "europe/helsinki"), "did you mean Europe/Helsinki?"));
  EXPECT_TRUE(contains(parseError("2026-06-21T12:00", "Helsinki"), "did you mean Europe/Helsinki?"));
  EXPECT_THROW(utcOffsetHours("Mars/Olympus", UtcTime{}), InputError);
  EXPECT_THROW(utcOffsetHours("", UtcTime{}), InputError);
}

TEST(CivilTime, InvalidFieldsAreInputErrors) {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"2026-13-01T12:00Z", "month 13 in \"2026-13-01T12:00Z\" is outside 1..12"},
      {"2026-00-01T12:00Z", "month 0"},
      {"2026-01-32T12:00Z", "day 32 in \"2026-01-32T12:00Z\" does not exist: month 1 of 2026 has 31 days"},
      {"2025-02-29T12:00Z", "day 29 in \"2025-02-29T12:00Z\" does not exist: month 2 of 2025 has 28 days"},
      {"2026-04-31T12:00Z", "month 4 of 2026 has 30 days"},
      {"2026-06-21T24:00Z", "hour 24"},
      {"2026-06-21T12:60Z", "minute 60"},
      {"2026-06-21T12:00:61Z", "second 61"},
      {"2026-06-21T12:00:60Z", "second 60 in \"2026-06-21T12:00:60Z\" is not a leap second"},
      {"6001-01-01T00:00Z", "year 6001"},
      {"-2001-01-01T00:00Z", "year -2001"},
      {"6000-12-31T23:00-05:00", "year 6001"},  // in range locally, not in UTC
      {"2026-06-21", "expected 'T' and a time after the date"},
      {"2026-6-21T12:00Z", "expected the month"},
      {"2026-06-21T12:00:00.Z", "expected digits after the decimal point"},
      {"2026-06-21T12:00+3", "cannot read \"+3\" as Z or a UTC offset"},
      {"2026-06-21T12:00+25:00", "cannot read \"+25:00\""},
      {"noon", "\"noon\" is not a time"},
  };
  for (const Case& c : cases) {
    const std::string e = parseError(c.text, "");
    EXPECT_TRUE(contains(e, std::string("--time: ")) && contains(e, c.message)) << c.text << " → " << e;
    EXPECT_TRUE(contains(e, "hint: ")) << c.text << " → " << e;
  }
  EXPECT_TRUE(contains(parseError("2025-02-29T12:00Z", ""), "2025 is not a leap year"));
  EXPECT_EQ(parseError("2024-02-29T12:00Z", ""), "");  // a leap year
  EXPECT_EQ(parseError("2000-02-29T12:00Z", ""), "");  // divisible by 400
  EXPECT_NE(parseError("1900-02-29T12:00Z", ""), "");  // divisible by 100 only
  EXPECT_TRUE(contains(parseError("2026-06-21T12:00", ""), "has no time zone"));
}

TEST(CivilTime, OffsetsAndUtcForms) {
  expectUtc(parseTime("2026-06-21T09:00:00Z", "Europe/Helsinki"), 2026, 6, 21, 9, 0, 0.0);  // Z wins over the zone
  expectUtc(parseTime("2026-06-21T12:00+03:00", ""), 2026, 6, 21, 9, 0, 0.0);
  expectUtc(parseTime("2026-06-21T12:00-07:00", ""), 2026, 6, 21, 19, 0, 0.0);
  expectUtc(parseTime("2026-06-21T12:00+0530", ""), 2026, 6, 21, 6, 30, 0.0);
  expectUtc(parseTime("2026-06-21T12:00+05", ""), 2026, 6, 21, 7, 0, 0.0);
  expectUtc(parseTime("2026-06-21T12:00", "+03:00"), 2026, 6, 21, 9, 0, 0.0);
  expectUtc(parseTime("2026-06-21T12:00", "-07:00"), 2026, 6, 21, 19, 0, 0.0);
  expectUtc(parseTime("2026-06-21T12:00", "+0530"), 2026, 6, 21, 6, 30, 0.0);
  expectUtc(parseTime("2026-06-21T12:00", "Z"), 2026, 6, 21, 12, 0, 0.0);
  expectUtc(parseTime("2026-06-21T12:00", "UTC"), 2026, 6, 21, 12, 0, 0.0);
  // An offset that crosses midnight and a year boundary.
  expectUtc(parseTime("2027-01-01T01:00+03:00", ""), 2026, 12, 31, 22, 0, 0.0);
  EXPECT_DOUBLE_EQ(utcOffsetHours("-07:00", UtcTime{}), -7.0);
  EXPECT_DOUBLE_EQ(utcOffsetHours("+0530", UtcTime{}), 5.5);
  EXPECT_DOUBLE_EQ(utcOffsetHours("Z", UtcTime{}), 0.0);

  EXPECT_EQ(zoneOfTime("2026-06-21T12:00Z"), "Z");
  EXPECT_EQ(zoneOfTime("2026-06-21T12:00:00.5+0530"), "+05:30");
  EXPECT_EQ(zoneOfTime("2026-06-21T12:00-07"), "-07:00");
  EXPECT_EQ(zoneOfTime("-0100-06-21T12:00-07:00"), "-07:00");
  EXPECT_EQ(zoneOfTime("2026-06-21T12:00"), "");
  EXPECT_EQ(zoneOfTime("2026-06-21 12:00"), "");
  EXPECT_EQ(zoneOfTime("  2026-06-21 12:00Z  "), "Z");
}

TEST(CivilTime, FractionalAndLeapSeconds) {
  expectUtc(parseTime("2026-06-21T12:00:00.25Z", ""), 2026, 6, 21, 12, 0, 0.25);
  expectUtc(parseTime("2026-06-21T12:00:07,5Z", ""), 2026, 6, 21, 12, 0, 7.5);
  // The leap second at the end of 2016, in UTC and as local time at +02:00.
  expectUtc(parseTime("2016-12-31T23:59:60Z", ""), 2016, 12, 31, 23, 59, 60.0);
  expectUtc(parseTime("2017-01-01T01:59:60.5+02:00", ""), 2016, 12, 31, 23, 59, 60.5);
  expectUtc(parseTime("2017-01-01T01:59:60.5", "Europe/Helsinki"), 2016, 12, 31, 23, 59, 60.5);
  EXPECT_TRUE(contains(parseError("2017-01-01T23:59:60+02:00", ""), "falls at 2017-01-01T21:59:59Z"));

  // Julian day: the leap second counts as second 60.x of its minute, so 23:59:60.5 has the Julian day of
  // 00:00:00.5 the next day (documented in civil_time.h).
  const double leap = julianDay(parseTime("2016-12-31T23:59:60.5Z", ""));
  const double next = julianDay(parseTime("2017-01-01T00:00:00.5Z", ""));
  EXPECT_NEAR(leap, next, 1e-9);
  EXPECT_GT(leap, julianDay(parseTime("2016-12-31T23:59:59.5Z", "")));

  EXPECT_NO_THROW(checkUtcTime(UtcTime{2016, 12, 31, 23, 59, 60.9}));
  EXPECT_THROW(checkUtcTime(UtcTime{2016, 12, 31, 22, 59, 60.0}), InputError);
  EXPECT_THROW(checkUtcTime(UtcTime{2016, 12, 31, 23, 59, 61.0}), InputError);
  EXPECT_THROW(checkUtcTime(UtcTime{2016, 12, 31, 23, 59, -0.5}), InputError);
}

TEST(CivilTime, IsoFormatting) {
  EXPECT_EQ((UtcTime{2026, 6, 21, 9, 0, 0.0}).iso(), "2026-06-21T09:00:00Z");
  EXPECT_EQ((UtcTime{2026, 6, 21, 9, 0, 5.25}).iso(), "2026-06-21T09:00:05.25Z");
  EXPECT_EQ((UtcTime{2016, 12, 31, 23, 59, 60.5}).iso(), "2016-12-31T23:59:60.5Z");
  EXPECT_EQ((UtcTime{-44, 3, 15, 12, 0, 0.0}).iso(), "-0044-03-15T12:00:00Z");
  // Just short of a minute's end rounds down to the microsecond rather than showing :60.
  EXPECT_EQ((UtcTime{2026, 6, 21, 9, 0, 59.9999999}).iso(), "2026-06-21T09:00:59.999999Z");
}

TEST(CivilTime, AddHoursNormalisesTheCalendar) {
  expectUtc(addHours(UtcTime{2026, 12, 31, 22, 0, 0.0}, 3.0), 2027, 1, 1, 1, 0, 0.0);
  expectUtc(addHours(UtcTime{2024, 3, 1, 1, 0, 0.0}, -2.0), 2024, 2, 29, 23, 0, 0.0);
  expectUtc(addHours(UtcTime{2026, 6, 21, 9, 0, 0.0}, 0.5), 2026, 6, 21, 9, 30, 0.0);
  expectUtc(addHours(UtcTime{2026, 6, 21, 0, 0, 0.0}, -24.0 * 365.0), 2025, 6, 21, 0, 0, 0.0);
  const UtcTime t = addHours(UtcTime{2026, 6, 21, 9, 0, 0.0}, 1.0 / 3600.0 * 1.25);
  EXPECT_NEAR(t.second, 1.25, 1e-9);
  // A leap second collapses to the last microsecond of its minute.
  const UtcTime leap = addHours(UtcTime{2016, 12, 31, 23, 59, 60.5}, 0.0);
  expectUtc(leap, 2016, 12, 31, 23, 59, 59.999999);
  EXPECT_THROW(addHours(UtcTime{}, std::nan("")), InputError);
}

TEST(CivilTime, JulianDayMatchesTheReportsTable) {
  // Reda & Andreas, table A4.1, its Gregorian-calendar rows (before 1582 the table uses the Julian calendar,
  // UtcTime the proleptic Gregorian one).
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{2000, 1, 1, 12, 0, 0.0}), 2451545.0);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1999, 1, 1, 0, 0, 0.0}), 2451179.5);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1987, 1, 27, 0, 0, 0.0}), 2446822.5);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1987, 6, 19, 12, 0, 0.0}), 2446966.0);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1988, 1, 27, 0, 0, 0.0}), 2447187.5);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1988, 6, 19, 12, 0, 0.0}), 2447332.0);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1900, 1, 1, 0, 0, 0.0}), 2415020.5);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1600, 1, 1, 0, 0, 0.0}), 2305447.5);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1600, 12, 31, 0, 0, 0.0}), 2305812.5);
  // The proleptic Gregorian calendar runs on before 1582: 1582-10-15 (Gregorian) is JD 2299160.5, and the Julian
  // calendar's 4713 BC January 1 noon (JD 0) is 4714 BC November 24 (year −4713) in it, 2713 years before the
  // range here; −2000-01-01 is 730,485 days (2000 proleptic Gregorian years) before 0000-01-01 = JD 1721059.5.
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{1582, 10, 15, 0, 0, 0.0}), 2299160.5);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{0, 1, 1, 0, 0, 0.0}), 1721059.5);
  EXPECT_DOUBLE_EQ(julianDay(UtcTime{-2000, 1, 1, 0, 0, 0.0}), 1721059.5 - 730485.0);
  // The paper's example instant (table A5.1) and dut1.
  EXPECT_NEAR(julianDay(UtcTime{2003, 10, 17, 19, 30, 30.0}), 2452930.312847, 5e-7);
  EXPECT_NEAR(julianDay(UtcTime{2000, 1, 1, 12, 0, 0.0}, 0.5) - 2451545.0, 0.5 / 86400.0, 1e-9);  // JD resolution ≈ 40 µs
}

}  // namespace
}  // namespace fly::sunsky

namespace fly::sunsky {
namespace {

TEST(CivilTime, DayOfYear) {
  EXPECT_EQ(dayOfYear(parseTime("2026-01-01T00:00Z", "")), 1);
  EXPECT_EQ(dayOfYear(parseTime("2026-06-21T23:59Z", "")), 172);  // 31+28+31+30+31+21
  EXPECT_EQ(dayOfYear(parseTime("2026-03-01T12:00Z", "")), 60);
  EXPECT_EQ(dayOfYear(parseTime("2024-03-01T12:00Z", "")), 61);   // leap year
  EXPECT_EQ(dayOfYear(parseTime("2024-12-31T12:00Z", "")), 366);
  EXPECT_EQ(dayOfYear(parseTime("2100-12-31T12:00Z", "")), 365);  // not a leap year (divisible by 100)
}

}  // namespace
}  // namespace fly::sunsky
