#include "cli/sun_path_diagram.h"

#include "cli/cairo_png.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/math.h"
#include "sunsky/civil_time.h"

namespace fly::cli {

namespace fs = std::filesystem;
using sunsky::UtcTime;

// Bands of the image as fractions of its size: title and subtitle above, the azimuth labels' ring around the
// horizon circle, the two caption lines below.
namespace {
constexpr double kTopBand = 0.07;
constexpr double kLabelRing = 0.045;
constexpr double kBottomBand = 0.06;
}  // namespace

glm::dvec2 SunPathLayout::pixel(double azimuthDeg, double elevationDeg) const {
  const double r = radiusPx * (90.0 - elevationDeg) / 90.0;
  const double az = degToRad(azimuthDeg);
  return centrePx + r * glm::dvec2(std::sin(az), -std::cos(az));
}

SunPathLayout sunPathLayout(int sizePx) {
  const double s = sizePx;
  const double radius = 0.5 * s * (1.0 - kTopBand - kBottomBand) - kLabelRing * s;
  return {glm::dvec2(0.5 * s, (kTopBand + kLabelRing) * s + radius), radius};
}

namespace {

struct SkyPoint {
  double azimuthDeg = 0.0;
  double elevationDeg = 0.0;  // apparent
};
using Track = std::vector<SkyPoint>;

struct Rgb {
  double r, g, b;
};
constexpr Rgb kWhite{1.0, 1.0, 1.0};
constexpr Rgb kInk{0.13, 0.13, 0.13};
constexpr Rgb kGrid{0.80, 0.80, 0.80};
constexpr Rgb kGridMajor{0.62, 0.62, 0.62};
constexpr Rgb kHorizon{0.30, 0.30, 0.30};
constexpr Rgb kArc{0.95, 0.58, 0.08};
constexpr Rgb kArcText{0.70, 0.36, 0.0};
constexpr Rgb kHour{0.16, 0.36, 0.76};
constexpr Rgb kMarker{kSunPathMarkerRgb[0] / 255.0, kSunPathMarkerRgb[1] / 255.0,
                      kSunPathMarkerRgb[2] / 255.0};

[[gnu::format(printf, 1, 2)]] std::string format(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  std::string out(static_cast<size_t>(std::max(n, 0)) + 1, '\0');
  std::vsnprintf(out.data(), out.size(), fmt, args);
  va_end(args);
  out.pop_back();
  return out;
}

std::string formatOffset(double hours) {
  const long minutes = std::lround(hours * 60.0);
  if (minutes == 0) return "UTC";
  const long m = std::labs(minutes);
  return format("UTC%c%02ld:%02ld", minutes < 0 ? '-' : '+', m / 60, m % 60);
}

std::string formatLocalTime(const UtcTime& local) {
  std::string s =
      format("%04d-%02d-%02d %02d:%02d", local.year, local.month, local.day, local.hour, local.minute);
  const int second = static_cast<int>(local.second);
  if (second != 0) s += format(":%02d", second);
  return s;
}

bool isLeapYear(int y) {
  return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
}

// The UTC offsets a zone has in a year, from those on the 1st and 15th of each month. Standard time is the
// smallest: daylight saving moves clocks forward (Europe/Dublin's "negative DST" in tzdata gives GMT, as its
// winter clocks show).
struct ZoneOffsets {
  double standardHours = 0.0;
  double summerHours = 0.0;  // = standardHours where the zone keeps no daylight saving time
};
ZoneOffsets zoneOffsets(const std::string& zone, int year) {
  const double first = sunsky::utcOffsetHours(zone, UtcTime{year, 1, 1, 12});
  ZoneOffsets o{first, first};
  for (int month = 1; month <= 12; ++month) {
    for (const int day : {1, 15}) {
      const double offset = sunsky::utcOffsetHours(zone, UtcTime{year, month, day, 12});
      o.standardHours = std::min(o.standardHours, offset);
      o.summerHours = std::max(o.summerHours, offset);
    }
  }
  return o;
}

// Where the horizon lies between two samples, a above and b below or the reverse (linear in elevation, the
// azimuth taken the short way round).
SkyPoint horizonCrossing(const SkyPoint& a, const SkyPoint& b) {
  const double f = a.elevationDeg / (a.elevationDeg - b.elevationDeg);
  const double dAz = std::remainder(b.azimuthDeg - a.azimuthDeg, 360.0);
  return {a.azimuthDeg + f * dAz, 0.0};
}

// The pieces of a sampled track that lie above the horizon, each ending on it. A closed track (an hour line,
// a year long) joins its last sample to its first.
std::vector<Track> aboveHorizon(Track track, bool closed) {
  const auto below =
      std::find_if(track.begin(), track.end(), [](const SkyPoint& p) { return p.elevationDeg < 0; });
  if (closed) {
    if (below == track.end()) {
      track.push_back(track.front());
      return {track};
    }
    std::rotate(track.begin(), below, track.end());  // start below the horizon, so no piece wraps round
    track.push_back(track.front());
  }
  std::vector<Track> pieces;
  Track piece;
  for (size_t i = 0; i < track.size(); ++i) {
    const SkyPoint& p = track[i];
    if (p.elevationDeg >= 0) {
      if (piece.empty() && i > 0) piece.push_back(horizonCrossing(track[i - 1], p));
      piece.push_back(p);
    } else if (!piece.empty()) {
      piece.push_back(horizonCrossing(track[i - 1], p));
      pieces.push_back(std::move(piece));
      piece.clear();
    }
  }
  if (!piece.empty()) pieces.push_back(std::move(piece));
  return pieces;
}

// Cairo drawing in the diagram's layout; sizes are given in units of 1/1200 of the image size (1 px at the
// default size), so the diagram looks the same at every size.
class Painter {
 public:
  Painter(cairo_t* cr, int sizePx) : cr_(cr), layout_(sunPathLayout(sizePx)), unit_(sizePx / 1200.0) {}

