#include "sdb/eulumdat.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>
#include <utility>

#include "base/error.h"
#include "base/file_io.h"
#include "base/log.h"
#include "sdb/photometric_text.h"

namespace fly::sdb {
namespace {

// As for IES files (sdb/ies.cpp): a table larger than this is taken for a corrupt count, intensities above
// this (cd) for a corrupt file.
constexpr double kMaxCandelaValues = 1e6;
constexpr double kMaxCandela = 1e12;
// More lamp sets than this is taken for a corrupt count (files list a handful of alternative equipments).
constexpr int kMaxLampSets = 100;
// Angles within this many degrees of 0°, 90°, 180°, 270° or 360° are snapped to them, as for IES files.
constexpr double kAngleSnapDeg = 1e-6;
// loadEulumdat warns when the intensities integrate to a flux this far (relative) from lamp flux × LORL.
constexpr double kFluxMismatchWarning = 0.05;

constexpr std::string_view kTruncatedHint =
    "the file is truncated, or a count in its header (Mc on line 4, Ng on line 6, n on line 26) does not "
    "match "
    "what follows; export it again";
constexpr std::string_view kFixValueHint = "check this line of the file, or export it again";

// A number as EULUMDAT files write it: a decimal point or, as some European software writes, a decimal comma.
bool parseNumber(std::string_view s, double& v) {
  std::string buf(s);
  if (buf.find('.') == std::string::npos) std::replace(buf.begin(), buf.end(), ',', '.');
  const char* first = buf.data();
  if (!buf.empty() && buf.front() == '+') ++first;
  const char* last = buf.data() + buf.size();
  const auto [end, ec] = std::from_chars(first, last, v);
  return ec == std::errc() && end == last && first != last;
}

struct Token {
  std::string_view text;
  int line = 0;
};

class Parser {
 public:
  Parser(std::string_view text, const std::string& fileName) : file_(fileName) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte order mark
    size_t pos = 0;
    while (pos < text.size()) {
      const size_t end = std::min(text.find('\n', pos), text.size());
      lines_.push_back(trimBlanks(text.substr(pos, end - pos)));
      pos = end + 1;
    }
    // A DOS end-of-file mark (0x1A) on a line of its own after the data is not a value.
    while (!lines_.empty() && (lines_.back().empty() || lines_.back() == "\x1a")) lines_.pop_back();
  }

