#include "sdb/scene_file.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cassert>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <type_traits>

#include "base/blackbody.h"
#include "base/error.h"
#include "base/file_io.h"
#include "base/json_value.h"
#include "sdb/eulumdat.h"
#include "sdb/gltf_import.h"
#include "sdb/ies.h"
#include "sdb/material_presets.h"

namespace fly::sdb {
namespace {

namespace fs = std::filesystem;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kFormatVersion = 1;

// --- Text helpers ----------------------------------------------------------------------------------------

std::string formatNumber(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : "?";
}

std::string inQuotes(std::string_view s) {
  return "\"" + std::string(s) + "\"";
}

// "a, b, c", the first `limit` names and then how many more there are.
std::string joinNames(std::span<const std::string> names, size_t limit = 30) {
  std::string s;
  for (size_t i = 0; i < names.size() && i < limit; ++i) s += (i ? ", " : "") + names[i];
  if (names.size() > limit) s += " … and " + std::to_string(names.size() - limit) + " more";
  return s;
}

// Optimal-string-alignment distance (a transposition counts as one edit), ignoring case.
size_t editDistance(std::string_view a, std::string_view b) {
  const auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1])) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

// "did you mean "x"?" for the closest candidate when it is a plausible misspelling of `given` (at most a
// third of its letters wrong, at least one, at most three), else the candidates that contain `given` ("glass"
// → "clear-glass", "frosted-glass"); "" when there are neither.
std::string didYouMean(std::string_view given, std::span<const std::string> candidates) {
  const size_t allowed = std::clamp<size_t>(given.size() / 3, 1, 3);
  const std::string* best = nullptr;
  size_t bestDistance = allowed + 1;
  for (const std::string& c : candidates) {
    const size_t d = editDistance(given, c);
    if (d < bestDistance) {
      bestDistance = d;
      best = &c;
    }
  }
  if (best) return "did you mean " + inQuotes(*best) + "?";
  std::vector<std::string> containing;
  for (const std::string& c : candidates) {
    if (!given.empty() && c.find(given) != std::string::npos) containing.push_back(inQuotes(c));
  }
  if (containing.empty()) return "";
  return containing.size() == 1 ? "did you mean " + containing[0] + "?"
                                : "did you mean one of " + joinNames(containing, 5) + "?";
}

// A closed, open or half-open interval of allowed numbers.
struct Range {
  double min = -kInf;
  double max = kInf;
  bool minOpen = false;
  bool maxOpen = false;

  bool contains(double v) const { return (minOpen ? v > min : v >= min) && (maxOpen ? v < max : v <= max); }
  // "[-90, 90]", "(0, 1)", "(0, 1000]", "≥ 0", "> 0"; "" for all numbers.
  std::string str() const {
    if (min == -kInf && max == kInf) return "";
    if (max == kInf) return (minOpen ? "> " : "≥ ") + formatNumber(min);
    if (min == -kInf) return (maxOpen ? "< " : "≤ ") + formatNumber(max);
    return (minOpen ? "(" : "[") + formatNumber(min) + ", " + formatNumber(max) + (maxOpen ? ")" : "]");
  }
};
Range closed(double lo, double hi) {
  return {lo, hi, false, false};
}
Range exclusive(double lo, double hi) {
  return {lo, hi, true, true};
}
Range leftOpen(double lo, double hi) {
  return {lo, hi, true, false};
}
Range atLeast(double lo) {
  return {lo, kInf, false, false};
}
Range above(double lo) {
  return {lo, kInf, true, false};
}
Range anyNumber() {
  return {};
}

// --- Typed reading of JSON values --------------------------------------------------------------------------

// "95", "a string (\"60\")", "an array of 2 elements", "an object", for "...; got ...".
std::string describeValue(const JsonValue& v) {
  if (v.isNumber()) return formatNumber(v.number());
  if (v.isArray()) {
    const size_t n = v.elements().size();
    return "an array of " + std::to_string(n) + (n == 1 ? " element" : " elements");
  }
  if (v.isString() && v.string().size() <= 60) return "a string (" + inQuotes(v.string()) + ")";
  return v.describe();
}

// The document being read and where its relative paths start. Every check throws InputError at the value.
class Source {
 public:
  Source(const JsonDocument& doc, fs::path baseDir) : doc_(doc), baseDir_(std::move(baseDir)) {}

  [[noreturn]] void fail(const JsonValue& at, const std::string& message, std::string hint = {}) const {
    throw InputError(doc_.locationOf(at), message, std::move(hint));
  }
  [[noreturn]] void fail(const JsonMember& key, const std::string& message, std::string hint = {}) const {
    throw InputError(doc_.locationOf(key), message, std::move(hint));
  }

  // A number within `range`; `unit` ("degrees", "metres") names it in the message.
  double number(const JsonValue& v, Range range, std::string_view unit) const {
    if (!v.isNumber() || !range.contains(v.number())) {
      std::string expected = "a number";
      if (!unit.empty()) expected += " in " + std::string(unit);
      if (const std::string r = range.str(); !r.empty()) expected += ", " + r;
      fail(v, "expected " + expected + "; got " + describeValue(v));
    }
    return v.number();
  }

  // As number(), for quantities stored in single precision: beyond ±3.4e38 is an error, not infinity.
  float floatNumber(const JsonValue& v, Range range, std::string_view unit) const {
    const double x = number(v, range, unit);
    if (std::abs(x) > std::numeric_limits<float>::max()) {
      fail(v, "the number " + formatNumber(x) + " is too large (single precision reaches about 3.4e38)");
    }
    return static_cast<float>(x);
  }

  // A whole number in [lo, hi]; 8 and 8.0 are both accepted.
  int64_t integer(const JsonValue& v, int64_t lo, int64_t hi, std::string_view unit = {}) const {
    const bool whole =
        v.isInteger() || (v.isNumber() && std::trunc(v.number()) == v.number() &&
                          std::abs(v.number()) <= 9007199254740992.0);  // 2^53: exact in a double
    const int64_t n = v.isInteger() ? v.integer() : whole ? static_cast<int64_t>(v.number()) : 0;
    if (!whole || n < lo || n > hi) {
      std::string expected = "an integer";
      if (!unit.empty()) expected += " (" + std::string(unit) + ")";
      fail(v, "expected " + expected + ", [" + std::to_string(lo) + ", " + std::to_string(hi) + "]; got " +
                  describeValue(v));
    }
    return n;
  }

  bool boolean(const JsonValue& v) const {
    if (!v.isBool()) fail(v, "expected true or false; got " + describeValue(v));
    return v.boolean();
  }

  // A non-empty string; `what` says what it names ("a glTF file's path").
  const std::string& string(const JsonValue& v, std::string_view what) const {
    if (!v.isString() || v.string().empty()) {
      fail(v, "expected " + std::string(what) + " as a non-empty string; got " + describeValue(v));
    }
    return v.string();
  }

  // The index of the string among `options`.
  size_t choice(const JsonValue& v, std::span<const std::string> options) const {
    if (v.isString()) {
      const auto it = std::find(options.begin(), options.end(), v.string());
      if (it != options.end()) return static_cast<size_t>(it - options.begin());
    }
    std::string list;
    for (const std::string& o : options) list += (list.empty() ? "" : ", ") + inQuotes(o);
    fail(v, "expected one of " + list + "; got " + describeValue(v),
         v.isString() ? didYouMean(v.string(), options) : std::string());
  }