  const SunPathLayout& layout() const { return layout_; }
  double unit() const { return unit_; }

  void track(const Track& points, const Rgb& colour, double width) {
    for (size_t i = 0; i < points.size(); ++i) {
      const glm::dvec2 p = layout_.pixel(points[i].azimuthDeg, points[i].elevationDeg);
      if (i == 0) {
        cairo_move_to(cr_, p.x, p.y);
      } else {
        cairo_line_to(cr_, p.x, p.y);
      }
    }
    stroke(colour, width);
  }

  void line(glm::dvec2 a, glm::dvec2 b, const Rgb& colour, double width) {
    cairo_move_to(cr_, a.x, a.y);
    cairo_line_to(cr_, b.x, b.y);
    stroke(colour, width);
  }

  void circle(glm::dvec2 centre, double radius, const Rgb& colour, double width) {
    cairo_new_sub_path(cr_);
    cairo_arc(cr_, centre.x, centre.y, radius, 0.0, 2.0 * kPi);
    stroke(colour, width);
  }

  void disc(glm::dvec2 centre, double radius, const Rgb& colour) {
    cairo_new_sub_path(cr_);
    cairo_arc(cr_, centre.x, centre.y, radius, 0.0, 2.0 * kPi);
    setColour(colour);
    cairo_fill(cr_);
  }

  // Text in a white halo, so that it reads over lines. Its anchor point, `anchorX` of its width from the
  // left and vertically centred, is at `at`; it is shrunk to at most `maxWidth` units when that is given.
  struct TextStyle {
    double size = 13.0;  // units
    Rgb colour = kInk;
    bool bold = false;
    double anchorX = 0.5;
    double maxWidth = 0.0;
  };
  void text(const std::string& s, glm::dvec2 at, const TextStyle& style) {
    double width = setFont(s, style);
    if (style.maxWidth > 0.0 && width > style.maxWidth * unit_) {
      cairo_set_font_size(cr_, style.size * unit_ * style.maxWidth * unit_ / width);
      width = style.maxWidth * unit_;
    }
    cairo_move_to(cr_, at.x - style.anchorX * width, at.y + baselineOffset());
    cairo_text_path(cr_, s.c_str());
    fillText(style);
  }

