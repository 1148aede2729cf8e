// Civil time: ISO 8601 input, time zones (IANA names through the system tz database, or fixed UTC offsets),
// leap seconds, and the Julian day of an instant.
#pragma once

#include <string>
#include <string_view>

namespace fly::sunsky {

// A UTC calendar instant. `second` is in [0, 61): 60.x is a leap second (23:59:60), valid input.
struct UtcTime {
  int year = 2000;   // proleptic Gregorian, [-2000, 6000]
  int month = 1;     // 1..12
  int day = 1;       // 1..31
  int hour = 0;      // 0..23
  int minute = 0;    // 0..59
  double second = 0.0;

  std::string iso() const;  // "2026-06-21T09:00:00Z" (fractional seconds when present)
};

// Parses a time as the CLI and scene files take it and converts it to UTC:
//   "2026-06-21T12:00[:00[.5]]"        local time in `timeZone`
//   "2026-06-21T09:00:00Z"             UTC (then `timeZone` is ignored)
//   "2026-06-21T12:00+03:00"           an explicit UTC offset; also "+0300" and "+03" (ISO 8601 basic forms)
// A space may stand for the "T"; fractional seconds may have any number of digits.
// `timeZone` is an IANA name ("Europe/Helsinki", daylight saving applied), a fixed offset ("+03:00", "-07:00",
// "UTC", "Z") or "" (then the time must carry Z or an offset). A local time that does not exist (in a
// daylight-saving gap) or exists twice (in the overlap) is an InputError that says so and names both
// candidates; an unknown zone, month 13 or minute 61 is an InputError naming `what` (e.g. "--time").
UtcTime parseTime(std::string_view text, std::string_view timeZone, std::string_view what = "time");

// The UTC offset in hours that `timeZone` has at the UTC instant `t` (DST included).
double utcOffsetHours(std::string_view timeZone, const UtcTime& t);

// `t` shifted by `hours` (any sign), normalised to a valid calendar date; leap seconds collapse to :59.999….
UtcTime addHours(const UtcTime& t, double hours);

// Day of the year (1..366) of t's calendar date (proleptic Gregorian).
int dayOfYear(const UtcTime& t);

// Julian day of a UTC instant (Reda & Andreas 2004, eq. 4; Gregorian calendar), with UT1 = UTC + dut1Seconds.
// A leap second 23:59:60.x counts as second 60.x of its minute: the day fraction runs on past 23:59:59
// (UT1 has no leap seconds; the ≤ 1 s this leaves is what dut1Seconds is for).
double julianDay(const UtcTime& t, double dut1Seconds = 0.0);

// InputError naming `what` unless `t` is a valid UTC instant: year, month, day (leap years included), hour,
// minute in range, second in [0, 61), and a second of 60.x only at 23:59 (a leap second).
void checkUtcTime(const UtcTime& t, std::string_view what = "time");

// The zone a time text carries, normalised: "Z", an offset "+05:30", or "" when it carries none (then
// parseTime takes the zone from its `timeZone` argument).
std::string zoneOfTime(std::string_view text);

}  // namespace fly::sunsky
