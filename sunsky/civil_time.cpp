#include "sunsky/civil_time.h"

#include <date/date.h>
#include <date/tz.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "base/error.h"

namespace fly::sunsky {
namespace {

constexpr int kMinYear = -2000;  // the range SPA is valid for (Reda & Andreas 2004)
constexpr int kMaxYear = 6000;
constexpr int kMaxOffsetMinutes = 18 * 60;  // ISO 8601 / java.time bound; real zones span −12:00..+14:00
// A leap second collapses to this when an instant is shifted (addHours): 1 µs, the resolution of iso(), before
// the minute ends.
constexpr double kLastSecondOfMinute = 59.999999;
constexpr const char* kFormHint =
    "write the time as 2026-06-21T12:00[:00[.5]], followed by Z (UTC) or an offset such as +03:00 when no time "
    "zone is given";

[[noreturn]] void fail(std::string_view what, const std::string& message, std::string hint) {
  throw InputError(SourceLocation{std::string(what)}, message, std::move(hint));
}

std::string quoted(std::string_view s) { return "\"" + std::string(s) + "\""; }

bool isLeapYear(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

int daysInMonth(int y, int m) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && isLeapYear(y) ? 29 : kDays[m - 1];
}

date::sys_days civilDays(int year, int month, int day) {
  return date::sys_days{date::year_month_day{date::year{year}, date::month{static_cast<unsigned>(month)},
                                             date::day{static_cast<unsigned>(day)}}};
}

// The calendar fields of a whole-second UTC instant (second in [0, 60)).
UtcTime utcFromSys(date::sys_seconds s) {
  const date::sys_days day = date::floor<date::days>(s);
  const date::year_month_day ymd{day};
  const date::hh_mm_ss<std::chrono::seconds> hms{s - day};
  UtcTime t;
  t.year = int(ymd.year());
  t.month = static_cast<int>(static_cast<unsigned>(ymd.month()));
  t.day = static_cast<int>(static_cast<unsigned>(ymd.day()));
  t.hour = static_cast<int>(hms.hours().count());
  t.minute = static_cast<int>(hms.minutes().count());
  t.second = static_cast<double>(hms.seconds().count());
  return t;
}

std::string formatOffset(int minutes) {
  char buf[16];
  const int a = std::abs(minutes);
  std::snprintf(buf, sizeof buf, "%c%02d:%02d", minutes < 0 ? '-' : '+', a / 60, a % 60);
  return buf;
}

bool allDigits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

int toInt(std::string_view digits) {
  int v = 0;
  std::from_chars(digits.data(), digits.data() + digits.size(), v);
  return v;
}

// A fixed zone: "Z", "UTC", or an offset "±hh:mm", "±hhmm", "±hh" (ISO 8601 extended and basic forms), in minutes
// east of UTC. nullopt when `s` is not of these forms (it may still be an IANA name).
std::optional<int> parseOffsetMinutes(std::string_view s) {
  if (s == "Z" || s == "z" || s == "UTC") return 0;
  if (s.size() < 3 || (s[0] != '+' && s[0] != '-')) return std::nullopt;
  const std::string_view body = s.substr(1);
  std::string_view hh, mm = "00";
  if (body.size() == 2) {
    hh = body;
  } else if (body.size() == 4) {
    hh = body.substr(0, 2);
    mm = body.substr(2);
  } else if (body.size() == 5 && body[2] == ':') {
    hh = body.substr(0, 2);
    mm = body.substr(3);
  } else {
    return std::nullopt;
  }
  if (!allDigits(hh) || !allDigits(mm)) return std::nullopt;
  const int minutes = toInt(hh) * 60 + toInt(mm);
  if (toInt(mm) >= 60 || minutes > kMaxOffsetMinutes) return std::nullopt;
  return s[0] == '-' ? -minutes : minutes;
}

// An IANA zone from the system tz database; an unknown name is an InputError with a suggestion.
const date::time_zone* locateZone(std::string_view name, std::string_view what) {
  try {
    return date::locate_zone(name);
  } catch (const std::runtime_error&) {
    // Suggest a zone that differs only in case or that ends in the given name ("helsinki" → Europe/Helsinki).
    const auto lower = [](std::string_view s) {
      std::string r(s);
      std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return char(std::tolower(c)); });
      return r;
    };
    const std::string wanted = lower(name);
    std::string suggestion;
    for (const date::time_zone& z : date::get_tzdb().zones) {
      const std::string candidate = lower(z.name());
      if (candidate == wanted || (candidate.size() > wanted.size() &&
                                  candidate.compare(candidate.size() - wanted.size(), wanted.size(), wanted) == 0 &&
                                  candidate[candidate.size() - wanted.size() - 1] == '/')) {
        suggestion = std::string(z.name());
        break;
      }
    }
    fail(what, "unknown time zone " + quoted(name),
         suggestion.empty() ? "use an IANA time-zone name such as Europe/Helsinki or America/Denver (the names "
                              "under /usr/share/zoneinfo), or a UTC offset such as +03:00"
                            : "did you mean " + suggestion + "?");
  }
}