  Eulumdat parse() {
    Eulumdat e;
    e.company = std::string(text(1, "company identification"));
    e.typeIndicator = integer(2, "type indicator Ityp", 0, 3,
                              "EULUMDAT knows Ityp 0 (point source without symmetry), 1 (symmetric about the "
                              "vertical axis), 2 (linear luminaire) and 3 (point source, other symmetry)");
    e.symmetry =
        integer(3, "symmetry indicator Isym", 0, 4,
                "EULUMDAT knows Isym 0 (no symmetry), 1 (about the vertical axis), 2 (about the C0–C180 "
                "plane), 3 (about the C90–C270 plane) and 4 (about both planes)");
    e.cPlaneCount = integer(4, "number of C-planes Mc", 1, static_cast<int>(kMaxCandelaValues),
                            "Mc counts the C-planes between 0° and 360°, usually 24 or 36");
    optionalNumber(5, "distance between C-planes Dc");
    e.gammaCount = integer(6, "number of intensities per C-plane Ng", 2, static_cast<int>(kMaxCandelaValues),
                           "Ng counts the γ angles of each C-plane, usually 19 or 37");
    optionalNumber(7, "distance between γ angles Dg");
    e.reportNumber = std::string(text(8, "measurement report number"));
    e.luminaireName = std::string(text(9, "luminaire name"));
    e.luminaireNumber = std::string(text(10, "luminaire number"));
    e.fileName = std::string(text(11, "file name"));
    e.dateUser = std::string(text(12, "date/user"));
    const double lengthMm = optionalNumber(13, "length or diameter of the luminaire (mm)");
    const double widthMm = optionalNumber(14, "width of the luminaire (mm)");
    const double heightMm = optionalNumber(15, "height of the luminaire (mm)");
    for (int n = 16; n <= 21; ++n) optionalNumber(n, "a dimension of the luminous area (mm)");
    e.downwardFluxFractionPercent = optionalNumber(22, "downward flux fraction DFF (%)");
    e.lightOutputRatioPercent = number(23, "light output ratio LORL (%)");
    if (!(e.lightOutputRatioPercent >= 0.0 && e.lightOutputRatioPercent <= 100.5)) {
      fail(23,
           "light output ratio LORL is " + formatNumber(e.lightOutputRatioPercent) + " %; it must be in [0, 100] %",
           "LORL is the luminaire's flux as a percentage of its lamps' (100 for absolute photometry; 0 when "
           "not stated)");
    }
    e.conversionFactor = number(24, "conversion factor for luminous intensities");
    if (!(e.conversionFactor > 0.0)) {
      fail(24, "conversion factor for luminous intensities must be positive, not " + formatNumber(e.conversionFactor),
           "EULUMDAT writes 1 where no factor applies");
    }
    e.tiltDeg = optionalNumber(25, "tilt of the luminaire during measurement (°)");
    const int sets =
        integer(26, "number of lamp sets n", 1, kMaxLampSets,
                "every file gives at least one lamp set (lines 26a–26f), the one its intensities "
                "refer to");
    readLampSets(e, sets);
    const int dr = 27 + 6 * sets;  // first direct ratio
    for (int k = 0; k < 10; ++k)
      e.directRatios[static_cast<size_t>(k)] = optionalNumber(dr + k, "direct ratio");
    tokenize(dr + 10);
    readDistribution(e, lengthMm, widthMm, heightMm);
    return e;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& message, std::string_view hint) const {
    SourceLocation location;
    location.file = file_;
    location.line = line;
    throw InputError(std::move(location), message, std::string(hint));
  }

  // Line `n` (1-based); a file that ends before it is truncated.
  std::string_view text(int n, const std::string& what) const {
    if (n > static_cast<int>(lines_.size())) {
      fail(static_cast<int>(lines_.size()),
           "file ends too early: after " + std::to_string(lines_.size()) + " lines, where line " +
               std::to_string(n) + " should give the " + what,
           kTruncatedHint);
    }
    return lines_[static_cast<size_t>(n - 1)];
  }

  double number(int n, const std::string& what) const {
    const std::string_view s = text(n, what);
    double v = 0.0;
    if (!parseNumber(s, v)) {
      fail(n, (s.empty() ? std::string("an empty line") : quotedExcerpt(s)) + " is not a number (the " + what + ")",
           kFixValueHint);
    }
    if (!std::isfinite(v) || std::abs(v) > 1e30) {
      fail(n, quotedExcerpt(s) + " is not a finite number (the " + what + ")", kFixValueHint);
    }
    return v;
  }

  // A number that only describes the luminaire; software leaves some of these lines blank, read as 0.
  double optionalNumber(int n, const std::string& what) const {
    return text(n, what).empty() ? 0.0 : number(n, what);
  }

  int integer(int n, const std::string& what, int lo, int hi, std::string_view hint) const {
    const double v = number(n, what);
    if (v != std::floor(v))
      fail(n, "the " + what + " must be a whole number, not " + quotedExcerpt(text(n, what)), hint);
    if (v < lo || v > hi) {
      fail(n,
           "the " + what + " is " + formatNumber(v) + "; it must be in [" + std::to_string(lo) + ", " +
               std::to_string(hi) + "]",
           hint);
    }
    return static_cast<int>(v);
  }

  // Lines 26a–26f: six groups of n lines (all lamp counts, then all types …), as the format describes them.
  // Some software writes the sets one block of six lines after another instead; that layout is read when the
  // described one fails and it does not. With one set both are the same.
  void readLampSets(Eulumdat& e, int sets) {
    try {
      readLampSets(e, sets, [sets](int field, int set) { return 27 + field * sets + set; });
    } catch (const InputError&) {
      if (sets == 1) throw;
      try {
        readLampSets(e, sets, [](int field, int set) { return 27 + set * 6 + field; });
      } catch (const InputError&) {
        readLampSets(e, sets, [sets](int field, int set) { return 27 + field * sets + set; });
      }
    }
  }