  // Text set along a polyline (pixels), like a contour label: centred at arc length `centre` (moved so that
  // it fits on the line where the line is long enough), upright, each glyph turned to the line's direction,
  // and the line broken under it.
  void textAlong(const std::string& s, std::vector<glm::dvec2> line, double centre, const TextStyle& style) {
    const double width = setFont(s, style);
    std::vector<double> at = arcLengths(line);
    if (tangent(line, at, centre).x < 0.0) {  // read left to right
      std::reverse(line.begin(), line.end());
      centre = at.back() - centre;
      at = arcLengths(line);
    }
    const double start = std::clamp(centre - 0.5 * width, 0.0, std::max(0.0, at.back() - width));

    cairo_font_extents_t f;
    cairo_font_extents(cr_, &f);
    const double pad = 0.3 * style.size * unit_;
    const int steps = static_cast<int>(std::ceil((width + 2.0 * pad) / (0.5 * pad)));
    for (int i = 0; i <= steps; ++i) {
      const glm::dvec2 q = point(line, at, start - pad + i * (width + 2.0 * pad) / steps);
      if (i == 0) {
        cairo_move_to(cr_, q.x, q.y);
      } else {
        cairo_line_to(cr_, q.x, q.y);
      }
    }
    setColour(kWhite);
    cairo_set_line_width(cr_, 1.1 * (f.ascent + f.descent));
    cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
    cairo_stroke(cr_);

    cairo_glyph_t* glyphs = nullptr;
    int count = 0;
    if (cairo_scaled_font_text_to_glyphs(cairo_get_scaled_font(cr_), 0.0, 0.0, s.c_str(), -1, &glyphs, &count,
                                         nullptr, nullptr, nullptr) != CAIRO_STATUS_SUCCESS) {
      throw std::runtime_error("cairo cannot lay out the label '" + s + "'");
    }
    for (int i = 0; i < count; ++i) {
      const double advance = (i + 1 < count ? glyphs[i + 1].x : width) - glyphs[i].x;
      const double middle = start + glyphs[i].x + 0.5 * advance;
      const glm::dvec2 q = point(line, at, middle);
      const glm::dvec2 t = tangent(line, at, middle);
      cairo_save(cr_);
      cairo_translate(cr_, q.x, q.y);
      cairo_rotate(cr_, std::atan2(t.y, t.x));
      cairo_glyph_t glyph = glyphs[i];
      glyph.x = -0.5 * advance;
      glyph.y = baselineOffset();
      cairo_glyph_path(cr_, &glyph, 1);
      cairo_restore(cr_);  // the path is not part of the saved state and stays
    }
    cairo_glyph_free(glyphs);
    fillText(style);
  }

 private:
  void setColour(const Rgb& c) { cairo_set_source_rgb(cr_, c.r, c.g, c.b); }

  // Selects the style's font and returns the width of `s` in it, pixels.
  double setFont(const std::string& s, const TextStyle& style) {
    cairo_select_font_face(cr_, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                           style.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr_, style.size * unit_);
    cairo_text_extents_t e;
    cairo_text_extents(cr_, s.c_str(), &e);
    return e.x_advance;
  }
  // From the baseline to the middle of the line box (ascent above, descent below the baseline).
  double baselineOffset() {
    cairo_font_extents_t f;
    cairo_font_extents(cr_, &f);
    return 0.5 * (f.ascent - f.descent);
  }
  // Fills the current text path in a white halo.
  void fillText(const TextStyle& style) {
    setColour(kWhite);
    cairo_set_line_width(cr_, 0.3 * style.size * unit_);
    cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
    cairo_stroke_preserve(cr_);
    setColour(style.colour);
    cairo_fill(cr_);
  }

  static std::vector<double> arcLengths(const std::vector<glm::dvec2>& line) {
    std::vector<double> at(line.size(), 0.0);
    for (size_t i = 1; i < line.size(); ++i) at[i] = at[i - 1] + glm::distance(line[i - 1], line[i]);
    return at;
  }
  // The segment of `line` that holds arc length `d`: the first or last one beyond the ends.
  static size_t segmentAt(const std::vector<double>& at, double d) {
    const auto it = std::upper_bound(at.begin() + 1, at.end() - 1, d);
    return static_cast<size_t>(it - at.begin()) - 1;
  }
  static glm::dvec2 point(const std::vector<glm::dvec2>& line, const std::vector<double>& at, double d) {
    const size_t i = segmentAt(at, d);
    const double length = at[i + 1] - at[i];
    return line[i] + (length > 0.0 ? (d - at[i]) / length : 0.0) * (line[i + 1] - line[i]);
  }
  static glm::dvec2 tangent(const std::vector<glm::dvec2>& line, const std::vector<double>& at, double d) {
    const size_t i = segmentAt(at, d);
    const glm::dvec2 v = line[i + 1] - line[i];
    return glm::length(v) > 0.0 ? glm::normalize(v) : glm::dvec2(1.0, 0.0);
  }
  void stroke(const Rgb& colour, double width) {
    setColour(colour);
    cairo_set_line_width(cr_, width * unit_);
    cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
    cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
    cairo_stroke(cr_);
  }

