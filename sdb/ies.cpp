#include "sdb/ies.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>
#include <utility>

#include "base/error.h"
#include "base/file_io.h"
#include "base/math.h"
#include "sdb/photometric_text.h"

namespace fly::sdb {
namespace {

// A candela table larger than this is taken for a corrupt count rather than allocated. One million values
// (8 MB) hold a full sphere at 0.25° × 0.5°, finer than goniophotometers measure.
constexpr double kMaxCandelaValues = 1e6;
// Scaled intensities above this (cd) are taken for a corrupt file: the brightest searchlights reach about 1e9
// cd. The bound also keeps the flux integral finite.
constexpr double kMaxCandela = 1e12;
// The smallest step between consecutive angles of a list, degrees.
constexpr double kMinAngleStepDeg = 1e-3;
// Angles within this many degrees of an end point that LM-63 prescribes (0, 90, 180, 270, 360) are snapped to
// it, so that the symmetry cases of candelaAt and totalFluxLm can compare exactly.
constexpr double kAngleSnapDeg = 1e-6;
constexpr double kMetresPerFoot = 0.3048;

constexpr std::string_view kTiltHint = "export the file with TILT=NONE";

struct Token {
  std::string_view text;
  int line = 0;
};

bool startsWithNoCase(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (size_t i = 0; i < prefix.size(); ++i) {
    const auto upper = [](char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c; };
    if (upper(s[i]) != upper(prefix[i])) return false;
  }
  return true;
}

bool near(double a, double b) {
  return std::abs(a - b) <= kAngleSnapDeg;
}

// Index i and weight t such that x = (1 − t)·a[i] + t·a[i + 1]; false when x lies outside [a.front(),
// a.back()]. A single angle matches only itself (t = 0, and a[i + 1] is never read).
bool locate(const std::vector<double>& a, double x, size_t& i, double& t) {
  if (a.size() == 1) {
    i = 0;
    t = 0.0;
    return x == a[0];
  }
  if (!(x >= a.front() && x <= a.back())) return false;  // also rejects NaN
  const auto upper = std::upper_bound(a.begin(), a.end(), x);
  i = std::min(static_cast<size_t>(upper - a.begin()), a.size() - 1) - 1;
  t = (x - a[i]) / (a[i + 1] - a[i]);
  return true;
}

double lerpAt(const std::vector<double>& row, size_t i, double t) {
  return t == 0.0 ? row[i] : row[i] + t * (row[i + 1] - row[i]);
}

// m0 = ∫ (b − θ)/Δ · sin θ dθ and m1 = ∫ (θ − a)/Δ · sin θ dθ over [a, b] (radians, Δ = b − a): the integrals
// of the two linear interpolation weights times sin θ, exactly, from ∫ (θ − a) sin θ dθ = [−(θ − a) cos θ +
// sin θ].
struct Moments {
  double m0 = 0.0;
  double m1 = 0.0;
};
Moments sinMoments(double a, double b) {
  const double d = b - a;
  const double whole = std::cos(a) - std::cos(b);
  const double m1 = (std::sin(b) - std::sin(a) - d * std::cos(b)) / d;
  return {whole - m1, m1};
}

// How many copies of the measured table the full distribution holds (the symmetries of LM-63-2002's vertical
// and horizontal angle ranges). A type C table with a single C-plane (rotational symmetry) is left to the
// caller.
double symmetryCopies(const IesProfile& p) {
  const double h0 = p.horizontalDeg.front();
  const double h1 = p.horizontalDeg.back();
  if (p.type == PhotometryType::kC) {
    if (h0 == 0.0 && h1 == 90.0) return 4.0;                                    // quadrant symmetric
    if ((h0 == 0.0 && h1 == 180.0) || (h0 == 90.0 && h1 == 270.0)) return 2.0;  // bilateral
    return 1.0;
  }
  const double v0 = p.verticalDeg.front();
  return (h0 == 0.0 ? 2.0 : 1.0) * (v0 == 0.0 ? 2.0 : 1.0);  // mirrored about H = 0 and/or V = 0
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& fileName) : text_(text), file_(fileName) {}

  IesProfile parse() {
    IesProfile p;
    parseHeader(p);
    tokenize();
    parseNumbers(p);
    return p;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& message, std::string_view hint) const {
    SourceLocation location;
    location.file = file_;
    location.line = line;
    throw InputError(std::move(location), message, std::string(hint));
  }