  template <class LineOf>
  void readLampSets(Eulumdat& e, int sets, const LineOf& lineOf) {
    e.lampSets.assign(static_cast<size_t>(sets), EulumdatLampSet{});
    for (int s = 0; s < sets; ++s) {
      EulumdatLampSet& l = e.lampSets[static_cast<size_t>(s)];
      const std::string which = sets > 1 ? " of lamp set " + std::to_string(s + 1) : "";
      const int countLine = lineOf(0, s);
      const double count = number(countLine, "number of lamps" + which);
      if (count != std::floor(count) || count == 0.0 || std::abs(count) > 1e6) {
        fail(countLine,
             "the number of lamps" + which + " is " + quotedExcerpt(text(countLine, "")) +
                 "; it must be a whole number other than 0",
             "a negative number (e.g. -1) marks absolute photometry, as for LED luminaires");
      }
      l.count = static_cast<int>(count);
      l.type = std::string(text(lineOf(1, s), "type of lamps" + which));
      const int fluxLine = lineOf(2, s);
      if (s == 0) fluxLine_ = fluxLine;
      l.totalFluxLm = number(fluxLine, "total luminous flux of the lamps" + which + " (lm)");
      if (s == 0 && !(l.totalFluxLm != 0.0)) {
        fail(fluxLine, "the total luminous flux of the lamps is 0 lm",
             "the intensities are given per 1000 lm of this flux: give the lamps' rated flux in lm (for "
             "absolute photometry the luminaire's)");
      }
      l.colourTemperature = std::string(text(lineOf(3, s), "colour temperature of the lamps" + which));
      l.colourRendering = std::string(text(lineOf(4, s), "colour rendering of the lamps" + which));
      l.watts = optionalNumber(lineOf(5, s), "wattage of the lamps" + which + " (W)");
      if (l.watts < 0.0) {
        fail(lineOf(5, s), "the wattage" + which + " is negative (" + formatNumber(l.watts) + ")", kFixValueHint);
      }
    }
  }

  // Lines from `first` on: C angles, γ angles and intensities, separated by line breaks (one value a line, as
  // files are written) or blanks (several a line, as some software writes them).
  void tokenize(int first) {
    for (size_t i = static_cast<size_t>(first - 1); i < lines_.size(); ++i) {
      const std::string_view line = lines_[i];
      size_t p = 0;
      while (p < line.size()) {
        while (p < line.size() && (line[p] == ' ' || line[p] == '\t')) ++p;
        const size_t start = p;
        while (p < line.size() && line[p] != ' ' && line[p] != '\t') ++p;
        if (p > start) tokens_.push_back({line.substr(start, p - start), static_cast<int>(i + 1)});
      }
    }
    firstTailLine_ = first;
  }

  double tokenNumber(const Token& t, const std::string& what) const {
    double v = 0.0;
    if (!parseNumber(t.text, v))
      fail(t.line, quotedExcerpt(t.text) + " is not a number (" + what + ")", kFixValueHint);
    if (!std::isfinite(v) || std::abs(v) > 1e30) {
      fail(t.line, quotedExcerpt(t.text) + " is not a finite number (" + what + ")", kFixValueHint);
    }
    return v;
  }

  // How many C-planes the file stores for its symmetry (Mc2 − Mc1 + 1) and the index of the first (Mc1 − 1).
  static std::pair<int, int> storedPlanes(int isym, int mc) {
    switch (isym) {
      case 1:
        return {1, 0};
      case 2:
        return {mc / 2 + 1, 0};
      case 3:
        return {mc / 2 + 1, 3 * mc / 4};
      case 4:
        return {mc / 4 + 1, 0};
      default:
        return {mc, 0};
    }
  }