// The parsed fields of a time text, before its zone is applied.
struct LocalFields {
  UtcTime t;              // local calendar fields (second may be 60.x)
  std::string_view zone;  // suffix: "", "Z" or an offset
  std::string_view local; // the text without the suffix, for messages
};

LocalFields parseFields(std::string_view text, std::string_view what) {
  const auto syntax = [&](const std::string& detail) {
    fail(what, quoted(text) + " is not a time: " + detail, kFormHint);
  };
  LocalFields f;
  std::string_view s = text;
  std::size_t i = 0;
  const auto digits = [&](std::size_t n, const char* field) {
    if (s.size() < i + n || !allDigits(s.substr(i, n))) syntax(std::string("expected the ") + field);
    const int v = toInt(s.substr(i, n));
    i += n;
    return v;
  };
  const auto expect = [&](char c, const char* after) {
    if (i >= s.size() || s[i] != c) syntax(std::string("expected '") + c + "' after the " + after);
    ++i;
  };
  int sign = 1;
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
    sign = s[0] == '-' ? -1 : 1;
    ++i;
  }
  f.t.year = sign * digits(4, "year (4 digits)");
  expect('-', "year");
  f.t.month = digits(2, "month (2 digits)");
  expect('-', "month");
  f.t.day = digits(2, "day (2 digits)");
  if (i >= s.size() || (s[i] != 'T' && s[i] != 't' && s[i] != ' ')) syntax("expected 'T' and a time after the date");
  ++i;
  f.t.hour = digits(2, "hour (2 digits)");
  expect(':', "hour");
  f.t.minute = digits(2, "minute (2 digits)");
  if (i < s.size() && s[i] == ':') {
    ++i;
    const std::size_t start = i;
    digits(2, "second (2 digits)");
    if (i < s.size() && (s[i] == '.' || s[i] == ',')) {
      ++i;
      const std::size_t fracStart = i;
      while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
      if (i == fracStart) syntax("expected digits after the decimal point of the second");
    }
    std::string secondText(s.substr(start, i - start));
    std::replace(secondText.begin(), secondText.end(), ',', '.');
    std::from_chars(secondText.data(), secondText.data() + secondText.size(), f.t.second);
  }
  f.local = s.substr(0, i);
  f.zone = s.substr(i);
  if (!f.zone.empty() && !parseOffsetMinutes(f.zone)) {
    syntax("cannot read " + quoted(f.zone) + " as Z or a UTC offset such as +03:00");
  }
  return f;
}

// Range checks shared by local and UTC fields; a leap second is checked once the UTC time is known.
void checkFields(const UtcTime& t, std::string_view what, std::string_view text) {
  const std::string in = text.empty() ? std::string() : " in " + quoted(text);
  if (t.year < kMinYear || t.year > kMaxYear) {
    fail(what, "year " + std::to_string(t.year) + in + " is outside " + std::to_string(kMinYear) + ".." +
                   std::to_string(kMaxYear),
         "the solar position algorithm is valid for the years -2000 to 6000");
  }
  if (t.month < 1 || t.month > 12) {
    fail(what, "month " + std::to_string(t.month) + in + " is outside 1..12", "months are numbered 01 to 12");
  }
  if (t.day < 1 || t.day > daysInMonth(t.year, t.month)) {
    fail(what,
         "day " + std::to_string(t.day) + in + " does not exist: month " + std::to_string(t.month) + " of " +
             std::to_string(t.year) + " has " + std::to_string(daysInMonth(t.year, t.month)) + " days",
         t.month == 2 && t.day == 29 ? std::to_string(t.year) + " is not a leap year" : "check the date");
  }
  if (t.hour < 0 || t.hour > 23) {
    fail(what, "hour " + std::to_string(t.hour) + in + " is outside 0..23", "write midnight as 00:00 of the next day");
  }
  if (t.minute < 0 || t.minute > 59) {
    fail(what, "minute " + std::to_string(t.minute) + in + " is outside 0..59", "check the time");
  }
  if (!(t.second >= 0.0 && t.second < 61.0)) {
    fail(what, "second " + std::to_string(t.second) + in + " is outside [0, 61)",
         "seconds run 00..59; 60 is valid only for a leap second (23:59:60 UTC)");
  }
}

[[noreturn]] void failLeapSecond(std::string_view what, std::string_view text, const UtcTime& utc) {
  fail(what,
       "second 60" + (text.empty() ? std::string() : " in " + quoted(text)) + " is not a leap second: it falls at " +
           utc.iso(),
       "a leap second is 23:59:60 UTC (at the end of a UTC day); other minutes end at :59");
}