  // Format line, keyword (or, for LM-63-1986, label) lines, then TILT=.
  void parseHeader(IesProfile& p) {
    if (text_.starts_with("\xEF\xBB\xBF")) pos_ = 3;  // UTF-8 byte order mark written by some editors
    bool first = true;
    while (pos_ < text_.size()) {
      const size_t end = std::min(text_.find('\n', pos_), text_.size());
      const std::string_view line = trimBlanks(text_.substr(pos_, end - pos_));
      ++line_;
      pos_ = end + 1;
      if (first) {
        first = false;
        if (startsFormatLine(line, p)) continue;
      }
      if (startsWithNoCase(line, "TILT")) {
        const std::string_view rest = trimBlanks(line.substr(4));
        if (!rest.empty() && rest.front() == '=') {
          checkTilt(trimBlanks(rest.substr(1)));
          return;
        }
      }
      if (!line.empty()) p.keywords.emplace_back(line);
    }
    fail(0,
         "no TILT= line found in " + std::to_string(line_) +
             " lines; LM-63 requires one (TILT=NONE) between the keyword lines and the photometric data",
         "is this an IES LM-63 file? Export it again from the photometry software, with TILT=NONE");
  }

  // True when the first line names the format; LM-63-1986 files have none and start with a label line.
  bool startsFormatLine(std::string_view line, IesProfile& p) const {
    if (line == "IESNA:LM-63-2002") {
      p.format = IesFormat::kLm63_2002;
    } else if (line == "IESNA:LM-63-1995") {
      p.format = IesFormat::kLm63_1995;
    } else if (line == "IESNA91") {
      p.format = IesFormat::kLm63_1991;
    } else if (startsWithNoCase(line, "IESNA:") || startsWithNoCase(line, "IES:")) {  // e.g. IES:LM-63-2019
      fail(line_, "unsupported IES format " + quotedExcerpt(line),
           "fly reads LM-63-1986, IESNA91, IESNA:LM-63-1995 and IESNA:LM-63-2002 files; export the file in "
           "one of these formats");
    } else {
      p.format = IesFormat::kLm63_1986;
      return false;
    }
    return true;
  }

  void checkTilt(std::string_view value) const {
    if (startsWithNoCase(value, "NONE") && value.size() == 4) return;
    if (startsWithNoCase(value, "INCLUDE") && value.size() == 7) {
      fail(line_, "TILT=INCLUDE is not supported; fly reads lamp-tilt-independent photometry only",
           kTiltHint);
    }
    fail(line_,
         "TILT=" + printableExcerpt(value) + " (tilt data in another file) is not supported; fly reads " +
             "lamp-tilt-independent photometry only",
         kTiltHint);
  }

  // The photometric data after the TILT line: numbers separated by blanks, commas or line breaks, spanning
  // lines freely (LM-63-2002, definition of "delimiter"). 0x1A is the DOS end-of-file mark that old files
  // carry.
  void tokenize() {
    const auto isSeparator = [](char c) {
      return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ',' || c == '\f' || c == '\v' ||
             c == '\x1a';
    };
    int line = line_ + 1;
    size_t i = pos_;
    while (i < text_.size()) {
      if (isSeparator(text_[i])) {
        if (text_[i] == '\n') ++line;
        ++i;
        continue;
      }
      const size_t start = i;
      while (i < text_.size() && !isSeparator(text_[i])) ++i;
      tokens_.push_back({text_.substr(start, i - start), line});
    }
    lastLine_ = tokens_.empty() ? line_ : tokens_.back().line;
  }

  // `describe()` names the expected value; it is called only when the message is needed, as tables run to a
  // million values.
  template <class Describe>
  double number(const Token& t, const Describe& describe) const {
    std::string_view s = t.text;
    // std::from_chars refuses an explicit plus sign.
    if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ptr != s.data() + s.size() || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
      fail(t.line, quotedExcerpt(t.text) + " is not a number (expected " + describe() + ")",
           "the photometric data after TILT=NONE may hold only numbers separated by blanks, commas or line "
           "breaks");
    }
    if (ec == std::errc::result_out_of_range || !std::isfinite(v)) {
      fail(t.line, quotedExcerpt(t.text) + " is not a finite number (" + describe() + ")",
           "NaN, infinite and out-of-range values are not allowed; export the file again");
    }
    return v;
  }
  double number(const Token& t, const char* what) const {
    return number(t, [what] { return std::string(what); });
  }