  // Three numbers [x, y, z], each finite in single precision.
  vec3 vector3(const JsonValue& v, std::string_view unit, Range each = anyNumber()) const {
    if (!v.isArray() || v.elements().size() != 3) {
      fail(v, "expected an array of 3 numbers [x, y, z]" + (unit.empty() ? "" : " in " + std::string(unit)) +
                  "; got " + describeValue(v));
    }
    vec3 r;
    for (int i = 0; i < 3; ++i) r[i] = floatNumber(v.elements()[i], each, unit);
    return r;
  }

  // A direction [x, y, z], normalised (in double precision, so that large components cannot overflow).
  vec3 direction(const JsonValue& v) const {
    const dvec3 d(vector3(v, ""));
    const double length = glm::length(d);
    if (!(length > 0.0)) fail(v, "a direction must not be the zero vector");
    return vec3(d / length);
  }

  // A linear Rec.709 colour [r, g, b], each channel within `each`.
  Rgb colour(const JsonValue& v, Range each, std::string_view unit = {}) const {
    if (!v.isArray() || v.elements().size() != 3) {
      std::string expected = "a colour [r, g, b] of 3 numbers";
      if (!unit.empty()) expected += " in " + std::string(unit);
      fail(v, "expected " + expected + ", each " + each.str() + "; got " + describeValue(v));
    }
    Rgb c;
    for (int i = 0; i < 3; ++i) c[i] = floatNumber(v.elements()[i], each, unit);
    return c;
  }

  // An input file's path, relative to the scene file's folder unless absolute; it must exist. `what` names
  // the kind of file ("glTF file").
  fs::path inputFile(const JsonValue& v, std::string_view what) const {
    const fs::path given(string(v, "the " + std::string(what) + "'s path"));
    const fs::path path = given.is_absolute() ? given : baseDir_ / given;
    try {
      checkInputFile(path, what);
    } catch (const InputError& e) {
      // Point at the scene file's line; the message names the path as resolved.
      fail(v, e.message() + ": " + path.string(), e.hint());
    }
    return path;
  }

 private:
  const JsonDocument& doc_;
  fs::path baseDir_;
};

// An object whose keys are all known in advance: any other key is an error at once, with the allowed keys and
// the nearest one. Getters return nullopt for an absent key.
class ObjectReader {
 public:
  ObjectReader(const Source& src, const JsonValue& object, std::vector<std::string> keys)
      : src_(src), object_(object), keys_(std::move(keys)) {
    if (!object.isObject()) {
      src.fail(object,
               "expected an object with the keys " + joinNames(keys_) + "; got " + describeValue(object));
    }
    for (const JsonMember& m : object.members()) {
      if (std::find(keys_.begin(), keys_.end(), m.key) == keys_.end()) {
        const std::string where = object.path().empty() ? "at the top level" : "in " + object.path();
        std::string hint = didYouMean(m.key, keys_);
        if (hint.empty()) hint = "keys are case-sensitive; docs/scene-format.md lists them all";
        src.fail(m, "unknown key " + inQuotes(m.key) + " " + where + "; expected one of: " + joinNames(keys_),
                 hint);
      }
    }
  }

  const JsonValue* find(std::string_view key) const {
    assert(std::find(keys_.begin(), keys_.end(), key) != keys_.end() && "key missing from the reader's list");
    const JsonMember* m = object_.find(key);
    return m ? &m->value : nullptr;
  }

  // The value of a key that must be there; `what` describes it in the message.
  const JsonValue& require(std::string_view key, std::string_view what) const {
    const JsonValue* v = find(key);
    if (!v) src_.fail(object_, "missing key " + inQuotes(key) + " (" + std::string(what) + ")");
    return *v;
  }

  // An error unless the key is absent: it does not apply here, and `why` says so.
  void forbid(std::string_view key, const std::string& why) const {
    if (const JsonMember* m = object_.find(key)) src_.fail(*m, "key " + inQuotes(key) + " " + why);
  }

  std::optional<double> number(std::string_view key, Range range, std::string_view unit) const {
    return read(key, [&](const JsonValue& v) { return src_.number(v, range, unit); });
  }
  std::optional<float> floatNumber(std::string_view key, Range range, std::string_view unit) const {
    return read(key, [&](const JsonValue& v) { return src_.floatNumber(v, range, unit); });
  }
  std::optional<int64_t> integer(std::string_view key, int64_t lo, int64_t hi,
                                 std::string_view unit = {}) const {
    return read(key, [&](const JsonValue& v) { return src_.integer(v, lo, hi, unit); });
  }
  std::optional<bool> boolean(std::string_view key) const {
    return read(key, [&](const JsonValue& v) { return src_.boolean(v); });
  }
  std::optional<std::string> string(std::string_view key, std::string_view what) const {
    return read(key, [&](const JsonValue& v) { return src_.string(v, what); });
  }
  std::optional<size_t> choice(std::string_view key, std::span<const std::string> options) const {
    return read(key, [&](const JsonValue& v) { return src_.choice(v, options); });
  }
  std::optional<vec3> vector3(std::string_view key, std::string_view unit, Range each = anyNumber()) const {
    return read(key, [&](const JsonValue& v) { return src_.vector3(v, unit, each); });
  }
  std::optional<Rgb> colour(std::string_view key, Range each, std::string_view unit = {}) const {
    return read(key, [&](const JsonValue& v) { return src_.colour(v, each, unit); });
  }
  std::optional<fs::path> inputFile(std::string_view key, std::string_view what) const {
    return read(key, [&](const JsonValue& v) { return src_.inputFile(v, what); });
  }

 private:
  template <class F>
  auto read(std::string_view key, F f) const
      -> std::optional<std::decay_t<std::invoke_result_t<F, const JsonValue&>>> {
    const JsonValue* v = find(key);
    if (!v) return std::nullopt;
    return f(*v);
  }

  const Source& src_;
  const JsonValue& object_;
  std::vector<std::string> keys_;
};

// An array (absent = empty); anything else is an error naming what its elements are.
std::span<const JsonValue> arrayOf(const Source& src, const JsonValue* v, std::string_view elements) {
  if (!v) return {};
  if (!v->isArray())
    src.fail(*v, "expected an array of " + std::string(elements) + "; got " + describeValue(*v));
  return v->elements();
}

// --- Names -------------------------------------------------------------------------------------------------

// A scene-file name pattern: the exact name, or a prefix followed by '*'.
bool matchesPattern(std::string_view pattern, std::string_view name) {
  if (!pattern.empty() && pattern.back() == '*')
    return name.starts_with(pattern.substr(0, pattern.size() - 1));
  return name == pattern;
}

// Sorted distinct names of the entities in `map`, for "materials in the scene: ...".
template <class Map>
std::vector<std::string> namesOf(const Map& map) {
  std::set<std::string> names;
  for (const auto& [id, entity] : map) names.insert(entity.name);
  return {names.begin(), names.end()};
}

// --- Date and time -----------------------------------------------------------------------------------------

bool isLeapYear(int y) {
  return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
}

int daysInMonth(int year, int month) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return month == 2 && isLeapYear(year) ? 29 : kDays[month - 1];
}

const char* const kMonthNames[12] = {"January", "February", "March",     "April",   "May",      "June",
                                     "July",    "August",   "September", "October", "November", "December"};