date::local_seconds localSeconds(const UtcTime& local) {
  return date::local_seconds{(civilDays(local.year, local.month, local.day) + std::chrono::hours{local.hour} +
                              std::chrono::minutes{local.minute} +
                              std::chrono::seconds{static_cast<long long>(std::min(std::floor(local.second), 59.0))})
                                 .time_since_epoch()};
}

// Local fields at a UTC offset (local − UTC) → UTC. The whole seconds go through the calendar; the fraction, and
// the extra second of a leap second (60.x), are added back to the UTC fields.
UtcTime shiftToUtc(const UtcTime& local, std::chrono::seconds localMinusUtc, std::string_view what,
                   std::string_view text) {
  const double whole = std::min(std::floor(local.second), 59.0);
  UtcTime utc = utcFromSys(date::sys_seconds{localSeconds(local).time_since_epoch() - localMinusUtc});
  if (local.second >= 60.0 && !(utc.hour == 23 && utc.minute == 59 && utc.second == 59.0)) {
    failLeapSecond(what, text, utc);
  }
  utc.second += local.second - whole;
  return utc;
}

std::string offsetLabel(const date::sys_info& info) {
  return info.abbrev + " " + formatOffset(static_cast<int>(info.offset.count() / 60));
}

// Local fields in an IANA zone → UTC; a time in a daylight-saving gap or overlap is an InputError naming both
// readings.
UtcTime zoneToUtc(const UtcTime& local, const date::time_zone& zone, std::string_view what, std::string_view text,
                  std::string_view localText) {
  const date::local_info info = zone.get_info(localSeconds(local));
  if (info.result == date::local_info::unique) return shiftToUtc(local, info.first.offset, what, text);
  const UtcTime a = shiftToUtc(local, info.first.offset, what, text);
  const UtcTime b = shiftToUtc(local, info.second.offset, what, text);
  const std::string readings = std::string(localText) + formatOffset(int(info.first.offset.count() / 60)) + " (" +
                               info.first.abbrev + ", " + a.iso() + ") or " + std::string(localText) +
                               formatOffset(int(info.second.offset.count() / 60)) + " (" + info.second.abbrev +
                               ", " + b.iso() + ")";
  // The local clock readings at the transition: before it (old offset) and after it (new offset).
  const date::sys_seconds change = info.second.begin;
  const auto clock = [&](std::chrono::seconds offset) {
    const UtcTime c = utcFromSys(change + offset);
    char buf[8];
    std::snprintf(buf, sizeof buf, "%02d:%02d", c.hour, c.minute);
    return std::string(buf);
  };
  if (info.result == date::local_info::nonexistent) {
    fail(what,
         quoted(localText) + " does not exist in " + zone.name() + ": the clocks jump from " +
             clock(info.first.offset) + " to " + clock(info.second.offset) + " (" + offsetLabel(info.first) +
             " to " + offsetLabel(info.second) + ")",
         "the time falls in the daylight-saving gap; give an offset to say which is meant: " + readings);
  }
  fail(what,
       quoted(localText) + " occurs twice in " + zone.name() + ": the clocks go back from " +
           clock(info.first.offset) + " to " + clock(info.second.offset) + " (" + offsetLabel(info.first) + " to " +
           offsetLabel(info.second) + ")",
       "give an offset to say which is meant: " + readings);
}

}  // namespace

std::string UtcTime::iso() const {
  // Microseconds, rounded; a time just short of a minute's end never shows as :60 unless it is a leap second.
  long long us = std::llround(second * 1e6);
  us = std::clamp(us, 0LL, second < 60.0 ? 59'999'999LL : 60'999'999LL);
  char buf[48];
  int n = std::snprintf(buf, sizeof buf, year < 0 ? "%05d-%02d-%02dT%02d:%02d:%02lld" : "%04d-%02d-%02dT%02d:%02d:%02lld",
                        year, month, day, hour, minute, us / 1'000'000);
  if (const long long frac = us % 1'000'000; frac != 0) {
    char f[8];
    std::snprintf(f, sizeof f, "%06lld", frac);
    std::string digits(f);
    digits.erase(digits.find_last_not_of('0') + 1);
    n += std::snprintf(buf + n, sizeof buf - std::size_t(n), ".%s", digits.c_str());
  }
  return std::string(buf, std::size_t(n)) + "Z";
}

void checkUtcTime(const UtcTime& t, std::string_view what) {
  checkFields(t, what, {});
  if (t.second >= 60.0 && !(t.hour == 23 && t.minute == 59)) failLeapSecond(what, {}, t);
}

