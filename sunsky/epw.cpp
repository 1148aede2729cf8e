#include "sunsky/epw.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <system_error>
#include <utility>

#include "base/error.h"
#include "base/file_io.h"

namespace fly::sunsky {
namespace {

// The header lines in the order the data dictionary gives them, by the first field of each line. Files in the
// wild spell the fifth "HOLIDAYS/DAYLIGHT SAVINGS"; the dictionary's IDD text "HOLIDAYS/DAYLIGHT SAVING".
constexpr std::array<std::string_view, 8> kHeaderKeywords = {"LOCATION",
                                                             "DESIGN CONDITIONS",
                                                             "TYPICAL/EXTREME PERIODS",
                                                             "GROUND TEMPERATURES",
                                                             "HOLIDAYS/DAYLIGHT SAVINGS",
                                                             "COMMENTS 1",
                                                             "COMMENTS 2",
                                                             "DATA PERIODS"};
constexpr int kHeaderLineCount = static_cast<int>(kHeaderKeywords.size());
constexpr char kHeaderOrderHint[] =
    "an EPW file starts with 8 header lines: LOCATION, DESIGN CONDITIONS, TYPICAL/EXTREME PERIODS, GROUND "
    "TEMPERATURES, HOLIDAYS/DAYLIGHT SAVINGS, COMMENTS 1, COMMENTS 2, DATA PERIODS";
constexpr char kTruncatedHint[] = "the file is truncated; download or export it again";
constexpr char kRecordHint[] =
    "an EPW record is 35 comma-separated fields (EnergyPlus Auxiliary Programs, EPW Data Dictionary)";

// Field names of an hourly record, 1-based in messages as in the data dictionary's table.
constexpr std::array<std::string_view, 35> kFieldNames = {"year",
                                                          "month",
                                                          "day",
                                                          "hour",
                                                          "minute",
                                                          "data source and uncertainty flags",
                                                          "dry bulb temperature",
                                                          "dew point temperature",
                                                          "relative humidity",
                                                          "atmospheric station pressure",
                                                          "extraterrestrial horizontal radiation",
                                                          "extraterrestrial direct normal radiation",
                                                          "horizontal infrared radiation intensity",
                                                          "global horizontal radiation",
                                                          "direct normal radiation",
                                                          "diffuse horizontal radiation",
                                                          "global horizontal illuminance",
                                                          "direct normal illuminance",
                                                          "diffuse horizontal illuminance",
                                                          "zenith luminance",
                                                          "wind direction",
                                                          "wind speed",
                                                          "total sky cover",
                                                          "opaque sky cover",
                                                          "visibility",
                                                          "ceiling height",
                                                          "present weather observation",
                                                          "present weather codes",
                                                          "precipitable water",
                                                          "aerosol optical depth",
                                                          "snow depth",
                                                          "days since last snowfall",
                                                          "albedo",
                                                          "liquid precipitation depth",
                                                          "liquid precipitation quantity"};
constexpr std::size_t kFieldCount = kFieldNames.size();
constexpr std::size_t kFlagsField = 5;
constexpr std::size_t kWeatherCodesField = 27;

// The numeric measurement fields: index in the record, the data dictionary's "\missing" code (a value at or
// above it is missing) and whether its "\minimum 0" is checked. Only the daylight fields fly uses are checked
// for sign; the rest are carried as written.
struct ValueField {
  std::size_t index;
  double missingFrom;
  bool nonNegative;
  std::optional<double> EpwRecord::*member;
};
constexpr std::array<ValueField, 28> kValueFields = {{
    {6, 99.9, false, &EpwRecord::dryBulbC},
    {7, 99.9, false, &EpwRecord::dewPointC},
    {8, 999.0, false, &EpwRecord::relativeHumidityPct},
    {9, 999999.0, false, &EpwRecord::pressurePa},
    {10, 9999.0, true, &EpwRecord::extraterrestrialHorizontalWm2},
    {11, 9999.0, true, &EpwRecord::extraterrestrialDirectNormalWm2},
    {12, 9999.0, true, &EpwRecord::horizontalInfraredWm2},
    {13, 9999.0, true, &EpwRecord::ghiWm2},
    {14, 9999.0, true, &EpwRecord::dniWm2},
    {15, 9999.0, true, &EpwRecord::dhiWm2},
    {16, 999900.0, true, &EpwRecord::ghiLux},  // "will be missing if >= 999900"
    {17, 999900.0, true, &EpwRecord::dniLux},
    {18, 999900.0, true, &EpwRecord::dhiLux},
    {19, 9999.0, true, &EpwRecord::zenithLuminanceCdM2},
    {20, 999.0, false, &EpwRecord::windDirectionDeg},
    {21, 999.0, false, &EpwRecord::windSpeedMS},
    {22, 99.0, false, &EpwRecord::totalSkyCoverTenths},
    {23, 99.0, false, &EpwRecord::opaqueSkyCoverTenths},
    {24, 9999.0, false, &EpwRecord::visibilityKm},
    {25, 99999.0, false, &EpwRecord::ceilingHeightM},
    {26, 9.0, false, &EpwRecord::presentWeatherObservation},
    {28, 999.0, false, &EpwRecord::precipitableWaterMm},
    {29, 0.999, false, &EpwRecord::aerosolOpticalDepth},
    {30, 999.0, false, &EpwRecord::snowDepthCm},
    {31, 99.0, false, &EpwRecord::daysSinceLastSnowfall},
    {32, 999.0, false, &EpwRecord::albedo},
    {33, 999.0, false, &EpwRecord::liquidPrecipitationDepthMm},
    {34, 99.0, false, &EpwRecord::liquidPrecipitationQuantityH},
}};

constexpr std::array<int, 12> kDaysInMonth = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};  // Feb: leap
constexpr int kHoursInLeapYear = 366 * 24;

struct Line {
  std::string_view text;   // without the line break
  int number = 0;          // 1-based
  bool terminated = true;  // ends with '\n' (false only for the last line of a file cut short)
};

struct Field {
  std::string_view text;  // trimmed
  int column = 0;         // 1-based byte column of the field's first character
};

std::string_view trim(std::string_view s) {
  const auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

char upper(char c) {
  return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
}

bool equalsNoCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (upper(a[i]) != upper(b[i])) return false;
  }
  return true;
}