// Checks an ISO 8601 local date-time "YYYY-MM-DDThh:mm" or "YYYY-MM-DDThh:mm:ss"; returns "" when valid,
// otherwise what is wrong. Seconds go to 60 for a leap second.
std::string checkLocalDateTime(std::string_view s, std::string* hint) {
  const auto digits = [&](size_t at, size_t n, int& out) {
    if (at + n > s.size()) return false;
    out = 0;
    for (size_t i = at; i < at + n; ++i) {
      if (s[i] < '0' || s[i] > '9') return false;
      out = out * 10 + (s[i] - '0');
    }
    return true;
  };
  int year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0;
  const bool dateTime = digits(0, 4, year) && s.size() > 4 && s[4] == '-' && digits(5, 2, month) &&
                        s.size() > 7 && s[7] == '-' && digits(8, 2, day) && s.size() > 10 && s[10] == 'T' &&
                        digits(11, 2, hour) && s.size() > 13 && s[13] == ':' && digits(14, 2, minute);
  const size_t length = dateTime && s.size() > 16 && s[16] == ':' && digits(17, 2, second) ? 19 : 16;
  if (!dateTime || s.size() != length) {
    const char next = dateTime && s.size() > length ? s[length] : '\0';
    if (next == 'Z' || next == '+' || next == '-') {
      *hint = "give the local time without a zone; the zone belongs in site.timeZone";
    } else if (next == '.') {
      *hint = "fractions of a second are not supported; round to whole seconds";
    } else {
      *hint = "write e.g. \"2026-06-21T12:00\" or \"2026-06-21T12:00:30\", with the 'T' and leading zeros";
    }
    return "expected a local date and time YYYY-MM-DDThh:mm[:ss]; got " + inQuotes(s);
  }
  if (month < 1 || month > 12) return "month " + std::to_string(month) + " is outside 1..12";
  if (day < 1 || day > daysInMonth(year, month)) {
    return "day " + std::to_string(day) + " is outside 1.." + std::to_string(daysInMonth(year, month)) +
           " for " + kMonthNames[month - 1] + " " + std::to_string(year);
  }
  if (hour > 23) {
    *hint = "midnight at the end of a day is 00:00 of the next day";
    return "hour " + std::to_string(hour) + " is outside 0..23";
  }
  if (minute > 59) return "minute " + std::to_string(minute) + " is outside 0..59";
  if (second > 60) return "second " + std::to_string(second) + " is outside 0..60";
  return "";
}

// "Z", a UTC offset "±hh:mm" (up to ±14:00) or an IANA zone name ("Europe/Helsinki", "UTC", "Etc/GMT+3").
// The name itself is checked against the zone database where the time is converted (sunsky/).
bool isTimeZoneForm(std::string_view z) {
  if (z == "Z") return true;
  if (z.size() == 6 && (z[0] == '+' || z[0] == '-') && z[3] == ':') {
    const auto d = [&](size_t i) { return z[i] >= '0' && z[i] <= '9'; };
    if (!(d(1) && d(2) && d(4) && d(5))) return false;
    const int hours = (z[1] - '0') * 10 + (z[2] - '0');
    const int minutes = (z[4] - '0') * 10 + (z[5] - '0');
    return minutes < 60 && hours * 60 + minutes <= 14 * 60;
  }
  if (z.empty() || !std::isalpha(static_cast<unsigned char>(z[0]))) return false;
  return std::all_of(z.begin(), z.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '/' || c == '_' || c == '-' || c == '+';
  });
}

// --- Bake values -------------------------------------------------------------------------------------------

// A duration "90s", "5m", "1.5h", "1h30m" in seconds; nullopt when malformed.
std::optional<double> parseDuration(std::string_view s) {
  double total = 0.0;
  size_t i = 0;
  if (s.empty()) return std::nullopt;
  while (i < s.size()) {
    double value = 0.0;
    const auto [end, ec] = std::from_chars(s.data() + i, s.data() + s.size(), value);
    if (ec != std::errc() || !(value >= 0.0)) return std::nullopt;
    i = static_cast<size_t>(end - s.data());
    if (i >= s.size()) return std::nullopt;
    const char unit = s[i++];
    if (unit == 's') {
      total += value;
    } else if (unit == 'm') {
      total += value * 60.0;
    } else if (unit == 'h') {
      total += value * 3600.0;
    } else {
      return std::nullopt;
    }
  }
  return std::isfinite(total) ? std::optional(total) : std::nullopt;
}

// --- Placement ---------------------------------------------------------------------------------------------

// parentFromLocal = T · Rz · Ry · Rx · S, angles in degrees about the parent's axes.
mat4 trsTransform(const vec3& translationM, const vec3& rotationDeg, const vec3& scale) {
  mat4 m = glm::translate(mat4(1.0f), translationM);
  m = glm::rotate(m, glm::radians(rotationDeg.z), vec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(rotationDeg.y), vec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(rotationDeg.x), vec3(1, 0, 0));
  return glm::scale(m, scale);
}

// Projections shorter than this (sin of ≈ 0.06°) leave no usable perpendicular direction.
constexpr float kMinPerpendicular = 1e-3f;

// The frame of a light at `positionM` shining along the unit vector `dir`: local −Z = dir, local +X = the
// part of `xHint` perpendicular to dir (normalised), local +Y = Z × X. `xHint` must not be parallel to dir.
mat4 lightFrame(const vec3& positionM, const vec3& dir, const vec3& xHint) {
  const vec3 z = -dir;
  const vec3 x = glm::normalize(xHint - glm::dot(xHint, z) * z);
  return frameTransform(x, glm::cross(z, x), z, positionM);
}

float perpendicularLength(const vec3& v, const vec3& unitDir) {
  return glm::length(v - glm::dot(v, unitDir) * unitDir);
}

// Goniometric files are told apart by their extension: .ldt (in any case) is EULUMDAT, anything else IES LM-63.
bool isEulumdatPath(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".ldt";
}

// --- The scene file ----------------------------------------------------------------------------------------

const std::vector<std::string> kSkyModels = {"none", "cie", "perez", "clear", "preetham"};
const std::vector<std::string> kLightTypes = {"point", "spot", "directional", "ies"};

class SceneFileReader {
 public:
  SceneFileReader(const JsonDocument& doc, fs::path baseDir, Scene& scene)
      : doc_(doc), src_(doc, std::move(baseDir)), scene_(scene) {}

  void read() {
    const JsonValue& root = doc_.root;
    if (!root.isObject()) {
      src_.fail(root, "expected a JSON object at the top level; got " + describeValue(root),
                "a scene file looks like { \"fly\": 1, \"models\": [...] }");
    }
    readVersion(root);
    const ObjectReader top(
        src_, root,
        {"fly", "models", "site", "time", "sky", "lights", "overrides", "bake", "cameras", "portals"});
    // Models first: overrides and bake settings refer to the names they bring.
    readModels(top.find("models"));
    readSiteTimeAndSky(top);
    readLights(top.find("lights"));
    readOverrides(top.find("overrides"));
    if (const JsonValue* bake = top.find("bake")) readBake(*bake);
    readCameras(top.find("cameras"));
    readPortals(top.find("portals"));
  }

 private:
  void readVersion(const JsonValue& root) {
    const JsonMember* fly = root.find("fly");
    if (!fly) {
      src_.fail(root, "missing key \"fly\" (the scene-file format version)",
                "begin the file with { \"fly\": " + std::to_string(kFormatVersion) + ", ...");
    }
    const JsonValue& v = fly->value;
    if (!v.isInteger()) src_.fail(v, "expected the format version as an integer; got " + describeValue(v));
    if (v.integer() != kFormatVersion) {
      src_.fail(v,
                "unsupported scene-file version " + std::to_string(v.integer()) +
                    "; this fly reads version " + std::to_string(kFormatVersion),
                "use the fly release that wrote the file, or convert it to version 1 (docs/scene-format.md)");
    }
  }

  // --- models