  double wholeNumber(const Token& t, const std::string& what, double lo, double hi) const {
    // Counts and type codes are integers; a fractional value means the numbers are out of step.
    const double v = number(t, what.c_str());
    if (v != std::floor(v)) fail(t.line, what + " must be a whole number, not " + quotedExcerpt(t.text), kFixCounts);
    if (v < lo) fail(t.line, what + " is " + formatNumber(v) + "; it must be at least " + formatNumber(lo), kFixCounts);
    if (v > hi) {
      fail(t.line, what + " " + formatNumber(v) + " is too large (at most " + formatNumber(hi) + ")",
           "the count is probably corrupt; export the file again");
    }
    return v;
  }

  double positive(const Token& t, const char* what) const {
    const double v = number(t, what);
    if (!(v > 0.0)) {
      fail(t.line, std::string(what) + " must be positive, not " + formatNumber(v),
           "LM-63 writes 1 where no factor applies");
    }
    return v;
  }

  // The photometric data in file order (LM-63-2002, the lines after TILT=).
  void parseNumbers(IesProfile& p) {
    constexpr size_t kHeaderValues = 13;  // 10 values on the first line after TILT=, 3 on the second
    if (tokens_.size() < kHeaderValues) {
      fail(lastLine_,
           "file ends too early: expected at least " + std::to_string(kHeaderValues) +
               " numbers after the TILT line (lamps, lumens, multiplier, angle counts, types, dimensions, "
               "ballast factors, watts), found " +
               std::to_string(tokens_.size()),
           kTruncatedHint);
    }
    const Token* t = tokens_.data();

    const double lamps = wholeNumber(t[0], "number of lamps", 1.0, 1e6);
    const double lumensPerLamp = number(t[1], "lumens per lamp");
    if (lumensPerLamp < 0.0 && lumensPerLamp != -1.0) {
      fail(t[1].line, "lumens per lamp is " + formatNumber(lumensPerLamp),
           "give the rated lamp lumens, or -1 for absolute photometry (LM-63-2002)");
    }
    p.lampLumens = lumensPerLamp < 0.0 ? 0.0 : lamps * lumensPerLamp;
    const double multiplier = positive(t[2], "candela multiplier");
    const double nV = wholeNumber(t[3], "number of vertical angles", 1.0, kMaxCandelaValues);
    const double nH = wholeNumber(t[4], "number of horizontal angles", 1.0, kMaxCandelaValues);
    if (nV * nH > kMaxCandelaValues) {
      fail(t[4].line,
           "candela table of " + formatNumber(nV) + " × " + formatNumber(nH) + " values is too large (at most " +
               formatNumber(kMaxCandelaValues) + ")",
           "the angle counts are probably corrupt; export the file again");
    }
    const double type = wholeNumber(t[5], "photometric type", 0.0, 1e9);
    if (type < 1.0 || type > 3.0) {
      fail(t[5].line, "unsupported photometric type " + formatNumber(type),
           "LM-63 knows type 1 (C), 2 (B) and 3 (A); fix the seventh number after the TILT line");
    }
    p.type = static_cast<PhotometryType>(static_cast<int>(type));
    const double units = wholeNumber(t[6], "units type", 0.0, 1e9);
    if (units != 1.0 && units != 2.0) {
      fail(t[6].line, "unknown units type " + formatNumber(units),
           "LM-63 knows units type 1 (feet) and 2 (metres); fix the eighth number after the TILT line");
    }
    const double toMetres = units == 1.0 ? kMetresPerFoot : 1.0;
    p.widthM = number(t[7], "luminous opening width") * toMetres;
    p.lengthM = number(t[8], "luminous opening length") * toMetres;
    p.heightM = number(t[9], "luminous opening height") * toMetres;

    const double ballast = positive(t[10], "ballast factor");
    // LM-63-2002 turned the ballast-lamp photometric factor of the earlier versions into a field "for future
    // use" (written as 1), which is read but not applied.
    double ballastLamp = 1.0;
    if (p.format == IesFormat::kLm63_2002) {
      number(t[11], "future-use value");
    } else {
      ballastLamp = positive(t[11], "ballast-lamp photometric factor");
    }
    p.inputWatts = number(t[12], "input watts");
    if (p.inputWatts < 0.0) {
      fail(t[12].line, "input watts is negative (" + formatNumber(p.inputWatts) + ")", kFixCounts);
    }

    const auto nv = static_cast<size_t>(nV);
    const auto nh = static_cast<size_t>(nH);
    const size_t expected = kHeaderValues + nv + nh + nv * nh;
    if (tokens_.size() < expected) {
      fail(lastLine_,
           "file ends too early: expected " + std::to_string(expected) +
               " numbers after the TILT line (13 header values, " + std::to_string(nv) +
               " vertical angles, " + std::to_string(nh) + " horizontal angles, " + std::to_string(nv) +
               " × " + std::to_string(nh) + " candela values), found " + std::to_string(tokens_.size()),
           kTruncatedHint);
    }
    if (tokens_.size() > expected) {
      fail(tokens_[expected].line,
           "unexpected " + quotedExcerpt(tokens_[expected].text) + " after the last candela value (" +
               std::to_string(tokens_.size() - expected) + " values too many)",
           "the numbers of vertical and horizontal angles (line " + std::to_string(t[3].line) +
               ") must match the table; fix them or export the file again");
    }

    p.verticalDeg = angles(t + kHeaderValues, nv, "vertical");
    p.horizontalDeg = angles(t + kHeaderValues + nv, nh, "horizontal");
    checkVerticalRange(p, t + kHeaderValues);
    checkHorizontalRange(p, t + kHeaderValues + nv);

    const double scale = multiplier * ballast * ballastLamp;
    const Token* c = t + kHeaderValues + nv + nh;
    p.candela.assign(nh, std::vector<double>(nv));
    for (size_t h = 0; h < nh; ++h) {
      for (size_t v = 0; v < nv; ++v, ++c) {
        const auto where = [&] {
          return "vertical angle " + formatNumber(p.verticalDeg[v]) + "°, horizontal angle " +
                 formatNumber(p.horizontalDeg[h]) + "°";
        };
        const double raw = number(*c, [&] { return "the candela value at " + where(); });
        if (raw < 0.0) {
          fail(c->line, "negative candela value " + formatNumber(raw) + " at " + where(),
               "luminous intensity cannot be negative; export the file again");
        }
        p.candela[h][v] = raw * scale;
        if (p.candela[h][v] > kMaxCandela) {
          fail(c->line,
               "candela value " + formatNumber(p.candela[h][v]) + " at " + where() + " exceeds " + formatNumber(kMaxCandela) +
                   " cd (after the multiplier and ballast factors)",
               "no luminaire is this bright; check the candela multiplier and the file");
        }
      }
    }
  }