std::string quoted(std::string_view s) { return "'" + printableExcerpt(s) + "'"; }

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string dateText(int month, int day) {
  return std::to_string(month) + "/" + std::to_string(day);
}

std::string recordText(int month, int day, int hour) {
  return dateText(month, day) + " hour " + std::to_string(hour);
}

// A finite number in C locale notation ("12", "-3.5", "+1e3", ".999"); nullopt for anything else.
std::optional<double> parseNumber(std::string_view s) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && (s.front() == '+' || s.front() == '-')) return std::nullopt;
  }
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

int dayOfLeapYear(int month, int day) {
  int d = day;
  for (int m = 1; m < month; ++m) d += kDaysInMonth[static_cast<std::size_t>(m - 1)];
  return d;
}

// Hours since 1 January 00:00 to the start of record hour `hour` (1..24) in a calendar with 29 February, the
// one slot per record hour used to check order and duplicates.
int leapSlot(int month, int day, int hour) {
  return (dayOfLeapYear(month, day) - 1) * 24 + (hour - 1);
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& fileName) : text_(text), fileName_(fileName) {}

  EpwFile parse() {
    if (text_.empty()) {
      throw InputError(
          {fileName_}, "the weather file is empty (0 bytes)",
          "the file was probably truncated while copying or saving; download or export it again");
    }
    // A UTF-8 byte order mark is not part of the first header line.
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
    checkText();
    splitLines();

    EpwFile file;
    file.fileName = fileName_;
    for (int i = 0; i < kHeaderLineCount; ++i) {
      if (static_cast<std::size_t>(i) >= lines_.size()) {
        throw InputError(
            {fileName_, static_cast<int>(lines_.size())},
            "the file ends after " + std::to_string(lines_.size()) + " lines, inside the 8 header lines",
            std::string(kHeaderOrderHint) + "; " + std::string(kTruncatedHint));
      }
      checkHeaderKeyword(lines_[static_cast<std::size_t>(i)], i);
    }
    file.location = parseLocation(lines_[0]);
    const DataPeriod period = parseDataPeriod(lines_[kHeaderLineCount - 1]);

    std::vector<int> lineOfSlot(kHoursInLeapYear, 0);
    for (std::size_t i = kHeaderLineCount; i < lines_.size(); ++i) {
      const Line& line = lines_[i];
      if (trim(line.text).empty()) {
        if (isBlankToEnd(i)) break;
        throw InputError({fileName_, line.number}, "empty line among the hourly records",
                         "remove the empty line; " + std::string(kRecordHint));
      }
      EpwRecord r = parseRecord(line);
      const int slot = leapSlot(r.month, r.day, r.hour);
      if (const int first = lineOfSlot[static_cast<std::size_t>(slot)]; first != 0) {
        throw InputError({fileName_, line.number},
                         "the record for " + recordText(r.month, r.day, r.hour) +
                             " repeats the one on line " + std::to_string(first) +
                             "; fly reads one year of hourly records",
                         "cut the file to one year");
      }
      lineOfSlot[static_cast<std::size_t>(slot)] = line.number;
      if (!file.records.empty()) checkFollows(file.records.back(), r);
      file.hasLeapDay = file.hasLeapDay || (r.month == 2 && r.day == 29);
      file.records.push_back(std::move(r));
    }
    checkAgainstDataPeriod(file, period);
    return file;
  }

 private:
  struct DataPeriod {
    int lineNumber = 0;
    // Start and end day as month/day; 0 where the file writes another form of date (a day of the year, a
    // month name), which is then not compared with the records.
    int startMonth = 0, startDay = 0, endMonth = 0, endDay = 0;
  };

  [[noreturn]] void fail(const Line& line, int column, const std::string& message,
                         std::string_view hint) const {
    throw InputError({fileName_, line.number, column}, message, std::string(hint));
  }

  // Rejects bytes that do not occur in a text file (control characters other than tab, CR and LF), so that a
  // binary file given by mistake gets one clear message. Bytes ≥ 0x80 pass: city names may be UTF-8 or
  // Latin-1.
  void checkText() const {
    int line = 1, column = 1;
    for (const char ch : text_) {
      const auto c = static_cast<unsigned char>(ch);
      if (c == '\n') {
        ++line;
        column = 1;
        continue;
      }
      if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "0x%02X", static_cast<unsigned>(c));
        throw InputError(
            {fileName_, line, column}, std::string("not a text file: it contains the byte ") + buf,
            "an EPW weather file is comma-separated text; give the .epw file itself, not a .zip, "
            ".wea or .ddy");
      }
      ++column;
    }
  }

  void splitLines() {
    std::size_t start = 0;
    int number = 1;
    while (start < text_.size()) {
      const std::size_t end = text_.find('\n', start);
      if (end == std::string_view::npos) {
        lines_.push_back({text_.substr(start), number, false});
        break;
      }
      lines_.push_back({text_.substr(start, end - start), number, true});
      start = end + 1;
      ++number;
    }
  }

  bool isBlankToEnd(std::size_t from) const {
    for (std::size_t i = from; i < lines_.size(); ++i) {
      if (!trim(lines_[i].text).empty()) return false;
    }
    return true;
  }

  static std::vector<Field> splitFields(std::string_view text) {
    std::vector<Field> fields;
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = text.find(',', start);
      const std::string_view raw =
          text.substr(start, comma == std::string_view::npos ? text.npos : comma - start);
      const std::string_view t = trim(raw);
      const std::size_t offset = start + static_cast<std::size_t>(t.data() - raw.data());
      fields.push_back({t, static_cast<int>(offset) + 1});
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    return fields;
  }

  void checkHeaderKeyword(const Line& line, int index) const {
    const std::string_view keyword = splitFields(line.text).front().text;
    const std::string_view expected = kHeaderKeywords[static_cast<std::size_t>(index)];
    const bool ok = equalsNoCase(keyword, expected) || (expected == "HOLIDAYS/DAYLIGHT SAVINGS" &&
                                                        equalsNoCase(keyword, "HOLIDAYS/DAYLIGHT SAVING"));
    if (ok) return;
    std::string message =
        "expected the " + std::string(expected) + " header line, found " + quoted(trim(line.text));
    if (index == 0) message += " (the LOCATION line is missing)";
    fail(line, 1, message, kHeaderOrderHint);
  }

  // Field `i` of a header line as a number in [lo, hi] (hiOpen: < hi).
  double headerNumber(const Line& line, const std::vector<Field>& f, std::size_t i, std::string_view name,
                      double lo, double hi, bool hiOpen, std::string_view hint) const {
    const std::optional<double> v = parseNumber(f[i].text);
    if (!v) {
      fail(line, f[i].column, std::string(name) + " " + quoted(f[i].text) + " is not a number", hint);
    }
    if (*v < lo || (hiOpen ? *v >= hi : *v > hi)) {
      fail(line, f[i].column,
           std::string(name) + " " + fmt(*v) + " is outside [" + fmt(lo) + ", " + fmt(hi) +
               (hiOpen ? ")" : "]"),
           hint);
    }
    return *v;
  }

  EpwLocation parseLocation(const Line& line) const {
    const std::vector<Field> f = splitFields(line.text);
    if (f.size() != 10) {
      fail(line, 1, "the LOCATION line has " + std::to_string(f.size()) + " fields, expected 10",
           "LOCATION, city, state/province/region, country, source, WMO number, latitude, longitude, time "
           "zone, "
           "elevation");
    }
    EpwLocation loc;
    loc.city = f[1].text;
    loc.stateProvinceRegion = f[2].text;
    loc.country = f[3].text;
    loc.source = f[4].text;
    loc.wmo = f[5].text;
    loc.latitudeDeg =
        headerNumber(line, f, 6, "latitude", -90.0, 90.0, false, "degrees north; south is negative");
    loc.longitudeDeg =
        headerNumber(line, f, 7, "longitude", -180.0, 180.0, false, "degrees east; west is negative");
    // The dictionary's maximum is +12, but standard time reaches UTC+14 (Line Islands).
    loc.timeZoneHours = headerNumber(line, f, 8, "time zone", -12.0, 14.0, false,
                                     "hours of standard time from UTC (Helsinki: 2, New York: -5)");
    loc.elevationM = headerNumber(line, f, 9, "elevation", -1000.0, 9999.9, true, "metres above sea level");
    return loc;
  }

  // "M/D" or "M/D/Y" (spaces allowed: the Weather Converter writes " 1/ 1") into month and day; other date
  // forms of the dictionary leave them 0.
  static void parseMonthDay(std::string_view s, int& month, int& day) {
    const std::size_t slash = s.find('/');
    if (slash == std::string_view::npos) return;
    std::string_view rest = s.substr(slash + 1);
    rest = rest.substr(0, rest.find('/'));
    const std::optional<double> m = parseNumber(trim(s.substr(0, slash)));
    const std::optional<double> d = parseNumber(trim(rest));
    if (!m || !d || *m != std::floor(*m) || *d != std::floor(*d) || *m < 1 || *m > 12 || *d < 1 ||
        *d > kDaysInMonth[static_cast<std::size_t>(*m) - 1]) {
      return;
    }
    month = static_cast<int>(*m);
    day = static_cast<int>(*d);
  }

  DataPeriod parseDataPeriod(const Line& line) const {
    const std::vector<Field> f = splitFields(line.text);
    if (f.size() < 7) {
      fail(line, 1, "the DATA PERIODS line has " + std::to_string(f.size()) + " fields, expected 7",
           "DATA PERIODS, number of periods, records per hour, name, start weekday, start day, end day");
    }
    const std::optional<double> periods = parseNumber(f[1].text);
    if (!periods || *periods != 1.0) {
      fail(line, f[1].column, "the file has " + quoted(f[1].text) + " data periods; fly reads files with one",
           "convert the file to a single data period with the EnergyPlus Weather Converter");
    }
    const std::optional<double> perHour = parseNumber(f[2].text);
    if (!perHour || *perHour != 1.0) {
      fail(line, f[2].column,
           "the file has " + quoted(f[2].text) + " records per hour; fly reads hourly files (1 per hour)",
           "convert the file to hourly records with the EnergyPlus Weather Converter");
    }
    DataPeriod p;
    p.lineNumber = line.number;
    parseMonthDay(f[5].text, p.startMonth, p.startDay);
    parseMonthDay(f[6].text, p.endMonth, p.endDay);
    return p;
  }

  // "field 7 (dry bulb temperature)"
  static std::string fieldName(std::size_t index) {
    return "field " + std::to_string(index + 1) + " (" + std::string(kFieldNames[index]) + ")";
  }

  // An integer field of a record within [lo, hi].
  int recordInteger(const Line& line, const Field& f, std::size_t index, int lo, int hi,
                    std::string_view hint) const {
    const std::optional<double> v = parseNumber(f.text);
    if (!v) fail(line, f.column, fieldName(index) + " is " + quoted(f.text) + ", not a number", kRecordHint);
    if (*v != std::floor(*v) || *v < lo || *v > hi) {
      fail(line, f.column,
           fieldName(index) + " is " + fmt(*v) + ", not a whole number in " + std::to_string(lo) + ".." +
               std::to_string(hi),
           hint);
    }
    return static_cast<int>(*v);
  }

  void readValue(const Line& line, const std::vector<Field>& f, const ValueField& vf, EpwRecord& r) const {
    const Field& field = f[vf.index];
    if (field.text.empty()) return;  // a blank measurement is missing
    const std::optional<double> v = parseNumber(field.text);
    if (!v) {
      fail(line, field.column, fieldName(vf.index) + " is " + quoted(field.text) + ", not a number",
           kRecordHint);
    }
    if (*v >= vf.missingFrom) return;
    if (vf.nonNegative && *v < 0.0) {
      fail(line, field.column, fieldName(vf.index) + " is " + fmt(*v) + "; it cannot be negative",
           "write the missing-value code " + fmt(vf.missingFrom) + " for a value that was not measured");
    }
    r.*vf.member = *v;
  }

  EpwRecord parseRecord(const Line& line) const {
    const std::vector<Field> f = splitFields(line.text);
    if (f.size() != kFieldCount) {
      if (!line.terminated && f.size() < kFieldCount) {
        fail(line, static_cast<int>(line.text.size()) + 1,
             "the file ends in the middle of a record (" + std::to_string(f.size()) + " of 35 fields)",
             kTruncatedHint);
      }
      fail(line, f.size() > kFieldCount ? f[kFieldCount].column : 1,
           "the record has " + std::to_string(f.size()) + " fields, expected 35", kRecordHint);
    }
    EpwRecord r;
    r.lineNumber = line.number;
    r.year = recordInteger(line, f[0], 0, std::numeric_limits<int>::min(), std::numeric_limits<int>::max(),
                           kRecordHint);
    r.month = recordInteger(line, f[1], 1, 1, 12, "months are 1..12");
    r.day = recordInteger(line, f[2], 2, 1, kDaysInMonth[static_cast<std::size_t>(r.month - 1)],
                          "month " + std::to_string(r.month) + " has " +
                              std::to_string(kDaysInMonth[static_cast<std::size_t>(r.month - 1)]) + " days");
    r.hour = recordInteger(line, f[3], 3, 1, 24,
                           "EPW hours are 1..24: hour 1 is the hour ending at 01:00 local standard time");
    r.minute = recordInteger(line, f[4], 4, 0, 60, "minutes are 0..60");
    r.dataSourceFlags = f[kFlagsField].text;
    r.presentWeatherCodes = f[kWeatherCodesField].text;
    for (const ValueField& vf : kValueFields) readValue(line, f, vf, r);
    return r;
  }

  // `next` must be the hour after `prev`: the next hour of the day, the first of the next day (29 February
  // optional), or 1 January after 31 December.
  void checkFollows(const EpwRecord& prev, const EpwRecord& next) const {
    const int step = leapSlot(next.month, next.day, next.hour) - leapSlot(prev.month, prev.day, prev.hour);
    const bool skipsLeapDay = prev.month == 2 && prev.day == 28 && prev.hour == 24 && next.month == 3 &&
                              next.day == 1 && next.hour == 1;
    const bool newYear = step == 1 - kHoursInLeapYear;
    if (step == 1 || skipsLeapDay || newYear) return;
    const Line& line = lines_[static_cast<std::size_t>(next.lineNumber - 1)];
    fail(line, 1,
         "the record for " + recordText(next.month, next.day, next.hour) +
             " does not follow the one on line " + std::to_string(prev.lineNumber) + " (" +
             recordText(prev.month, prev.day, prev.hour) + "): the hours must be consecutive",
         "the file has a gap or is out of order; fill the gap with missing-value codes");
  }

  void checkAgainstDataPeriod(const EpwFile& file, const DataPeriod& p) const {
    if (file.records.empty()) {
      throw InputError({fileName_, static_cast<int>(lines_.size())},
                       "the file has no hourly records after its 8 header lines", kTruncatedHint);
    }
    const EpwRecord& first = file.records.front();
    const EpwRecord& last = file.records.back();
    if (p.startMonth != 0 && (first.month != p.startMonth || first.day != p.startDay || first.hour != 1)) {
      throw InputError({fileName_, first.lineNumber},
                       "the first record is for " + recordText(first.month, first.day, first.hour) +
                           ", but the DATA PERIODS line (line " + std::to_string(p.lineNumber) +
                           ") says the data start on " + dateText(p.startMonth, p.startDay) + " hour 1",
                       "correct the DATA PERIODS line or restore the missing records");
    }
    if (p.endMonth != 0 && (last.month != p.endMonth || last.day != p.endDay || last.hour != 24)) {
      throw InputError({fileName_, last.lineNumber},
                       "the records end at " + recordText(last.month, last.day, last.hour) +
                           ", but the DATA PERIODS line (line " + std::to_string(p.lineNumber) +
                           ") says they run to " + dateText(p.endMonth, p.endDay) + " hour 24",
                       kTruncatedHint);
    }
  }

  std::string_view text_;
  const std::string& fileName_;
  std::vector<Line> lines_;
};