  void readModels(const JsonValue* models) {
    for (const JsonValue& m : arrayOf(src_, models, "models { \"file\": ... }")) readModel(m);
  }

  void readModel(const JsonValue& v) {
    const ObjectReader r(src_, v, {"file", "name", "namePrefix", "translation", "rotationDeg", "scale"});
    const fs::path file = src_.inputFile(r.require("file", "the glTF file to place"), "glTF file");
    const std::string name = r.string("name", "the model's name").value_or(file.stem().string());
    vec3 scale(1.0f);
    if (const JsonValue* s = r.find("scale")) {
      // Negative factors mirror the model; the importer then reverses the winding of its triangles.
      scale = s->isArray() ? src_.vector3(*s, "") : vec3(src_.floatNumber(*s, anyNumber(), ""));
      if (scale.x == 0.0f || scale.y == 0.0f || scale.z == 0.0f) {
        src_.fail(*s, "a scale factor of 0 flattens the model",
                  "give non-zero factors; 1 keeps the model's size");
      }
    }
    Node node;
    node.name = name;
    node.parentFromLocal = trsTransform(r.vector3("translation", "metres").value_or(vec3(0.0f)),
                                        r.vector3("rotationDeg", "degrees").value_or(vec3(0.0f)), scale);
    const NodeId parent = scene_.addNode(std::move(node)).id;
    // InputErrors of the importer name the glTF file and the element; they pass through unchanged.
    importGltf(scene_, file,
               {.parent = parent, .namePrefix = r.string("namePrefix", "a name prefix").value_or("")});
  }

  // --- site, time, sky

  // "grid": "utm:35" (a UTM zone, 1..60) or "tm:27" (a transverse-Mercator grid by its central meridian in
  // degrees east, [-180, 180]).
  void readGrid(const JsonValue& g, Site& site) {
    const std::string& text = src_.string(g, "a map grid, \"utm:ZONE\" or \"tm:CENTRAL_MERIDIAN_DEG\"");
    const std::string hint = "write e.g. \"utm:35\" (UTM zone 35) or \"tm:27\" (ETRS-TM35FIN, central meridian 27° E)";
    const size_t colon = text.find(':');
    const std::string kind = text.substr(0, colon);
    const std::string value = colon == std::string::npos ? "" : text.substr(colon + 1);
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    const bool numeric = !value.empty() && end == value.c_str() + value.size() && std::isfinite(number);
    if (kind == "utm" && numeric && number == std::floor(number) && number >= 1 && number <= 60) {
      site.grid = Site::Grid::kUtm;
      site.utmZone = int(number);
    } else if (kind == "tm" && numeric && number >= -180 && number <= 180) {
      site.grid = Site::Grid::kTransverseMercator;
      site.gridCentralMeridianDeg = number;
    } else {
      src_.fail(g, "expected \"utm:ZONE\" (zone 1..60) or \"tm:DEGREES\" (central meridian, [-180, 180]); got " +
                       inQuotes(text), hint);
    }
  }

  void readSiteTimeAndSky(const ObjectReader& top) {
    const JsonValue* siteValue = top.find("site");
    bool hasTimeZone = false;
    if (siteValue) {
      const ObjectReader r(src_, *siteValue,
                           {"latitude", "longitude", "elevation", "timeZone", "northAngle", "grid"});
      Site site;
      site.latitudeDeg =
          src_.number(r.require("latitude", "degrees north, [-90, 90]"), closed(-90, 90), "degrees");
      site.longitudeDeg =
          src_.number(r.require("longitude", "degrees east, [-180, 180]"), closed(-180, 180), "degrees");
      site.elevationM = r.number("elevation", closed(-500, 9000), "metres").value_or(site.elevationM);
      if (const JsonValue* z = r.find("timeZone")) {
        site.timeZone = src_.string(*z, "a time zone");
        if (!isTimeZoneForm(site.timeZone)) {
          src_.fail(*z,
                    "expected an IANA time-zone name (\"Europe/Helsinki\") or a UTC offset (\"+03:00\", "
                    "\"Z\"); got " +
                        inQuotes(site.timeZone),
                    "write an offset with two-digit hours and minutes, e.g. \"-05:00\"");
        }
        hasTimeZone = true;
      }
      site.northAngleDeg = r.number("northAngle", closed(-360, 360), "degrees").value_or(site.northAngleDeg);
      if (const JsonValue* g = r.find("grid")) readGrid(*g, site);
      scene_.setSite(site);
    }

    const JsonValue* timeValue = top.find("time");
    if (timeValue) {
      const std::string& t = src_.string(*timeValue, "the local date and time");
      std::string hint;
      if (const std::string problem = checkLocalDateTime(t, &hint); !problem.empty()) {
        src_.fail(*timeValue, problem, hint);
      }
      if (!siteValue) {
        src_.fail(
            *timeValue, "a local time needs a site to be placed",
            "add \"site\": { \"latitude\": ..., \"longitude\": ..., \"timeZone\": \"Europe/Helsinki\" }");
      }
      if (!hasTimeZone) {
        src_.fail(*siteValue, "the site has no \"timeZone\", so the local time at /time cannot be placed",
                  "add e.g. \"timeZone\": \"Europe/Helsinki\" or \"timeZone\": \"+02:00\" to the site");
      }
      scene_.setTime({t});
    }

    if (const JsonValue* skyValue = top.find("sky")) readSky(*skyValue, siteValue && timeValue);
  }

  void readSky(const JsonValue& v, bool hasSiteAndTime) {
    const ObjectReader r(src_, v, {"model", "cieType", "turbidity", "weatherFile", "sun", "groundAlbedo"});
    SkySettings sky;
    sky.model = static_cast<SkyModel>(r.choice("model", kSkyModels).value_or(0));
    static_assert(static_cast<int>(SkyModel::kPreetham) == 4, "kSkyModels follows the order of SkyModel");
    sky.sun = r.boolean("sun").value_or(false);
    const std::string model = inQuotes(skyModelName(sky.model));
    if (sky.model == SkyModel::kCie) {
      sky.cieType =
          static_cast<int>(r.integer("cieType", 1, 15, "CIE standard sky type").value_or(sky.cieType));
    } else {
      r.forbid("cieType", "applies to the CIE sky only (\"model\": \"cie\"); this sky is " + model);
    }
    if (isClearSky(sky.model) || sky.sun) {
      sky.turbidity = r.number("turbidity", closed(1.7, 10), "Linke turbidity").value_or(sky.turbidity);
    } else {
      r.forbid("turbidity",
               "applies to the clear sky and the sun only; this sky is " + model + " without a sun");
    }
    sky.groundAlbedo =
        r.number("groundAlbedo", closed(0.0, 1.0), "ground reflectance").value_or(sky.groundAlbedo);
    if (sky.model == SkyModel::kPerez) {
      sky.weatherFile =
          src_.inputFile(r.require("weatherFile", "an EnergyPlus weather file, .epw"), "weather file")
              .string();
    } else {
      r.forbid("weatherFile", "applies to the Perez sky only (\"model\": \"perez\"); this sky is " + model);
    }
    if ((sky.model != SkyModel::kNone || sky.sun) && !hasSiteAndTime) {
      const JsonValue& at = sky.sun ? *r.find("sun") : *r.find("model");
      src_.fail(at,
                std::string(sky.sun ? "the sun" : "a " + model + " sky") + " needs a site and a local time",
                "add \"site\": { \"latitude\": ..., \"longitude\": ..., \"timeZone\": ... } and "
                "\"time\": \"2026-06-21T12:00\"");
    }
    scene_.setSky(sky);
  }