  std::vector<double> angles(const Token* t, size_t n, const std::string& kind) const {
    std::vector<double> a(n);
    for (size_t i = 0; i < n; ++i) {
      a[i] =
          number(t[i], [&] { return kind + " angle " + std::to_string(i + 1) + " of " + std::to_string(n); });
      if (i > 0 && !(a[i] > a[i - 1])) {
        fail(t[i].line,
             kind + " angles are not in ascending order: " + formatNumber(a[i]) + "° follows " + formatNumber(a[i - 1]) + "°",
             "LM-63 lists angles from smallest to largest, each once; fix the angle list or its count");
      }
      // Steps below a thousandth of a degree measure nothing (goniophotometers step by 0.1° at the finest) and
      // make the flux integral's cells degenerate.
      if (i > 0 && a[i] - a[i - 1] < kMinAngleStepDeg) {
        fail(t[i].line,
             kind + " angles " + formatNumber(a[i - 1]) + "° and " + formatNumber(a[i]) + "° are less than " +
                 formatNumber(kMinAngleStepDeg) + "° apart",
             "list each measured angle once; fix the angle list or its count");
      }
    }
    return a;
  }

  // Snaps the end points to the value LM-63 requires, or fails naming the allowed ranges.
  void checkVerticalRange(IesProfile& p, const Token* t) const {
    std::vector<double>& v = p.verticalDeg;
    const size_t n = v.size();
    const bool typeC = p.type == PhotometryType::kC;
    const std::string allowed =
        typeC ? "0–90°, 90–180° or 0–180° for type C (LM-63-2002, vertical angles)"
              : "0–90° (mirrored) or −90–90° for types A and B (LM-63-2002, vertical angles)";
    if (n < 2) {
      fail(t[0].line, "a single vertical angle (" + formatNumber(v[0]) + "°) cannot describe a distribution",
           "the vertical angles must span " + allowed);
    }
    const auto snap = [&](double& a, std::initializer_list<double> choices, const Token& tok) {
      for (const double c : choices) {
        if (near(a, c)) {
          a = c;
          return;
        }
      }
      fail(tok.line,
           "vertical angles from " + formatNumber(v.front()) + "° to " + formatNumber(v.back()) + "° are not an LM-63 range",
           "the vertical angles must span " + allowed);
    };
    if (typeC) {
      snap(v.front(), {0.0, 90.0}, t[0]);
      snap(v.back(), {90.0, 180.0}, t[n - 1]);
    } else {
      snap(v.front(), {-90.0, 0.0}, t[0]);
      snap(v.back(), {90.0}, t[n - 1]);
    }
  }