  cairo_t* cr_;
  SunPathLayout layout_;
  double unit_;
};

void drawGrid(Painter& p, double latitudeDeg) {
  const SunPathLayout& l = p.layout();
  for (int az = 0; az < 360; az += 15) {
    p.line(l.centrePx, l.pixel(az, 0.0), az % 30 == 0 ? kGridMajor : kGrid, 1.0);
  }
  for (int el = 10; el < 90; el += 10) p.circle(l.centrePx, l.radiusPx * (90 - el) / 90.0, kGrid, 1.0);
  p.circle(l.centrePx, l.radiusPx, kHorizon, 2.0);

  // Elevation labels on the spoke towards the pole, the side the sun visits least.
  const double poleAz = latitudeDeg >= 0.0 ? 0.0 : 180.0;
  for (int el = 10; el < 90; el += 10) {
    p.text(format("%d°", el), l.pixel(poleAz, el) + glm::dvec2(5.0 * p.unit(), 0.0), {.anchorX = 0.0});
  }
  static constexpr const char* kCardinal[] = {"N", "E", "S", "W"};
  for (int az = 0; az < 360; az += 30) {
    const glm::dvec2 at = l.pixel(az, -90.0 * 26.0 * p.unit() / l.radiusPx);  // 26 units outside the horizon
    if (az % 90 == 0) {
      p.text(kCardinal[az / 90], at, {.size = 20.0, .bold = true});
    } else {
      p.text(format("%d°", az), at, {.size = 14.0});
    }
  }
}

// A text label, drawn after every line so that no line crosses it.
struct Label {
  std::string text;
  Rgb colour;
  bool bold = false;
  glm::dvec2 at{0.0};               // the centre of a straight label, pixels
  std::vector<glm::dvec2> alongPx;  // or a line to set the label along (pixels) …
  double centreAlongPx = 0.0;       // … centred at this arc length
};

// The sun's apparent position over the diagram's year, with times in the zone's local standard time.
class SunTracks {
 public:
  SunTracks(const sunsky::SpaInput& spa, int year, double standardOffset)
      : spa_(spa), year_(year), standardOffsetHours_(standardOffset) {}

  int year() const { return year_; }

  // `hours` after midnight, local standard time, on the given day; hours past 24 run into the next days.
  SkyPoint at(int month, int day, double hours) {
    spa_.utc = sunsky::addHours(UtcTime{year_, month, day}, hours - standardOffsetHours_);
    const sunsky::SunPosition s = sunsky::sunPosition(spa_);
    return {s.azimuthDeg, s.apparentElevationDeg()};
  }