  // --- lights

  void readLights(const JsonValue* lights) {
    const std::span<const JsonValue> all = arrayOf(src_, lights, "lights { \"type\": ... }");
    for (size_t i = 0; i < all.size(); ++i) readLight(all[i], i);
  }

  void readLight(const JsonValue& v, size_t index) {
    const ObjectReader r(src_, v,
                         {"name", "type", "position", "direction", "c0Direction", "color", "temperatureK",
                          "intensity", "flux", "range", "innerConeDeg", "outerConeDeg", "file"});
    Light light;
    light.name = r.string("name", "the light's name").value_or("light " + std::to_string(index));
    const size_t type =
        src_.choice(r.require("type", "one of \"point\", \"spot\", \"directional\", \"ies\""), kLightTypes);
    const bool point = type == 0, spot = type == 1, directional = type == 2, ies = type == 3;
    light.type = point         ? LightType::kPoint
                 : spot        ? LightType::kSpot
                 : directional ? LightType::kDirectional
                               : LightType::kGoniometric;
    const std::string isA = "; this light is of type " + inQuotes(kLightTypes[type]);

    vec3 position(0.0f);
    if (directional) {
      r.forbid("position", "does not apply to a directional light (it is infinitely far away)");
      r.forbid("range", "does not apply to a directional light");
    } else {
      position = src_.vector3(r.require("position", "[x, y, z] in metres"), "metres");
      light.rangeM = r.floatNumber("range", above(0.0), "metres").value_or(light.rangeM);
    }

    vec3 dir(0.0f, -1.0f, 0.0f);
    if (point) {
      r.forbid("direction", "does not apply to a point light (it shines equally in all directions)");
    } else if (const JsonValue* d = r.find("direction")) {
      dir = src_.direction(*d);
    }

    // Local +X is the IES C = 0° direction (light.h); for other lights it only has to be perpendicular.
    vec3 xHint(1.0f, 0.0f, 0.0f);
    if (perpendicularLength(xHint, dir) < kMinPerpendicular) xHint = vec3(0.0f, 0.0f, -1.0f);
    if (!ies) {
      r.forbid("c0Direction", "applies to IES lights only" + isA);
    } else if (const JsonValue* c0 = r.find("c0Direction")) {
      xHint = src_.direction(*c0);
      if (perpendicularLength(xHint, dir) < kMinPerpendicular) {
        src_.fail(*c0, "c0Direction must not be parallel to the light's direction",
                  "give a direction across the beam, e.g. [1, 0, 0] for a downlight");
      }
    }

    readLightColour(r, light);

    if (spot) {
      const float inner = r.floatNumber("innerConeDeg", closed(0, 90), "degrees").value_or(0.0f);
      const float outer = r.floatNumber("outerConeDeg", closed(0, 90), "degrees").value_or(45.0f);
      if (!(inner < outer)) {
        const JsonValue* at = r.find("innerConeDeg") ? r.find("innerConeDeg") : r.find("outerConeDeg");
        src_.fail(
            *at,
            "innerConeDeg (" + formatNumber(inner) + ") must be smaller than outerConeDeg (" +
                formatNumber(outer) + ")",
            "the light is at full intensity inside the inner cone and fades out towards the outer cone");
      }
      light.innerConeRad = glm::radians(inner);
      light.outerConeRad = glm::radians(outer);
    } else {
      r.forbid("innerConeDeg", "applies to spot lights only" + isA);
      r.forbid("outerConeDeg", "applies to spot lights only" + isA);
    }

    if (ies) {
      const JsonValue& fileValue = r.require("file", "the IES or EULUMDAT (.ldt) file");
      const bool eulumdat = isEulumdatPath(src_.string(fileValue, "the IES or EULUMDAT file's path"));
      const fs::path file = src_.inputFile(fileValue, eulumdat ? "EULUMDAT file" : "IES file");
      light.ies = std::make_shared<const IesProfile>(eulumdat ? loadEulumdat(file).profile : loadIes(file));
      light.iesPath = file.string();
    } else {
      r.forbid("file", "applies to IES lights only" + isA);
    }
    readLightOutput(r, light);
    if (const std::string problem = validate(light); !problem.empty())
      src_.fail(v, "invalid light: " + problem);
    Node node;
    node.name = light.name;
    node.parentFromLocal = lightFrame(position, dir, xHint);
    node.light = scene_.addLight(std::move(light)).id;
    scene_.addNode(std::move(node));
  }

  // "color" (linear Rec.709) or "temperatureK" (a black body's colour at luminance 1), not both.
  void readLightColour(const ObjectReader& r, Light& light) const {
    const JsonValue* temperature = r.find("temperatureK");
    if (!temperature) {
      light.color = r.colour("color", atLeast(0)).value_or(light.color);
      return;
    }
    if (r.find("color")) {
      r.forbid(
          "temperatureK",
          "conflicts with \"color\": give the light's colour either as RGB or as a colour temperature, not "
          "both");
    }
    const double kelvin = src_.number(*temperature, anyNumber(), "kelvin");
    if (!(kelvin >= kMinColourTemperatureK && kelvin <= kMaxColourTemperatureK)) {
      src_.fail(
          *temperature,
          "colour temperature " + formatNumber(kelvin) +
              " K is outside [1000, 40000] K, the black-body colours fly computes",
          "a candle is about 1900 K, a warm-white lamp 2700 K, daylight about 6500 K; for another colour "
          "give an RGB \"color\" instead");
    }
    light.temperatureK = static_cast<float>(kelvin);
    light.color = planckianRec709(kelvin);
  }

  // "intensity" (cd, lux, or a multiplier of a goniometric file's candela values) or "flux" (lm), not both.
  // The flux is what the light emits in its colour: intensity = flux / (luminance(color) × the flux of a
  // white light of intensity 1), so a tinted light still emits the lumens given.
  void readLightOutput(const ObjectReader& r, Light& light) const {
    const bool directional = light.type == LightType::kDirectional;
    const bool goniometric = light.type == LightType::kGoniometric;
    const JsonValue* flux = r.find("flux");
    if (!flux) {
      if (goniometric) {
        light.intensity =
            r.floatNumber("intensity", atLeast(0), "multiples of the file's candela values").value_or(1.0f);
      } else {
        light.intensity = src_.floatNumber(
            r.require("intensity", directional ? "illuminance in lux"
                                               : "luminous intensity in candela, or \"flux\" in lumens"),
            atLeast(0), directional ? "lux" : "candela");
      }
      return;
    }
    if (directional) {
      r.forbid("flux",
               "does not apply to a directional light (it lights everything from infinitely far away, so its "
               "flux is not finite); give its illuminance in lux with \"intensity\"");
    }
    if (r.find("intensity")) {
      r.forbid("flux",
               "conflicts with \"intensity\": give the light's output either as luminous flux (lm) or as " +
                   std::string(goniometric ? "a multiplier of the file's candela values" : "intensity (cd)") +
                   ", not both");
    }
    const double lumens = src_.number(*flux, above(0), "lumens");
    const double perIntensityLm = static_cast<double>(luminance(light.color)) * fluxPerUnitIntensityLm(light);
    if (!(perIntensityLm > 0.0)) {
      const bool dark = !(luminance(light.color) > 0.0f);
      src_.fail(*flux,
                dark          ? "a light whose color has luminance 0 emits no flux, whatever its intensity"
                : goniometric ? "the goniometric file " + light.iesPath +
                                    " emits no light (its intensities are all 0), so no scale gives it a flux"
                              : "a spot light whose outer cone is this narrow emits no light (the cone's cosine "
                                "rounds to 1 in single precision)",
                dark ? "give the light a colour, or its intensity instead of its flux"
                : goniometric ? "use a file with a distribution, or give the light's intensity instead"
                              : "widen outerConeDeg");
    }
    const double intensity = lumens / perIntensityLm;
    if (!(intensity <= std::numeric_limits<float>::max())) {
      src_.fail(*flux,
                "a flux of " + formatNumber(lumens) + " lm needs an intensity of " + formatNumber(intensity) +
                    ", beyond single precision (about 3.4e38)",
                "give a smaller flux, or widen the spot's cone");
    }
    light.intensity = static_cast<float>(intensity);
  }

