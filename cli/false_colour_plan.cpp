#include "cli/false_colour_plan.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "cli/cairo_png.h"
#include "cli/false_colour_legend.h"

namespace fly::cli {

namespace {

// Sizes in units of 1/1200 of the image width (1 px at 1200 px), so the plan looks alike at every size.
constexpr double kMargin = 30.0;
constexpr double kTitleBand = 86.0;
constexpr double kBottomBand = 74.0;
constexpr double kRightColumn = 230.0;
constexpr double kMaxAspect = 1.6;  // plan height / width at most

struct Extent {
  dvec2 lo{0.0};
  dvec2 hi{0.0};
};

Extent planExtent(const PlanGrid& grid, const PlanDrawing& drawing) {
  const double half = 0.5 * grid.spacingM;
  Extent e{grid.originM - half,
           grid.originM + grid.spacingM * dvec2(grid.values.columns - 1, grid.values.rows - 1) + half};
  // The outline widens the plan by at most one spacing around the grid: a section through distant geometry
  // (terrain, a neighbouring building) must not shrink the grid to a corner of the image.
  const Extent limit{e.lo - grid.spacingM, e.hi + grid.spacingM};
  for (const auto& s : drawing.outlineM) {
    for (const dvec2& p : s) {
      const dvec2 q = glm::clamp(p, limit.lo, limit.hi);
      e.lo = glm::min(e.lo, q);
      e.hi = glm::max(e.hi, q);
    }
  }
  return e;
}

// The 1-2-5 value at or below v > 0.
double niceBelow(double v) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (const double s : {5.0, 2.0, 1.0}) {
    if (s * decade <= v) return s * decade;
  }
  return decade;
}

std::string formatValue(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

class Pen {
 public:
  Pen(cairo_t* cr, double unit) : cr_(cr), unit_(unit) {}
  double unit() const { return unit_; }

  // Text with its anchor (anchorX of its width from the left, vertically centred) at `at`, shrunk to at most
  // maxWidthPx pixels wide when that is given.
  void text(const std::string& s, dvec2 at, double size, bool bold = false, double anchorX = 0.0,
            double maxWidthPx = 0.0) {
    cairo_select_font_face(cr_, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr_, size * unit_);
    cairo_text_extents_t e;
    cairo_text_extents(cr_, s.c_str(), &e);
    if (maxWidthPx > 0.0 && e.x_advance > maxWidthPx) {
      cairo_set_font_size(cr_, size * unit_ * maxWidthPx / e.x_advance);
      cairo_text_extents(cr_, s.c_str(), &e);
    }
    cairo_font_extents_t f;
    cairo_font_extents(cr_, &f);
    cairo_move_to(cr_, at.x - anchorX * e.x_advance, at.y + 0.5 * (f.ascent - f.descent));
    cairo_set_source_rgb(cr_, 0.1, 0.1, 0.1);
    cairo_show_text(cr_, s.c_str());
  }
  void segments(const std::vector<std::array<dvec2, 2>>& pixels, double width, double grey) {
    for (const auto& s : pixels) {
      cairo_move_to(cr_, s[0].x, s[0].y);
      cairo_line_to(cr_, s[1].x, s[1].y);
    }
    cairo_set_source_rgb(cr_, grey, grey, grey);
    cairo_set_line_width(cr_, width * unit_);
    cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
    cairo_stroke(cr_);
  }

 private:
  cairo_t* cr_;
  double unit_;
};

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

SurfacePtr imageSurface(int width, int height) {
  return SurfacePtr(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height), &cairo_surface_destroy);
}

void setPixel(cairo_surface_t* s, int x, int y, const Rgb8& c) {
  auto* row =
      reinterpret_cast<uint32_t*>(cairo_image_surface_get_data(s) + y * cairo_image_surface_get_stride(s));
  row[x] = 0xFF000000u | uint32_t(c.r) << 16 | uint32_t(c.g) << 8 | uint32_t(c.b);
}

// The value the plan shows at lattice coordinates (u, v): bilinear between the four sensors around it, the
// nearest sensor's where one is missing, NaN beyond half a spacing from every sensor.
double planValue(const ScalarGrid& g, double u, double v) {
  const int nc = int(std::lround(u)), nr = int(std::lround(v));
  if (nc < 0 || nr < 0 || nc >= g.columns || nr >= g.rows) return NAN;
  const double nearest = g.at(nc, nr);
  if (!std::isfinite(nearest)) return NAN;
  const int c0 = int(std::floor(u)), r0 = int(std::floor(v));
  if (c0 < 0 || r0 < 0 || c0 + 1 >= g.columns || r0 + 1 >= g.rows) return nearest;
  const double a = g.at(c0, r0), b = g.at(c0 + 1, r0), c = g.at(c0, r0 + 1), d = g.at(c0 + 1, r0 + 1);
  if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c) || !std::isfinite(d)) return nearest;
  const double fu = u - c0, fv = v - r0;
  return (1 - fv) * ((1 - fu) * a + fu * b) + fv * ((1 - fu) * c + fu * d);
}

}  // namespace