  void readDistribution(Eulumdat& e, double lengthMm, double widthMm, double heightMm) {
    const int mc = e.cPlaneCount;
    const int ng = e.gammaCount;
    const int isym = e.symmetry;
    if ((isym == 2 && mc % 2 != 0) || ((isym == 3 || isym == 4) && mc % 4 != 0)) {
      fail(4,
           "Mc = " + std::to_string(mc) + " C-planes cannot be symmetric as Isym " + std::to_string(isym) +
               " (line 3) says",
           isym == 2 ? "symmetry about the C0–C180 plane needs an even number of C-planes"
                     : "symmetry about the C90–C270 plane needs a number of C-planes divisible by 4");
    }
    const auto [stored, firstStored] = storedPlanes(isym, mc);
    if (static_cast<double>(stored) * ng > kMaxCandelaValues) {
      fail(6,
           "an intensity table of " + std::to_string(stored) + " × " + std::to_string(ng) +
               " values is too large (at most " + formatNumber(kMaxCandelaValues) + ")",
           "the counts Mc and Ng are probably corrupt; export the file again");
    }
    const size_t expected = static_cast<size_t>(mc) + static_cast<size_t>(ng) +
                            static_cast<size_t>(stored) * static_cast<size_t>(ng);
    if (tokens_.size() < expected) {
      fail(static_cast<int>(lines_.size()),
           "file ends too early: expected " + std::to_string(expected) + " values from line " +
               std::to_string(firstTailLine_) + " on (" + std::to_string(mc) + " C angles, " +
               std::to_string(ng) + " γ angles, " + std::to_string(stored) + " × " + std::to_string(ng) +
               " intensities for Isym " + std::to_string(isym) + "), found " + std::to_string(tokens_.size()),
           kTruncatedHint);
    }
    if (tokens_.size() > expected) {
      const Token& t = tokens_[expected];
      fail(t.line,
           "unexpected " + quotedExcerpt(t.text) + " after the last intensity (" +
               std::to_string(tokens_.size() - expected) + " values too many)",
           "Mc (line 4), Ng (line 6) and Isym (line 3) must match the table; fix them or export the file "
           "again");
    }

    std::vector<double> c = angles(0, static_cast<size_t>(mc), "C angle");
    std::vector<double> g = angles(static_cast<size_t>(mc), static_cast<size_t>(ng), "γ angle");
    checkCAngles(c, isym, firstStored, stored);
    checkGammaAngles(g, static_cast<size_t>(mc));

    // Stored planes in file order, intensities in cd.
    const double lampFluxLm = std::abs(e.lampSets.front().totalFluxLm);
    const double scale = lampFluxLm / 1000.0 * e.conversionFactor;
    std::vector<std::vector<double>> planes(static_cast<size_t>(stored),
                                            std::vector<double>(static_cast<size_t>(ng)));
    std::vector<double> planeDeg(static_cast<size_t>(stored));
    const Token* t = tokens_.data() + mc + ng;
    for (int p = 0; p < stored; ++p) {
      const double cDeg = c[static_cast<size_t>((firstStored + p) % mc)];
      // Isym 3 stores C270° … 345°, 0° … 90°: as −90° … 90°, ascending.
      planeDeg[static_cast<size_t>(p)] = (isym == 3 && cDeg >= 270.0) ? cDeg - 360.0 : cDeg;
      for (int k = 0; k < ng; ++k, ++t) {
        const auto where = [&] {
          return "the intensity at C = " + formatNumber(cDeg) + "°, γ = " + formatNumber(g[static_cast<size_t>(k)]) + "°";
        };
        const double raw = tokenNumber(*t, where());
        if (raw < 0.0) {
          fail(t->line, "negative intensity " + formatNumber(raw) + " cd/klm (" + where() + ")",
               "luminous intensity cannot be negative; export the file again");
        }
        const double cd = raw * scale;
        if (cd > kMaxCandela) {
          fail(t->line,
               "intensity " + formatNumber(cd) + " cd (" + where() + ", after × " + formatNumber(lampFluxLm) +
                   " lm / 1000 × the conversion factor) exceeds " + formatNumber(kMaxCandela) + " cd",
               "no luminaire is this bright; check the lamp flux (line " + std::to_string(fluxLine_) +
                   ") and the conversion factor (line 24)");
        }
        planes[static_cast<size_t>(p)][static_cast<size_t>(k)] = cd;
      }
    }

    IesProfile& prof = e.profile;
    prof.format = IesFormat::kEulumdat;
    prof.type = PhotometryType::kC;
    prof.verticalDeg = g;
    prof.lampLumens = lampFluxLm;
    prof.inputWatts = e.lampSets.front().watts;
    prof.lengthM = lengthMm / 1000.0;
    prof.widthM = widthMm / 1000.0;
    prof.heightM = heightMm / 1000.0;
    const auto keyword = [&](const char* key, const std::string& value) {
      if (!value.empty()) prof.keywords.push_back(std::string(key) + " " + value);
    };
    keyword("[MANUFAC]", e.company);
    keyword("[TEST]", e.reportNumber);
    keyword("[LUMINAIRE]", e.luminaireName);
    keyword("[LUMCAT]", e.luminaireNumber);
    keyword("[ISSUEDATE]", e.dateUser);
    keyword("[LAMP]", e.lampSets.front().type);
    if (isym == 1) {
      prof.horizontalDeg = {0.0};
      prof.candela = {planes.front()};
      return;
    }
    prof.horizontalDeg = c;
    prof.horizontalDeg.push_back(360.0);
    prof.candela.reserve(prof.horizontalDeg.size());
    for (const double f : prof.horizontalDeg) {
      prof.candela.push_back(planeAt(mirrored(f, isym), planeDeg, planes));
    }
  }