  void checkHorizontalRange(IesProfile& p, const Token* t) const {
    std::vector<double>& h = p.horizontalDeg;
    const size_t n = h.size();
    const bool typeC = p.type == PhotometryType::kC;
    const auto bad = [&](const Token& tok) {
      fail(tok.line,
           "horizontal angles from " + formatNumber(h.front()) + "° to " + formatNumber(h.back()) +
               "° are not one of LM-63's symmetries",
           typeC ? "type C horizontal angles must be a single 0° (rotationally symmetric), or span 0–90° "
                   "(quadrant symmetric), 0–180° or 90–270° (bilateral) or 0–360° (no symmetry) (LM-63-2002, "
                   "horizontal angles)"
                 : "type A and B horizontal angles must span 0–90° (mirrored) or −90–90° (LM-63-2002, "
                   "horizontal angles)");
    };
    const auto snap = [&](double& a, double value) {
      if (!near(a, value)) return false;
      a = value;
      return true;
    };
    if (!typeC) {
      if (n < 2 || !(snap(h.front(), 0.0) || snap(h.front(), -90.0))) bad(t[0]);
      if (!snap(h.back(), 90.0)) bad(t[n - 1]);
      return;
    }
    if (n == 1) {
      if (!snap(h.front(), 0.0)) bad(t[0]);
      return;
    }
    if (snap(h.front(), 0.0)) {
      if (!(snap(h.back(), 90.0) || snap(h.back(), 180.0) || snap(h.back(), 360.0))) bad(t[n - 1]);
    } else if (snap(h.front(), 90.0)) {
      if (!snap(h.back(), 270.0)) bad(t[n - 1]);
    } else {
      bad(t[0]);
    }
  }

  static constexpr std::string_view kTruncatedHint =
      "the file is truncated, or the numbers of vertical and horizontal angles do not match the table; "
      "export it again";
  static constexpr std::string_view kFixCounts = "check this value in the file, or export it again";

  std::string_view text_;
  const std::string& file_;
  size_t pos_ = 0;    // byte offset of the next header line
  int line_ = 0;      // 1-based number of the last header line read
  int lastLine_ = 0;  // line of the last number, where a truncated file ends
  std::vector<Token> tokens_;
};

}  // namespace

double IesProfile::candelaAt(double vDeg, double hDeg) const {
  if (candela.empty() || verticalDeg.empty() || horizontalDeg.empty()) return 0.0;
  double v = vDeg;
  double h = hDeg;
  const double h0 = horizontalDeg.front();
  const double h1 = horizontalDeg.back();
  if (type == PhotometryType::kC) {
    // Fold C into the measured range (LM-63-2002, horizontal angles).
    h = std::fmod(h, 360.0);
    if (h < 0.0) h += 360.0;
    if (horizontalDeg.size() == 1) {
      h = h0;  // rotationally symmetric
    } else if (h0 == 0.0 && h1 == 90.0) {
      if (h > 180.0) h = 360.0 - h;  // quadrant symmetric: mirror about 0–180, then about 90–270
      if (h > 90.0) h = 180.0 - h;
    } else if (h0 == 0.0 && h1 == 180.0) {
      if (h > 180.0) h = 360.0 - h;  // bilateral about the 0–180° plane
    } else if (h0 == 90.0 && h1 == 270.0) {
      // Bilateral about the 90–270° plane: C ↦ 180° − C.
      if (h < 90.0) {
        h = 180.0 - h;
      } else if (h > 270.0) {
        h = 540.0 - h;
      }
    }
  } else {
    if (h0 == 0.0) h = std::abs(h);                   // mirrored about H = 0
    if (verticalDeg.front() == 0.0) v = std::abs(v);  // mirrored about V = 0
  }
  size_t iv = 0, ih = 0;
  double tv = 0.0, th = 0.0;
  if (!locate(verticalDeg, v, iv, tv) || !locate(horizontalDeg, h, ih, th)) return 0.0;
  const double a = lerpAt(candela[ih], iv, tv);
  return th == 0.0 ? a : a + th * (lerpAt(candela[ih + 1], iv, tv) - a);
}