  // --- overrides

  // Reads the material parameters of an override into edits that apply them to a material.
  std::vector<std::function<void(Material&)>> readMaterialEdits(const ObjectReader& r) const {
    std::vector<std::function<void(Material&)>> edits;
    const auto add = [&](auto value, auto apply) {
      if (value) edits.push_back([v = *value, apply](Material& m) { apply(m, v); });
    };
    const Range unit = closed(0, 1);
    add(r.colour("diffuse", unit), [](Material& m, Rgb c) { m.diffuseColor = c; });
    add(r.colour("reflection", unit), [](Material& m, Rgb c) { m.reflectionColor = c; });
    add(r.colour("transmission", unit), [](Material& m, Rgb c) { m.transmissionColor = c; });
    add(r.boolean("fresnel"), [](Material& m, bool f) {
      m.reflectionModel = f ? ReflectionModel::kFresnel : ReflectionModel::kUniform;
    });
    add(r.floatNumber("ior", closed(1, 4), ""), [](Material& m, float x) { m.ior = x; });
    add(r.floatNumber("reflectionGlossiness", unit, ""),
        [](Material& m, float x) { m.reflectionGlossiness = x; });
    if (const JsonValue* e = r.find("engineReflection")) {
      const std::string mode = e->isString() ? e->string() : "";
      const EngineReflection chosen = mode == "auto"     ? EngineReflection::kAuto
                                      : mode == "planar"  ? EngineReflection::kPlanar
                                      : mode == "cubemap" ? EngineReflection::kCubemap
                                      : mode == "none"    ? EngineReflection::kNone
                                                          : EngineReflection(-1);
      if (chosen == EngineReflection(-1))
        src_.fail(*e, "expected \"auto\", \"planar\", \"cubemap\" or \"none\"; got " + describeValue(*e));
      edits.push_back([chosen](Material& m) { m.engineReflection = chosen; });
    }
    if (const JsonValue* a = r.find("anisotropy")) {
      if (!a->isArray() || a->elements().size() != 2) {
        src_.fail(*a, "expected an array of 2 numbers [u, v], each in [0, 1]; got " + describeValue(*a));
      }
      const float u = src_.floatNumber(a->elements()[0], unit, "");
      const float w = src_.floatNumber(a->elements()[1], unit, "");
      edits.push_back([u, w](Material& m) {
        m.anisotropyU = u;
        m.anisotropyV = w;
      });
    }
    add(r.floatNumber("anisotropyRotationDeg", closed(-360, 360), "degrees"),
        [](Material& m, float deg) { m.anisotropyRotationRad = glm::radians(deg); });
    add(r.floatNumber("transmissionGlossiness", unit, ""),
        [](Material& m, float x) { m.transmissionGlossiness = x; });
    add(r.colour("scatteringColor", leftOpen(0, 1)), [](Material& m, Rgb c) { m.scatteringColor = c; });
    add(r.floatNumber("scatteringDistance", above(0), "metres"),
        [](Material& m, float x) { m.scatteringDistanceM = x; });
    add(r.floatNumber("reflectionFogDistance", above(0), "metres"),
        [](Material& m, float x) { m.reflectionFogDistanceM = x; });
    add(r.colour("reflectionFogColor", unit), [](Material& m, Rgb c) { m.reflectionFogColor = c; });
    add(r.floatNumber("bumpScale", atLeast(0), ""), [](Material& m, float x) { m.bumpScale = x; });
    add(r.boolean("doubleSided"), [](Material& m, bool b) { m.doubleSided = b; });
    add(r.colour("emission", atLeast(0), "cd/m²"), [](Material& m, Rgb c) { m.emissionLuminance = c; });
    if (const JsonValue* b = r.find("brdf")) {
      if (b->isString()) {
        const fs::path path = src_.inputFile(*b, "measured BRDF file");
        std::shared_ptr<const MeasuredBrdf> table;
        try {
          table = std::make_shared<const MeasuredBrdf>(readMerlBrdf(path));
        } catch (const InputError& e) {
          src_.fail(*b, e.message() + ": " + path.string(), e.hint());
        }
        edits.push_back([path, table](Material& m) {
          m.measuredBrdfPath = path.string();
          m.measuredBrdf = table;
          m.carPaint.reset();
        });
      } else {
        const CarPaintBrdf paint = readCarPaint(*b);
        edits.push_back([paint](Material& m) {
          m.carPaint = paint;
          m.measuredBrdf.reset();
          m.measuredBrdfPath.clear();
        });
      }
    }
    return edits;
  }

  // A car-paint BRDF object: {"base": [r, g, b], "flakes": [{"reflectance": [r, g, b], "roughness": r}, …],
  // "coat": {"ior": η, "roughness": r}}; roughness r as in glTF (GGX α = r²).
  CarPaintBrdf readCarPaint(const JsonValue& v) const {
    if (!v.isObject()) {
      src_.fail(v, "expected a measured BRDF file's path (a MERL .binary file) or a car-paint object "
                   "{\"base\", \"flakes\", \"coat\"}; got " + describeValue(v));
    }
    const ObjectReader r(src_, v, {"base", "flakes", "coat"});
    CarPaintBrdf paint;
    paint.baseAlbedo = src_.colour(r.require("base", "the pigment's albedo [r, g, b]"), closed(0, 1));
    if (const JsonValue* flakes = r.find("flakes")) {
      const auto& lobes = arrayOf(src_, flakes, "flake lobes {\"reflectance\", \"roughness\"}");
      if (lobes.size() > size_t(CarPaintBrdf::kMaxLobes)) {
        src_.fail(*flakes, "a car paint has at most " + std::to_string(CarPaintBrdf::kMaxLobes) +
                               " flake lobes; got " + std::to_string(lobes.size()));
      }
      for (size_t k = 0; k < lobes.size(); ++k) {
        const ObjectReader f(src_, lobes[k], {"reflectance", "roughness"});
        const float roughness =
            src_.floatNumber(f.require("roughness", "GGX roughness r, α = r²"), closed(0.1, 1), "");
        paint.lobes[k] = {src_.colour(f.require("reflectance", "the flakes' reflectance at normal incidence"),
                                      closed(0, 1)),
                          roughness * roughness};
      }
    }
    paint.coatIor = 1.5f;
    paint.coatAlpha = 0.01f;  // roughness 0.1: a factory clear coat
    if (const JsonValue* coat = r.find("coat")) {
      const ObjectReader c(src_, *coat, {"ior", "roughness"});
      paint.coatIor = c.floatNumber("ior", closed(1, 3), "").value_or(paint.coatIor);
      const float roughness = c.floatNumber("roughness", closed(0.0316, 1), "").value_or(0.1f);
      paint.coatAlpha = roughness * roughness;
    }
    return paint;
  }