  std::vector<double> angles(size_t first, size_t n, const std::string& kind) const {
    std::vector<double> a(n);
    for (size_t i = 0; i < n; ++i) {
      const Token& t = tokens_[first + i];
      a[i] = tokenNumber(t, kind + " " + std::to_string(i + 1) + " of " + std::to_string(n));
      if (i > 0 && !(a[i] > a[i - 1])) {
        fail(t.line, kind + "s are not increasing: " + formatNumber(a[i]) + "° follows " + formatNumber(a[i - 1]) + "°",
             "EULUMDAT lists angles from 0° upwards, each once; fix the list or its count");
      }
    }
    return a;
  }

  // The C angles start at 0°, stay below 360°, and the planes the symmetry stores end where it says.
  void checkCAngles(std::vector<double>& c, int isym, int firstStored, int stored) const {
    const int mc = static_cast<int>(c.size());
    const auto tokenLine = [&](int i) { return tokens_[static_cast<size_t>(i)].line; };
    const auto snapTo = [&](int i, double value) {
      if (std::abs(c[static_cast<size_t>(i)] - value) > kAngleSnapDeg) return false;
      c[static_cast<size_t>(i)] = value;
      return true;
    };
    if (!snapTo(0, 0.0)) {
      fail(tokenLine(0), "the first C angle is " + formatNumber(c.front()) + "°; EULUMDAT's C angles begin at 0°",
           "list the C-planes from 0° upwards");
    }
    if (!(c.back() < 360.0 - kAngleSnapDeg)) {
      fail(tokenLine(mc - 1), "the last C angle is " + formatNumber(c.back()) + "°; C angles stay below 360°",
           "C = 360° is the plane C = 0° again; leave it out and fix Mc (line 4)");
    }
    const auto require = [&](int i, double value) {
      if (snapTo(i, value)) return;
      fail(tokenLine(i),
           "Isym " + std::to_string(isym) + " stores the C-planes " +
               (isym == 2   ? "0°–180°"
                : isym == 3 ? "270°–360°–90°"
                            : "0°–90°") +
               ", but C angle " + std::to_string(i + 1) + " of " + std::to_string(mc) + ", where they " +
               (value == 270.0 ? "begin" : "end") + ", is " + formatNumber(c[static_cast<size_t>(i)]) + "°, not " +
               formatNumber(value) + "°",
           "the C angles must be symmetric as Isym (line 3) says; fix Isym or the angles");
    };
    if (isym == 2) require(stored - 1, 180.0);
    if (isym == 3) {
      require(firstStored, 270.0);
      require(mc / 4, 90.0);
    }
    if (isym == 4) require(stored - 1, 90.0);
  }