std::optional<double> lerp(const std::optional<double>& a, const std::optional<double>& b, double w) {
  if (w == 0.0) return a;
  if (!a || !b) return std::nullopt;
  return *a + w * (*b - *a);
}

std::string clockText(double hour) {
  const double minutes = std::round(hour * 60.0);
  char buf[16];
  std::snprintf(buf, sizeof buf, "%d:%02d", static_cast<int>(minutes / 60.0),
                static_cast<int>(std::fmod(minutes, 60.0)));
  return buf;
}

}  // namespace

EpwFile parseEpw(std::string_view text, const std::string& fileName) {
  return Parser(text, fileName).parse();
}

EpwFile loadEpw(const std::filesystem::path& path) {
  return parseEpw(readInputFile(path, "weather file"), path.string());
}

EpwSample sampleAt(const EpwFile& file, int month, int day, double localStandardHour) {
  const SourceLocation where{file.fileName};
  if (month < 1 || month > 12) {
    throw InputError(where, "month " + std::to_string(month) + " does not exist", "months are 1..12");
  }
  const int daysInMonth =
      (month == 2 && !file.hasLeapDay) ? 28 : kDaysInMonth[static_cast<std::size_t>(month - 1)];
  if (day < 1 || day > daysInMonth) {
    throw InputError(where, "day " + dateText(month, day) + " is not in the weather file's year",
                     month == 2 && day == 29 ? "the file has no 29 February; use 28 February or 1 March"
                                             : "month " + std::to_string(month) + " has " +
                                                   std::to_string(daysInMonth) + " days");
  }
  if (!(localStandardHour >= 0.0 && localStandardHour <= 24.0)) {
    throw InputError(where, "hour " + fmt(localStandardHour) + " is outside [0, 24]",
                     "give the local standard time of day in hours");
  }
  if (file.records.empty()) throw InputError(where, "the weather file has no hourly records");

  // Hours since 1 January 00:00 in the file's calendar; record r covers [slot(r), slot(r) + 1).
  const int yearHours = file.hasLeapDay ? kHoursInLeapYear : kHoursInLeapYear - 24;
  const auto slotOf = [&](int m, int d) {
    int doy = dayOfLeapYear(m, d);
    if (!file.hasLeapDay && m > 2) --doy;
    return (doy - 1) * 24;
  };
  const EpwRecord& first = file.records.front();
  const int firstSlot = slotOf(first.month, first.day) + first.hour - 1;
  const auto count = static_cast<int>(file.records.size());
  const auto wrap = [&](double hours) { return hours - yearHours * std::floor(hours / yearHours); };

  // The instant in hours after the start of the first record, and the mid-point before it.
  const double sinceFirst = wrap(slotOf(month, day) + localStandardHour - firstSlot);
  if (count < yearHours && sinceFirst > count) {
    const EpwRecord& last = file.records.back();
    throw InputError(where,
                     "the weather file covers " + dateText(first.month, first.day) + " " +
                         clockText(first.hour - 1.0) + " to " + dateText(last.month, last.day) + " " +
                         clockText(last.hour) + " local standard time; " + dateText(month, day) + " " +
                         clockText(localStandardHour) + " is outside it",
                     "choose a time inside the file's data, or use a full-year weather file");
  }
  const double before = std::floor(sinceFirst - 0.5);  // offset of the record whose mid-point precedes
  double w = sinceFirst - 0.5 - before;
  auto i0 = static_cast<int>(before);
  int i1 = i0 + 1;
  if (count == yearHours) {
    i0 = (i0 + yearHours) % yearHours;
    i1 %= yearHours;
  } else if (i0 < 0) {  // the first half hour of a part-year file
    i0 = i1;
    w = 0.0;
  } else if (i1 >= count) {  // its last half hour
    w = 0.0;
  }
  if (w == 0.0) i1 = i0;

  const EpwRecord& a = file.records[static_cast<std::size_t>(i0)];
  const EpwRecord& b = file.records[static_cast<std::size_t>(i1)];
  EpwSample s;
  s.recordBefore = static_cast<std::size_t>(i0);
  s.recordAfter = static_cast<std::size_t>(i1);
  s.weightAfter = w;
  s.dryBulbC = lerp(a.dryBulbC, b.dryBulbC, w);
  s.dewPointC = lerp(a.dewPointC, b.dewPointC, w);
  s.pressurePa = lerp(a.pressurePa, b.pressurePa, w);
  s.ghiWm2 = lerp(a.ghiWm2, b.ghiWm2, w);
  s.dniWm2 = lerp(a.dniWm2, b.dniWm2, w);
  s.dhiWm2 = lerp(a.dhiWm2, b.dhiWm2, w);
  s.ghiLux = lerp(a.ghiLux, b.ghiLux, w);
  s.dniLux = lerp(a.dniLux, b.dniLux, w);
  s.dhiLux = lerp(a.dhiLux, b.dhiLux, w);
  s.zenithLuminanceCdM2 = lerp(a.zenithLuminanceCdM2, b.zenithLuminanceCdM2, w);
  s.albedo = lerp(a.albedo, b.albedo, w);
  return s;
}

EpwSample sampleAtUtc(const EpwFile& file, const UtcTime& utc) {
  const UtcTime local = addHours(utc, file.location.timeZoneHours);
  return sampleAt(file, local.month, local.day, local.hour + local.minute / 60.0 + local.second / 3600.0);
}

}  // namespace fly::sunsky