std::string zoneOfTime(std::string_view text) {
  text = text.substr(0, text.find_last_not_of(" \t") + 1);
  text.remove_prefix(std::min(text.find_first_not_of(" \t"), text.size()));
  // The suffix after the time of day: a 'Z', or the last '+' or '-' (the date's '-' come before the 'T').
  const std::size_t t = text.find_first_of("Tt ", 1);
  if (t == std::string_view::npos) return {};
  const std::size_t z = text.find_first_of("Zz+-", t);
  if (z == std::string_view::npos) return {};
  const std::optional<int> minutes = parseOffsetMinutes(text.substr(z));
  if (!minutes) return {};
  return text[z] == 'Z' || text[z] == 'z' ? "Z" : formatOffset(*minutes);
}

UtcTime parseTime(std::string_view text, std::string_view timeZone, std::string_view what) {
  const auto trim = [](std::string_view s) {
    const std::size_t b = s.find_first_not_of(" \t");
    if (b == std::string_view::npos) return std::string_view();
    return s.substr(b, s.find_last_not_of(" \t") - b + 1);
  };
  text = trim(text);
  timeZone = trim(timeZone);
  const LocalFields f = parseFields(text, what);
  checkFields(f.t, what, text);
  UtcTime utc;
  if (!f.zone.empty()) {
    utc = shiftToUtc(f.t, std::chrono::minutes{*parseOffsetMinutes(f.zone)}, what, text);
  } else if (timeZone.empty()) {
    fail(what, quoted(text) + " has no time zone",
         "append Z (UTC) or a UTC offset such as +03:00, or give a time zone such as Europe/Helsinki");
  } else if (const std::optional<int> offset = parseOffsetMinutes(timeZone)) {
    utc = shiftToUtc(f.t, std::chrono::minutes{*offset}, what, text);
  } else {
    utc = zoneToUtc(f.t, *locateZone(timeZone, what), what, text, f.local);
  }
  checkUtcTime(utc, what);  // the year range holds for the UTC instant too
  return utc;
}

double utcOffsetHours(std::string_view timeZone, const UtcTime& t) {
  checkUtcTime(t);
  if (timeZone.empty()) {
    fail("time zone", "no time zone given", "give an IANA time-zone name such as Europe/Helsinki or an offset such as +03:00");
  }
  if (const std::optional<int> offset = parseOffsetMinutes(timeZone)) return *offset / 60.0;
  const date::sys_seconds s =
      civilDays(t.year, t.month, t.day) + std::chrono::hours{t.hour} + std::chrono::minutes{t.minute} +
      std::chrono::seconds{static_cast<long long>(std::min(std::floor(t.second), 59.0))};
  return static_cast<double>(locateZone(timeZone, "time zone")->get_info(s).offset.count()) / 3600.0;
}

UtcTime addHours(const UtcTime& t, double hours) {
  if (!std::isfinite(hours)) fail("time", "cannot shift a time by a non-finite number of hours", {});
  const double second = std::min(t.second, kLastSecondOfMinute);
  double secondOfDay = t.hour * 3600.0 + t.minute * 60.0 + second + hours * 3600.0;
  double dayShift = std::floor(secondOfDay / 86400.0);
  secondOfDay -= dayShift * 86400.0;
  if (secondOfDay >= 86400.0) {  // rounding of a tiny negative remainder
    secondOfDay -= 86400.0;
    dayShift += 1.0;
  }
  secondOfDay = std::max(secondOfDay, 0.0);
  const date::sys_days day = civilDays(t.year, t.month, t.day) + date::days{static_cast<long long>(dayShift)};
  UtcTime r = utcFromSys(date::sys_seconds{day});
  r.hour = std::min(static_cast<int>(secondOfDay / 3600.0), 23);
  secondOfDay -= r.hour * 3600.0;
  r.minute = std::min(static_cast<int>(secondOfDay / 60.0), 59);
  r.second = std::min(secondOfDay - r.minute * 60.0, kLastSecondOfMinute);
  return r;
}

double julianDay(const UtcTime& t, double dut1Seconds) {
  // Eq. 4 with the Gregorian B for every year (the proleptic Gregorian calendar), evaluated through an exact day
  // count so that negative years need none of eq. 4's INT() truncation rules. JD 2440587.5 = 1970-01-01 0h.
  const double days = static_cast<double>(civilDays(t.year, t.month, t.day).time_since_epoch().count());
  const double secondOfDay = t.hour * 3600.0 + t.minute * 60.0 + t.second + dut1Seconds;
  return 2440587.5 + days + secondOfDay / 86400.0;
}

int dayOfYear(const UtcTime& t) {
  static constexpr int kDaysBefore[12] = {0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334};
  const bool leap = (t.year % 4 == 0 && t.year % 100 != 0) || t.year % 400 == 0;
  return kDaysBefore[t.month - 1] + t.day + (leap && t.month > 2 ? 1 : 0);
}

}  // namespace fly::sunsky