  // γ within 0° (nadir) … 180° (zenith); usually 0°–180°, 0°–90° for downlights or 90°–180° for uplights. A
  // file may end its γ angles early (a spotlight's at 140°): beyond them the intensity is 0, as IesProfile
  // reads any direction outside its angles. `first` is the index of the first γ angle among the tokens.
  void checkGammaAngles(std::vector<double>& g, size_t first) const {
    for (const size_t i : {size_t{0}, g.size() - 1}) {
      for (const double snap : {0.0, 90.0, 180.0}) {
        if (std::abs(g[i] - snap) <= kAngleSnapDeg) g[i] = snap;
      }
      if (!(g[i] >= 0.0 && g[i] <= 180.0)) {
        fail(tokens_[first + i].line,
             std::string(i == 0 ? "the first" : "the last") + " γ angle is " + formatNumber(g[i]) +
                 "°; γ angles lie in [0°, 180°] (0° straight down, 180° straight up)",
             "fix the γ angles or their count Ng (line 6)");
      }
    }
  }

  // The stored plane's angle coordinate whose intensities the plane at C = f (degrees, 0–360) repeats.
  static double mirrored(double f, int isym) {
    switch (isym) {
      case 2:
        return f <= 180.0 ? f : 360.0 - f;  // mirror about the C0–C180 plane
      case 3: {                             // mirror about the C90–C270 plane, in −90° … 90°
        const double u = f > 180.0 ? f - 360.0 : f;
        return u > 90.0 ? 180.0 - u : u < -90.0 ? -180.0 - u : u;
      }
      case 4: {  // mirror about both planes, into 0° … 90°
        const double m = std::fmod(f, 180.0);
        return m > 90.0 ? 180.0 - m : m;
      }
      default:
        return f >= 360.0 ? 0.0 : f;
    }
  }

  // The intensities at stored angle `m`: the stored plane there, or the linear interpolation of its
  // neighbours where the angles are not spaced symmetrically.
  static std::vector<double> planeAt(double m, const std::vector<double>& planeDeg,
                                     const std::vector<std::vector<double>>& planes) {
    const auto upper = std::lower_bound(planeDeg.begin(), planeDeg.end(), m - kAngleSnapDeg);
    const size_t i = static_cast<size_t>(upper - planeDeg.begin());
    if (i < planeDeg.size() && std::abs(planeDeg[i] - m) <= kAngleSnapDeg) return planes[i];
    if (i == 0) return planes.front();
    if (i == planeDeg.size()) return planes.back();
    const double t = (m - planeDeg[i - 1]) / (planeDeg[i] - planeDeg[i - 1]);
    std::vector<double> r(planes[i].size());
    for (size_t k = 0; k < r.size(); ++k) r[k] = planes[i - 1][k] + t * (planes[i][k] - planes[i - 1][k]);
    return r;
  }

  const std::string& file_;
  std::vector<std::string_view> lines_;
  std::vector<Token> tokens_;
  int firstTailLine_ = 0;
  int fluxLine_ = 0;  // the first lamp set's flux
};

}  // namespace

Eulumdat parseEulumdat(std::string_view text, const std::string& fileName) {
  return Parser(text, fileName).parse();
}

Eulumdat loadEulumdat(const std::filesystem::path& path) {
  Eulumdat e = parseEulumdat(readInputFile(path, "EULUMDAT file"), path.string());
  const double integrated = e.profile.totalFluxLm();
  const double stated = e.statedLuminaireFluxLm();
  if (stated > 0.0 && std::abs(integrated - stated) > kFluxMismatchWarning * stated) {
    log::warn(path.string() + ": the intensities integrate to " + formatNumber(std::round(integrated)) +
              " lm, but lamp flux × LORL gives " + formatNumber(std::round(stated)) +
              " lm; fly uses the intensities as given (check the file's symmetry indicator and lamp flux)");
  }
  return e;
}

}  // namespace fly::sdb