  // `original` with a preset's parameters. Kept from the original: the name, its textures (a preset has none;
  // a wood texture should survive "polished-wood"), its emission and its being double-sided (a glTF
  // double-sided surface is a single sheet of geometry whatever it is made of).
  static Material withPreset(const Material& original, const MaterialPreset& preset) {
    Material m = preset.material;
    m.name = original.name;
    m.diffuseTexture = original.diffuseTexture;
    m.reflectionTexture = original.reflectionTexture;
    m.reflectionTextureSrgb = original.reflectionTextureSrgb;
    m.reflectionGlossinessTexture = original.reflectionGlossinessTexture;
    m.anisotropyTexture = original.anisotropyTexture;
    m.anisotropyRotationTexture = original.anisotropyRotationTexture;
    m.transmissionTexture = original.transmissionTexture;
    m.metalnessTexture = original.metalnessTexture;
    m.metalnessFactor = original.metalnessFactor;
    m.bumpTexture = original.bumpTexture;
    m.bumpScale = original.bumpScale;
    m.emissionLuminance = original.emissionLuminance;
    m.emissionTexture = original.emissionTexture;
    m.doubleSided = preset.material.doubleSided || original.doubleSided;
    return m;
  }

  void readOverrides(const JsonValue* overrides) {
    for (const JsonValue& v : arrayOf(src_, overrides, "overrides { \"material\" or \"node\": ... }"))
      readOverride(v);
  }

  void readOverride(const JsonValue& v) {
    const ObjectReader r(src_, v,
                         {"material",
                          "node",
                          "preset",
                          "diffuse",
                          "reflection",
                          "transmission",
                          "fresnel",
                          "ior",
                          "reflectionGlossiness",
                          "engineReflection",
                          "anisotropy",
                          "anisotropyRotationDeg",
                          "transmissionGlossiness",
                          "scatteringColor",
                          "scatteringDistance",
                          "reflectionFogDistance",
                          "reflectionFogColor",
                          "bumpScale",
                          "doubleSided",
                          "emission",
                          "brdf",
                          "twoSided",
                          "lightTexture"});
    const JsonValue* materialName = r.find("material");
    const JsonValue* nodeName = r.find("node");
    if (bool(materialName) == bool(nodeName)) {
      src_.fail(materialName ? *materialName : v,
                materialName ? "an override names either a material or a node, not both"
                             : "an override needs \"material\" (a material name) or \"node\" (a node name)",
                "a trailing '*' matches every name that begins with the text before it");
    }

    const MaterialPreset* preset = nullptr;
    if (const JsonValue* p = r.find("preset")) {
      preset = findMaterialPreset(src_.string(*p, "a preset name"));
      if (!preset) {
        std::vector<std::string> names;
        for (const MaterialPreset& mp : materialPresets()) names.emplace_back(mp.name);
        std::string hint = didYouMean(p->string(), names);
        src_.fail(*p, "unknown preset " + inQuotes(p->string()) + "; the presets are: " + joinNames(names),
                  hint.empty() ? "docs/scene-format.md describes each preset" : hint);
      }
    }
    const std::vector<std::function<void(Material&)>> edits = readMaterialEdits(r);
    const auto edit = [&](Material m) {
      if (preset) m = withPreset(m, *preset);
      for (const auto& e : edits) e(m);
      if (const std::string problem = validate(m); !problem.empty()) {
        src_.fail(v, "the overridden material " + inQuotes(m.name) + " is invalid: " + problem);
      }
      return m;
    };
    const bool changesMaterial = preset || !edits.empty();

    if (materialName) {
      r.forbid("twoSided", "applies to node overrides only (it is a property of meshes, not materials)");
      r.forbid("lightTexture", "applies to node overrides only (it is a property of meshes, not materials)");
      if (!changesMaterial)
        src_.fail(v, "the override changes nothing", "give a \"preset\" or material parameters");
      const std::string& pattern = src_.string(*materialName, "a material name");
      std::vector<MaterialId> matched;
      for (const auto& [id, m] : scene_.materials()) {
        if (matchesPattern(pattern, m.name)) matched.push_back(id);
      }
      if (matched.empty()) failNoMatch(*materialName, "material", namesOf(scene_.materials()));
      for (MaterialId id : matched) scene_.setMaterial(id, edit(scene_.material(id)));
      return;
    }

    const std::string& pattern = src_.string(*nodeName, "a node name");
    std::set<MeshId> meshes;
    bool matchedNode = false;
    for (const auto& [id, n] : scene_.nodes()) {
      if (matchesPattern(pattern, n.name)) {
        matchedNode = true;
        collectMeshes(id, meshes);
      }
    }
    if (!matchedNode) failNoMatch(*nodeName, "node", namesOf(scene_.nodes()));
    const std::optional<bool> twoSided = r.boolean("twoSided");
    const std::optional<LightTextureRequest> lightTexture = readLightTextureRequest(r);
    if (!changesMaterial && !twoSided && !lightTexture) {
      src_.fail(v, "the override changes nothing",
                "give a \"preset\", material parameters, \"twoSided\" or \"lightTexture\"");
    }
    // Meshes below the node get a new material derived from their current one, so that other users of that
    // material are unaffected; meshes sharing a material keep sharing the derived one.
    std::map<MaterialId, MaterialId> derived;
    for (MeshId mesh : meshes) {
      if (changesMaterial) {
        const MaterialId from = scene_.mesh(mesh).material;
        auto it = derived.find(from);
        if (it == derived.end()) {
          Material m = edit(scene_.material(from));
          m.name += "@" + pattern;
          it = derived.emplace(from, scene_.addMaterial(std::move(m)).id).first;
        }
        scene_.setMeshMaterial(mesh, it->second);
      }
      if (twoSided) scene_.setMeshTwoSided(mesh, *twoSided);
      if (lightTexture) scene_.setMeshLightTexture(mesh, *lightTexture);
    }
  }

  // "lightTexture": true | false | texels per metre.
  std::optional<LightTextureRequest> readLightTextureRequest(const ObjectReader& r) const {
    const JsonValue* v = r.find("lightTexture");
    if (!v) return std::nullopt;
    if (v->isBool()) return LightTextureRequest{v->boolean(), 0.0f, v->boolean()};
    if (!v->isNumber()) {
      src_.fail(*v,
                "expected true, false or a texel density in texels/m, (0, 1000]; got " + describeValue(*v));
    }
    return LightTextureRequest{true, src_.floatNumber(*v, leftOpen(0, 1000), "texels/m")};
  }

  // The meshes of a node and of every node below it.
  void collectMeshes(NodeId id, std::set<MeshId>& out) const {
    const Node& n = scene_.node(id);
    out.insert(n.meshes.begin(), n.meshes.end());
    for (NodeId c : n.children) collectMeshes(c, out);
  }

  [[noreturn]] void failNoMatch(const JsonValue& at, const std::string& kind,
                                const std::vector<std::string>& names) const {
    const std::string& pattern = at.string();
    std::string hint = didYouMean(pattern, names);
    if (hint.empty())
      hint =
          "names are case-sensitive; a trailing '*' matches every name that begins with the text before it";
    src_.fail(at,
              "no " + kind + " named " + inQuotes(pattern) + "; " + kind +
                  "s in the scene: " + (names.empty() ? "none" : joinNames(names)),
              hint);
  }

  // --- bake