double IesProfile::candelaTowards(double x, double y, double z) const {
  const double len = std::sqrt(x * x + y * y + z * z);
  if (!(len > 0.0) || !std::isfinite(len)) return 0.0;
  x /= len;
  y /= len;
  z /= len;
  switch (type) {
    case PhotometryType::kC: {
      double c = radToDeg(std::atan2(y, x));
      if (c < 0.0) c += 360.0;
      return candelaAt(radToDeg(std::acos(std::clamp(z, -1.0, 1.0))), c);
    }
    case PhotometryType::kA:
      return candelaAt(radToDeg(std::asin(std::clamp(-y, -1.0, 1.0))), radToDeg(std::atan2(x, z)));
    case PhotometryType::kB:
      return candelaAt(radToDeg(std::atan2(-y, z)), radToDeg(std::asin(std::clamp(x, -1.0, 1.0))));
  }
  return 0.0;
}

// Integrates the bilinear interpolant exactly, cell by cell: with the weight w (sin γ for type C, cos V for
// type A, cos H for type B) on one axis, ∫∫ I w = Δ(other axis)/2 · Σ corner values × the moments of w
// (sinMoments).
double IesProfile::totalFluxLm() const {
  if (candela.empty() || verticalDeg.size() < 2) return 0.0;
  const std::vector<double>& V = verticalDeg;
  const std::vector<double>& H = horizontalDeg;
  // cos θ = sin(θ + 90°): types A and B use the moments of sin on shifted intervals.
  const double shift = type == PhotometryType::kC ? 0.0 : 90.0;
  const bool weightOnVertical = type != PhotometryType::kB;
  const std::vector<double>& weighted = weightOnVertical ? V : H;
  std::vector<Moments> m(weighted.size() - 1);
  for (size_t i = 0; i + 1 < weighted.size(); ++i) {
    m[i] = sinMoments(degToRad(weighted[i] + shift), degToRad(weighted[i + 1] + shift));
  }
  double sum = 0.0;
  if (H.size() == 1) {  // type C, rotationally symmetric: 2π × ∫ I(γ) sin γ dγ
    for (size_t i = 0; i + 1 < V.size(); ++i) sum += candela[0][i] * m[i].m0 + candela[0][i + 1] * m[i].m1;
    return 2.0 * kPi * sum;
  }
  for (size_t j = 0; j + 1 < H.size(); ++j) {
    const std::vector<double>& c0 = candela[j];
    const std::vector<double>& c1 = candela[j + 1];
    const double dh = degToRad(H[j + 1] - H[j]);
    for (size_t i = 0; i + 1 < V.size(); ++i) {
      if (weightOnVertical) {
        sum += 0.5 * dh * ((c0[i] + c1[i]) * m[i].m0 + (c0[i + 1] + c1[i + 1]) * m[i].m1);
      } else {
        const double dv = degToRad(V[i + 1] - V[i]);
        sum += 0.5 * dv * ((c0[i] + c0[i + 1]) * m[j].m0 + (c1[i] + c1[i + 1]) * m[j].m1);
      }
    }
  }
  return sum * symmetryCopies(*this);
}

double IesProfile::maxCandela() const {
  double m = 0.0;
  for (const std::vector<double>& row : candela) {
    for (const double c : row) m = std::max(m, c);
  }
  return m;
}

IesProfile parseIes(std::string_view text, const std::string& fileName) {
  return Parser(text, fileName).parse();
}

IesProfile loadIes(const std::filesystem::path& path) {
  return parseIes(readInputFile(path, "IES file"), path.string());
}

}  // namespace fly::sdb