PlanLayout falseColourPlanLayout(const PlanGrid& grid, const PlanDrawing& drawing) {
  const ScalarGrid& g = grid.values;
  if (g.columns < 1 || g.rows < 1 || g.values.size() != size_t(g.columns) * size_t(g.rows) ||
      !(grid.spacingM > 0.0) || drawing.widthPx < 400 || drawing.widthPx > 20000) {
    throw std::invalid_argument(
        "falseColourPlanLayout: empty grid, spacing ≤ 0 or width outside [400, 20000]");
  }
  const double u = drawing.widthPx / 1200.0;
  const Extent e = planExtent(grid, drawing);
  const dvec2 size = e.hi - e.lo;
  PlanLayout l;
  l.widthPx = drawing.widthPx;
  const double available = drawing.widthPx - (2.0 * kMargin + kRightColumn) * u;
  l.pxPerMetre = std::min(available / size.x, kMaxAspect * available / size.y);
  l.planWidthPx = std::max(1, int(std::lround(size.x * l.pxPerMetre)));
  l.planHeightPx = std::max(1, int(std::lround(size.y * l.pxPerMetre)));
  l.planMinM = e.lo;
  l.planTopLeftPx = dvec2(std::round(kMargin * u), std::round(kTitleBand * u));
  l.legendWidthPx = std::round(36.0 * u);
  l.legendLeftPx = std::round(l.planTopLeftPx.x + available + 40.0 * u);
  l.legendTopPx = std::round(l.planTopLeftPx.y + 40.0 * u);
  const double legendHeight = std::clamp(l.planHeightPx - 200.0 * u, 300.0 * u, 700.0 * u);
  l.legendBottomPx = std::round(l.legendTopPx + legendHeight);
  l.heightPx = int(std::ceil(
      std::max(l.planTopLeftPx.y + l.planHeightPx + kBottomBand * u, l.legendBottomPx + 200.0 * u)));
  return l;
}