  void readBake(const JsonValue& v) {
    const ObjectReader r(src_, v,
                         {"samples", "targetError", "time", "maxBounces", "texelsPerMetre", "lightTextures"});
    BakeSettings bake;
    if (const JsonValue* s = r.find("samples")) {
      const int64_t n = src_.integer(*s, 0, int64_t{1} << 31, "samples per vertex or texel");
      if (n != 0 && (n & (n - 1)) != 0) {
        int64_t below = 1;
        while (below * 2 < n) below *= 2;
        src_.fail(
            *s, "expected 0 or a power of two; got " + std::to_string(n),
            "the nearest powers of two are " + std::to_string(below) + " and " + std::to_string(below * 2));
      }
      bake.samples = static_cast<uint32_t>(n);
    }
    if (const JsonValue* e = r.find("targetError")) {
      if (e->isString()) {
        const std::string& s = e->string();
        double percent = 0.0;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), percent);
        if (ec != std::errc() || std::string_view(end, s.data() + s.size()) != "%" ||
            !(percent > 0 && percent < 100)) {
          src_.fail(*e,
                    "expected a relative error in (0, 1) or a percentage in (0%, 100%) such as \"1%\"; got " +
                        inQuotes(s));
        }
        bake.targetErrorRel = percent / 100.0;
      } else {
        bake.targetErrorRel = src_.number(*e, exclusive(0, 1), "relative standard error (0.01 = 1 %)");
      }
    }
    if (const JsonValue* t = r.find("time")) {
      const std::optional<double> seconds = t->isString() ? parseDuration(t->string()) : std::nullopt;
      if (t->isString() && !seconds) {
        src_.fail(*t, "expected a duration such as \"90s\", \"5m\", \"1.5h\" or \"1h30m\"; got " +
                          inQuotes(t->string()));
      }
      bake.timeLimitS = seconds ? *seconds : src_.number(*t, atLeast(0), "seconds");
    }
    if (const std::optional<int64_t> b = r.integer("maxBounces", 0, 10000, "indirect bounces")) {
      bake.maxBounces = static_cast<uint32_t>(*b);
    }
    bake.texelsPerMetre =
        r.number("texelsPerMetre", leftOpen(0, 1000), "texels/m").value_or(bake.texelsPerMetre);
    // Patterns are expanded here, so that the bake settings hold the names themselves, and the meshes they name
    // (or that lie below the nodes they name) ask for a light texture at the bake's density.
    std::set<MeshId> lightTextured;
    for (const JsonValue& n : arrayOf(src_, r.find("lightTextures"), "mesh or node names")) {
      const std::string& pattern = src_.string(n, "a mesh or node name");
      std::set<std::string> matched;
      for (const auto& [id, mesh] : scene_.meshes()) {
        if (matchesPattern(pattern, mesh.name)) {
          matched.insert(mesh.name);
          lightTextured.insert(id);
        }
      }
      for (const auto& [id, node] : scene_.nodes()) {
        if (matchesPattern(pattern, node.name)) {
          matched.insert(node.name);
          collectMeshes(id, lightTextured);
        }
      }
      if (matched.empty()) {
        std::set<std::string> all;
        for (const std::string& name : namesOf(scene_.meshes())) all.insert(name);
        for (const std::string& name : namesOf(scene_.nodes())) all.insert(name);
        failNoMatch(n, "mesh or node", {all.begin(), all.end()});
      }
      std::vector<std::string>& names = bake.lightTextureNames;
      for (const std::string& name : matched) {
        if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
      }
    }
    for (MeshId mesh : lightTextured) {
      // A density an override gave the mesh wins; 0 means the bake's texelsPerMetre.
      const float density = scene_.mesh(mesh).lightTexture.texelsPerMetre;
      scene_.setMeshLightTexture(mesh, {true, density});
    }
    scene_.setBakeSettings(bake);
  }

  // --- cameras

  void readCameras(const JsonValue* cameras) {
    std::set<std::string> names;
    for (const JsonValue& v : arrayOf(src_, cameras, "cameras { \"name\": ..., \"position\": ... }")) {
      const ObjectReader r(src_, v, {"name", "position", "target", "up", "fovDeg", "near", "far"});
      const JsonValue& nameValue = r.require("name", "the camera's name");
      Camera cam;
      cam.name = src_.string(nameValue, "the camera's name");
      if (!names.insert(cam.name).second) {
        src_.fail(nameValue, "a camera named " + inQuotes(cam.name) + " is already defined",
                  "give each camera its own name");
      }
      const vec3 eye = src_.vector3(r.require("position", "[x, y, z] in metres"), "metres");
      const JsonValue& targetValue = r.require("target", "the point looked at, [x, y, z] in metres");
      const vec3 target = src_.vector3(targetValue, "metres");
      const vec3 up = r.vector3("up", "").value_or(vec3(0.0f, 1.0f, 0.0f));
      cam.yfovRad =
          glm::radians(r.floatNumber("fovDeg", exclusive(0, 180), "degrees (vertical)").value_or(50.0f));
      cam.znearM = r.floatNumber("near", above(0), "metres").value_or(cam.znearM);
      if (const JsonValue* far = r.find("far")) {
        cam.zfarM = src_.floatNumber(*far, above(cam.znearM), "metres (beyond near)");
      }
      Node node;
      node.name = cam.name;
      try {
        node.parentFromLocal = lookAtTransform(eye, target, up);
      } catch (const std::invalid_argument& e) {
        const JsonValue* upValue = r.find("up");
        const JsonValue& at = eye == target ? targetValue : upValue ? *upValue : v;
        src_.fail(at, e.what(),
                  eye == target
                      ? "move the target away from the position"
                      : "give an \"up\" vector across the view, e.g. [0, 0, -1] for a camera looking down");
      }
      node.camera = scene_.addCamera(std::move(cam)).id;
      scene_.addNode(std::move(node));
    }
  }

  // --- portals

  void readPortals(const JsonValue* portals) {
    const std::span<const JsonValue> all =
        arrayOf(src_, portals, "portals { \"name\": ..., \"corners\": [[x, y, z], ...] }");
    if (all.empty()) return;
    std::vector<Portal> read;
    for (size_t i = 0; i < all.size(); ++i) {
      const ObjectReader r(src_, all[i], {"name", "corners"});
      Portal portal;
      portal.name = r.string("name", "the portal's name").value_or("portal " + std::to_string(i));
      const JsonValue& corners =
          r.require("corners", "3 or 4 corners [[x, y, z], ...] in metres, in order around the opening");
      const std::span<const JsonValue> points = arrayOf(src_, &corners, "3 or 4 corners [x, y, z] in metres");
      if (points.size() != 3 && points.size() != 4) {
        src_.fail(corners, "expected 3 or 4 corners; got " + describeValue(corners),
                  "give a triangle of 3 corners or a convex quad of 4, in order around the opening's edge "
                  "(an opening of more corners: declare several portals)");
      }
      for (const JsonValue& p : points) portal.cornersM.push_back(src_.vector3(p, "metres"));
      if (const std::optional<PortalProblem> problem = checkPortal(portal.cornersM)) {
        src_.fail(problem->corner ? points[*problem->corner] : corners, problem->message, problem->hint);
      }
      read.push_back(std::move(portal));
    }
    scene_.setPortals(std::move(read));
  }

  const JsonDocument& doc_;
  Source src_;
  Scene& scene_;
};

}  // namespace

Scene parseSceneFile(std::string_view text, const std::string& fileName, const fs::path& baseDir) {
  const JsonDocument doc = parseJson(text, fileName);
  Scene scene;
  SceneFileReader(doc, baseDir, scene).read();
  return scene;
}

Scene loadSceneFile(const fs::path& path) {
  Scene scene = parseSceneFile(readInputFile(path, "scene file"), path.string(), path.parent_path());
  scene.sourcePath = path;
  return scene;
}

}  // namespace fly::sdb