 private:
  sunsky::SpaInput spa_;
  int year_;
  double standardOffsetHours_;
};

const SkyPoint& highest(const Track& track) {
  return *std::max_element(track.begin(), track.end(), [](const SkyPoint& a, const SkyPoint& b) {
    return a.elevationDeg < b.elevationDeg;
  });
}

// Day arcs: the 24 hours around local standard noon on the 21st of each month, every 4 minutes. Months of
// equal declination share a label, placed at a half hour 2 or 4 hours past transit (alternately, so that
// labels of neighbouring arcs do not meet): in the afternoon sky, clear of the crowded zenith and between two
// hour lines. Where that is below the horizon, an earlier half hour or transit itself.
void drawDayArcs(Painter& p, SunTracks& sun, std::vector<Label>& labels) {
  struct ArcLabel {
    int month;
    const char* text;
    double hoursAfterTransit;
  };
  static constexpr ArcLabel kArcLabels[] = {
      {12, "21 Dec (solstice)", 2.0},       {1, "21 Jan, 21 Nov", 4.0}, {2, "21 Feb, 21 Oct", 2.0},
      {3, "21 Mar, 21 Sep (equinox)", 4.0}, {4, "21 Apr, 21 Aug", 2.0}, {5, "21 May, 21 Jul", 4.0},
      {6, "21 Jun (solstice)", 2.0}};
  constexpr int kStepMinutes = 4;
  constexpr int kHalfSamples = 12 * 60 / kStepMinutes;
  const auto hoursOf = [](int index) { return 12.0 + (index - kHalfSamples) * kStepMinutes / 60.0; };

  for (int month = 1; month <= 12; ++month) {
    Track arc;
    for (int i = 0; i <= 2 * kHalfSamples; ++i) arc.push_back(sun.at(month, 21, hoursOf(i)));
    const bool major = month % 3 == 0;  // solstices and equinoxes
    for (const Track& piece : aboveHorizon(arc, false)) p.track(piece, kArc, major ? 3.0 : 2.0);

    const auto label = std::find_if(std::begin(kArcLabels), std::end(kArcLabels),
                                    [month](const ArcLabel& a) { return a.month == month; });
    const SkyPoint& transit = highest(arc);
    if (label == std::end(kArcLabels) || transit.elevationDeg < 0.0) continue;
    const int transitIndex = static_cast<int>(&transit - arc.data());
    int chosen = transitIndex;
    for (double after = label->hoursAfterTransit; after > 0.0; after -= 1.0) {
      const double hours = std::floor(hoursOf(transitIndex) + after) + 0.5;
      const int i =
          std::clamp(static_cast<int>(std::lround((hours - 12.0) * 60.0 / kStepMinutes)) + kHalfSamples, 1,
                     2 * kHalfSamples - 1);
      if (arc[i].elevationDeg >= 0.0) {
        chosen = i;
        break;
      }
    }
    // The label's line: the arc's samples up to 90 minutes either side, above the horizon.
    constexpr int kReach = 90 / kStepMinutes;
    int first = chosen, last = chosen;
    while (first > std::max(chosen - kReach, 0) && arc[first - 1].elevationDeg >= 0.0) --first;
    while (last < std::min(chosen + kReach, 2 * kHalfSamples) && arc[last + 1].elevationDeg >= 0.0) ++last;
    Label l{label->text, kArcText, major};
    for (int i = first; i <= last; ++i) {
      l.alongPx.push_back(p.layout().pixel(arc[i].azimuthDeg, arc[i].elevationDeg));
      if (i > first && i <= chosen) {
        l.centreAlongPx += glm::distance(l.alongPx[l.alongPx.size() - 2], l.alongPx.back());
      }
    }
    labels.push_back(std::move(l));
  }
}

// Hour lines: each whole hour of local standard time on every day of the year, a closed analemma. The label
// goes just inside its highest point (near the summer solstice), towards the zenith.
void drawHourLines(Painter& p, SunTracks& sun, std::vector<Label>& labels) {
  const int days = isLeapYear(sun.year()) ? 366 : 365;
  const SunPathLayout& layout = p.layout();
  for (int hour = 0; hour < 24; ++hour) {
    Track line;
    for (int day = 0; day < days; ++day) line.push_back(sun.at(1, 1, 24.0 * day + hour));
    for (const Track& piece : aboveHorizon(line, true)) p.track(piece, kHour, 1.5);
    const SkyPoint& top = highest(line);
    if (top.elevationDeg < 0.0) continue;
    const glm::dvec2 at = layout.pixel(top.azimuthDeg, top.elevationDeg);
    const glm::dvec2 toCentre = layout.centrePx - at;
    const double inset = 24.0 * p.unit();
    labels.push_back({format("%d", hour), kHour, true,
                      glm::length(toCentre) > 2.0 * inset ? at + inset * glm::normalize(toCentre)
                                                          : at + glm::dvec2(inset, 0.0)});
  }
}

}  // namespace

void drawSunPath(const SunPathRequest& request, const fs::path& pngOut) {
  const int size = request.sizePx;
  if (size < 300 || size > 8000) {
    throw std::invalid_argument("drawSunPath: size " + std::to_string(size) + " px is outside [300, 8000]");
  }
  const sunsky::SpaInput& spa = request.spa;
  const std::string zone = request.timeZone.empty() ? "UTC" : request.timeZone;
  const sunsky::SunPosition marked = sunsky::sunPosition(spa);  // validates the site and the instant
  const double markedOffset = sunsky::utcOffsetHours(zone, spa.utc);
  const UtcTime markedLocal = sunsky::addHours(spa.utc, markedOffset);
  const int year = markedLocal.year;
  const ZoneOffsets offsets = zoneOffsets(zone, year);

  const std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, size, size), &cairo_surface_destroy);
  const std::unique_ptr<cairo_t, decltype(&cairo_destroy)> context(cairo_create(surface.get()),
                                                                   &cairo_destroy);
  cairo_t* cr = context.get();
  cairo_set_source_rgb(cr, kWhite.r, kWhite.g, kWhite.b);
  cairo_paint(cr);
  Painter p(cr, size);
  drawGrid(p, spa.latitudeDeg);
  SunTracks sun(spa, year, offsets.standardHours);
  std::vector<Label> labels;
  drawDayArcs(p, sun, labels);
  drawHourLines(p, sun, labels);
  for (const Label& l : labels) {
    if (l.alongPx.size() >= 2) {
      p.textAlong(l.text, l.alongPx, l.centreAlongPx, {.colour = l.colour, .bold = l.bold});
    } else {
      p.text(l.text, l.at, {.colour = l.colour, .bold = l.bold});
    }
  }

  // Title, subtitle and caption, at most 1140 units wide.
  constexpr double kWidth = 1140.0;
  const double cx = 0.5 * size;
  p.text(format("Sun path  ·  %.2f° %c, %.2f° %c  ·  %s  ·  %d", std::fabs(spa.latitudeDeg),
                spa.latitudeDeg >= 0.0 ? 'N' : 'S', std::fabs(spa.longitudeDeg),
                spa.longitudeDeg >= 0.0 ? 'E' : 'W', zone.c_str(), year),
         {cx, 0.028 * size}, {.size = 26.0, .bold = true, .maxWidth = kWidth});
  p.text("Equidistant polar projection of the sky seen from above: north up, east right; apparent elevation",
         {cx, 0.058 * size}, {.size = 15.0, .maxWidth = kWidth});
  std::string hourLines = "hour lines in local standard time, " + formatOffset(offsets.standardHours);
  if (offsets.summerHours > offsets.standardHours) {
    hourLines +=
        format(" (clocks on daylight saving time, %s, read %g h later)",
               formatOffset(offsets.summerHours).c_str(), offsets.summerHours - offsets.standardHours);
  }
  p.text("Day arcs on the 21st of each month  ·  " + hourLines, {cx, 0.955 * size},
         {.size = 15.0, .maxWidth = kWidth});
  const std::string when = formatLocalTime(markedLocal) + " (" + formatOffset(markedOffset) + ")";
  const double elevation = marked.apparentElevationDeg();
  if (elevation >= 0.0) {
    p.text(format("Marked: %s  ·  elevation %.2f°  ·  azimuth %.2f°", when.c_str(), elevation,
                  marked.azimuthDeg),
           {cx, 0.983 * size}, {.size = 15.0, .bold = true, .maxWidth = kWidth});
    const glm::dvec2 at = p.layout().pixel(marked.azimuthDeg, elevation);
    const double radius = 10.0 * p.unit();
    p.text(format("%02d:%02d", markedLocal.hour, markedLocal.minute),
           at + glm::dvec2(radius + 6.0 * p.unit(), 0.0), {.size = 14.0, .bold = true, .anchorX = 0.0});
    p.disc(at, radius + 2.0 * p.unit(), kInk);
    p.disc(at, radius, kMarker);
  } else {
    p.text(format("%s: the sun is below the horizon (elevation %.2f°, azimuth %.2f°), not marked",
                  when.c_str(), elevation, marked.azimuthDeg),
           {cx, 0.983 * size}, {.size = 15.0, .bold = true, .maxWidth = kWidth});
  }

  writeCairoPng(surface.get(), cr, pngOut, "sun-path diagram", request.metadata);
}

}  // namespace fly::cli