void drawFalseColourPlan(const PlanGrid& grid, const PlanDrawing& drawing,
                         const std::filesystem::path& pngOut) {
  const PlanLayout l = falseColourPlanLayout(grid, drawing);
  const double u = l.widthPx / 1200.0;
  const SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, l.widthPx, l.heightPx),
                           &cairo_surface_destroy);
  const std::unique_ptr<cairo_t, decltype(&cairo_destroy)> context(cairo_create(surface.get()),
                                                                   &cairo_destroy);
  cairo_t* cr = context.get();
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);
  Pen pen(cr, u);

  // The false colour, pixel by pixel, at each pixel's centre.
  const SurfacePtr plan = imageSurface(l.planWidthPx, l.planHeightPx);
  cairo_surface_flush(plan.get());
  for (int y = 0; y < l.planHeightPx; ++y) {
    for (int x = 0; x < l.planWidthPx; ++x) {
      const dvec2 m = l.planMinM + (dvec2(x, y) + 0.5) / l.pxPerMetre;
      const dvec2 lattice = (m - grid.originM) / grid.spacingM;
      const double v = planValue(grid.values, lattice.x, lattice.y);
      if (std::isfinite(v)) {
        setPixel(plan.get(), x, y, falseColour(drawing.scale.fraction(v)));
      } else {
        setPixel(plan.get(), x, y, Rgb8{255, 255, 255});
      }
    }
  }
  cairo_surface_mark_dirty(plan.get());
  cairo_set_source_surface(cr, plan.get(), l.planTopLeftPx.x, l.planTopLeftPx.y);
  cairo_paint(cr);

  // Iso-lines at the ticks (a white casing under a dark line reads on every colour), then the section.
  cairo_save(cr);
  cairo_rectangle(cr, l.planTopLeftPx.x, l.planTopLeftPx.y, l.planWidthPx, l.planHeightPx);
  cairo_clip(cr);
  std::vector<std::array<dvec2, 2>> contours;
  for (const double level : drawing.scale.ticks()) {
    // Not at the scale's ends, where a plateau of values (DF = 100 % outside) would draw its noise.
    if (level <= drawing.scale.minValue * (1.0 + 1e-9) || level >= drawing.scale.maxValue * (1.0 - 1e-9))
      continue;
    for (const auto& s : isoContours(grid.values, level)) {
      contours.push_back(
          {l.pixel(grid.originM + grid.spacingM * s[0]), l.pixel(grid.originM + grid.spacingM * s[1])});
    }
  }
  pen.segments(contours, 3.2, 1.0);
  pen.segments(contours, 1.3, 0.15);
  std::vector<std::array<dvec2, 2>> outline;
  for (const auto& s : drawing.outlineM) outline.push_back({l.pixel(s[0]), l.pixel(s[1])});
  pen.segments(outline, 2.4, 0.0);
  cairo_restore(cr);
  cairo_rectangle(cr, l.planTopLeftPx.x - 0.5, l.planTopLeftPx.y - 0.5, l.planWidthPx + 1.0,
                  l.planHeightPx + 1.0);
  cairo_set_source_rgb(cr, 0.5, 0.5, 0.5);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);

  // Title and subtitle.
  const double textWidth = l.widthPx - 2.0 * l.planTopLeftPx.x;
  pen.text(drawing.title, {l.planTopLeftPx.x, 30.0 * u}, 24.0, true, 0.0, textWidth);
  pen.text(drawing.subtitle, {l.planTopLeftPx.x, 60.0 * u}, 15.0, false, 0.0, textWidth);

  drawFalseColourLegend(cr, drawing.scale, drawing.unit,
                        {l.legendLeftPx, l.legendTopPx, l.legendWidthPx, l.legendBottomPx}, u);

  // North arrow under the legend.
  if (drawing.northPlan) {
    const dvec2 centre(l.legendLeftPx + 50.0 * u, l.legendBottomPx + 110.0 * u);
    const dvec2 n = glm::normalize(*drawing.northPlan);
    const dvec2 side(-n.y, n.x);
    const double r = 38.0 * u;
    cairo_new_sub_path(cr);
    cairo_arc(cr, centre.x, centre.y, r, 0.0, 2.0 * 3.141592653589793);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_set_line_width(cr, 1.5 * u);
    cairo_stroke(cr);
    const dvec2 tip = centre + 0.9 * r * n, tail = centre - 0.9 * r * n;
    cairo_move_to(cr, tip.x, tip.y);
    cairo_line_to(cr, tail.x + 0.4 * r * side.x, tail.y + 0.4 * r * side.y);
    cairo_line_to(cr, centre.x - 0.5 * r * n.x, centre.y - 0.5 * r * n.y);
    cairo_line_to(cr, tail.x - 0.4 * r * side.x, tail.y - 0.4 * r * side.y);
    cairo_close_path(cr);
    cairo_fill(cr);
    pen.text("N", centre + (r + 16.0 * u) * n, 18.0, true, 0.5);
  }

  // Scale bar under the plan: a 1-2-5 length of at most a quarter of the plan's width, in two halves.
  const double lengthM = niceBelow(0.25 * l.planWidthPx / l.pxPerMetre);
  const double barY = l.planTopLeftPx.y + l.planHeightPx + 30.0 * u;
  const double x0 = l.planTopLeftPx.x, x1 = x0 + lengthM * l.pxPerMetre, xm = 0.5 * (x0 + x1);
  cairo_rectangle(cr, x0, barY, xm - x0, 8.0 * u);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_fill(cr);
  cairo_rectangle(cr, x0, barY, x1 - x0, 8.0 * u);
  cairo_set_line_width(cr, 1.0 * u);
  cairo_stroke(cr);
  pen.text("0", {x0, barY + 24.0 * u}, 13.0, false, 0.5);
  pen.text(formatValue(lengthM) + " m", {x1, barY + 24.0 * u}, 13.0, false, 0.5);
  pen.text(drawing.caption, {x1 + 50.0 * u, barY + 4.0 * u}, 15.0, false, 0.0, l.widthPx - x1 - 80.0 * u);

  writeCairoPng(surface.get(), cr, pngOut, "false-colour plan", drawing.metadata);
}

}  // namespace fly::cli
