#include "cli/convergence_plot.h"

#include "cli/cairo_png.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "base/file_io.h"
#include "base/math.h"

namespace fly::cli {

namespace fs = std::filesystem;
using raytracer::ConvergencePoint;

namespace {

// Margins around the plot area as fractions of the image: room for the title above, tick labels and axis
// titles left and below, the legend inside.
constexpr double kLeft = 0.13, kRight = 0.04, kTop = 0.10, kBottom = 0.14;

bool plottable(const ConvergencePoint& p) {
  return p.seconds > 0.0 && std::isfinite(p.seconds) && p.relativeErrorP95 > 0.0f &&
         std::isfinite(p.relativeErrorP95);
}

// The whole decades [floor(log10 lo), ceil(log10 hi)], at least one. A value within 10⁻⁶ of a decade (in
// log10) counts as on it, so that a float error of 1 % (0.00999999977f) does not add a decade below.
void decades(double lo, double hi, double& outMin, double& outMax) {
  constexpr double kSlack = 1e-6;
  outMin = std::floor(std::log10(lo) + kSlack);
  outMax = std::max(std::ceil(std::log10(hi) - kSlack), outMin + 1.0);
}

std::string tickLabel(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

struct Painter {
  cairo_t* cr;
  double unit;  // pixels per unit of a 900-pixel-wide image

  void colour(double r, double g, double b) const { cairo_set_source_rgb(cr, r, g, b); }
  void line(glm::dvec2 a, glm::dvec2 b, double width) const {
    cairo_set_line_width(cr, width * unit);
    cairo_move_to(cr, a.x, a.y);
    cairo_line_to(cr, b.x, b.y);
    cairo_stroke(cr);
  }
  // Text with its anchor (ax, ay ∈ [0, 1] of its extent) at p, turned by `angle` radians.
  void text(const std::string& s, glm::dvec2 p, double size, double ax, double ay, double angle = 0.0) const {
    cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size * unit);
    cairo_text_extents_t e;
    cairo_text_extents(cr, s.c_str(), &e);
    cairo_save(cr);
    cairo_translate(cr, p.x, p.y);
    cairo_rotate(cr, angle);
    cairo_move_to(cr, -e.x_bearing - ax * e.width, -e.y_bearing - ay * e.height);
    cairo_show_text(cr, s.c_str());
    cairo_restore(cr);
  }
};

}  // namespace

glm::dvec2 ConvergencePlotLayout::pixel(double seconds, double relativeError) const {
  const double u = (std::log10(seconds) - log10SecondsMin) / (log10SecondsMax - log10SecondsMin);
  const double v = (std::log10(relativeError) - log10ErrorMin) / (log10ErrorMax - log10ErrorMin);
  return topLeftPx + glm::dvec2(u * sizePx.x, (1.0 - v) * sizePx.y);
}

namespace {

ConvergencePlotLayout layoutOf(std::span<const ConvergenceCurve> curves, const ConvergencePlotRequest& request) {
  ConvergencePlotLayout l;
  const double w = request.widthPx, h = request.heightPx;
  l.topLeftPx = {kLeft * w, kTop * h};
  l.sizePx = {(1.0 - kLeft - kRight) * w, (1.0 - kTop - kBottom) * h};
  double tLo = INFINITY, tHi = 0.0, eLo = INFINITY, eHi = 0.0;
  for (const ConvergenceCurve& curve : curves) {
    for (const ConvergencePoint& p : curve.history) {
      if (!plottable(p)) continue;
      tLo = std::min(tLo, p.seconds);
      tHi = std::max(tHi, p.seconds);
      eLo = std::min(eLo, double(p.relativeErrorP95));
      eHi = std::max(eHi, double(p.relativeErrorP95));
    }
  }
  if (request.targetRelativeError > 0.0f) {
    eLo = std::min(eLo, double(request.targetRelativeError));
    eHi = std::max(eHi, double(request.targetRelativeError));
  }
  if (tHi > 0.0) decades(tLo, tHi, l.log10SecondsMin, l.log10SecondsMax);
  if (eHi > 0.0) decades(eLo, eHi, l.log10ErrorMin, l.log10ErrorMax);
  return l;
}

}  // namespace

ConvergencePlotLayout convergencePlotLayout(std::span<const ConvergencePoint> history,
                                            const ConvergencePlotRequest& request) {
  const ConvergenceCurve curve{history, ""};
  return layoutOf({&curve, 1}, request);
}

void drawConvergencePlot(std::span<const ConvergencePoint> history, const fs::path& pngOut,
                         const ConvergencePlotRequest& request) {
  const ConvergenceCurve curve{history, "estimate after each pass"};
  drawConvergencePlot({&curve, 1}, "Bake convergence: estimated error against run time", pngOut, request);
}

void drawConvergencePlot(std::span<const ConvergenceCurve> curves, const std::string& title,
                         const fs::path& pngOut, const ConvergencePlotRequest& request) {
  const int w = request.widthPx, h = request.heightPx;
  if (w < 300 || w > 8000 || h < 300 || h > 8000) {
    throw std::invalid_argument("drawConvergencePlot: size " + std::to_string(w) + " × " + std::to_string(h) +
                                " px is outside [300, 8000]");
  }
  const ConvergencePlotLayout l = layoutOf(curves, request);
  const std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h), &cairo_surface_destroy);
  const std::unique_ptr<cairo_t, decltype(&cairo_destroy)> context(cairo_create(surface.get()),
                                                                   &cairo_destroy);
  cairo_t* cr = context.get();
  const Painter p{cr, w / 900.0};
  p.colour(1, 1, 1);
  cairo_paint(cr);

  const glm::dvec2 tl = l.topLeftPx, br = l.topLeftPx + l.sizePx;
  // Grid: every decade (labelled) and its 2…9 multiples.
  for (double k = l.log10SecondsMin; k <= l.log10SecondsMax; ++k) {
    for (int m = 1; m <= 9 && (m == 1 || k < l.log10SecondsMax); ++m) {
      const double x = l.pixel(m * std::pow(10.0, k), std::pow(10.0, l.log10ErrorMin)).x;
      p.colour(m == 1 ? 0.75 : 0.9, m == 1 ? 0.75 : 0.9, m == 1 ? 0.75 : 0.9);
      p.line({x, tl.y}, {x, br.y}, 1.0);
      if (m == 1) {
        p.colour(0.13, 0.13, 0.13);
        p.text(tickLabel(std::pow(10.0, k)), {x, br.y + 8 * p.unit}, 14, 0.5, 0.0);
      }
    }
  }
  for (double k = l.log10ErrorMin; k <= l.log10ErrorMax; ++k) {
    for (int m = 1; m <= 9 && (m == 1 || k < l.log10ErrorMax); ++m) {
      const double y = l.pixel(std::pow(10.0, l.log10SecondsMin), m * std::pow(10.0, k)).y;
      p.colour(m == 1 ? 0.75 : 0.9, m == 1 ? 0.75 : 0.9, m == 1 ? 0.75 : 0.9);
      p.line({tl.x, y}, {br.x, y}, 1.0);
      if (m == 1) {
        p.colour(0.13, 0.13, 0.13);
        p.text(tickLabel(100.0 * std::pow(10.0, k)), {tl.x - 8 * p.unit, y}, 14, 1.0, 0.5);
      }
    }
  }
  p.colour(0.13, 0.13, 0.13);
  cairo_set_line_width(cr, 1.5 * p.unit);
  cairo_rectangle(cr, tl.x, tl.y, l.sizePx.x, l.sizePx.y);
  cairo_stroke(cr);
  p.text(title, {0.5 * w, 0.04 * h}, 20, 0.5, 0.5);
  p.text("run time (s)", {0.5 * (tl.x + br.x), h - 0.035 * h}, 15, 0.5, 1.0);
  p.text("relative standard error, 95th percentile over vertices and texels (%)",
         {0.035 * w, 0.5 * (tl.y + br.y)}, 15, 0.5, 0.0, -0.5 * kPi);

  // The reference lines stay inside the plot area; the points lie inside it by construction, and are drawn
  // unclipped so that one on the edge (an error of exactly 1 %) shows whole, over the frame.
  cairo_save(cr);
  cairo_rectangle(cr, tl.x, tl.y, l.sizePx.x, l.sizePx.y);
  cairo_clip(cr);
  const std::span<const ConvergencePoint> history =
      curves.empty() ? std::span<const ConvergencePoint>() : curves.front().history;
  const auto first = std::find_if(history.begin(), history.end(), plottable);
  if (first != history.end()) {
    // error = e₀·√(t₀ / t): the slope −1/2 through the first point, across the whole plot.
    const double t0 = first->seconds, e0 = first->relativeErrorP95;
    const double ta = std::pow(10.0, l.log10SecondsMin), tb = std::pow(10.0, l.log10SecondsMax);
    const double dash = 6.0 * p.unit;
    cairo_set_dash(cr, &dash, 1, 0.0);
    p.colour(0.45, 0.45, 0.45);
    p.line(l.pixel(ta, e0 * std::sqrt(t0 / ta)), l.pixel(tb, e0 * std::sqrt(t0 / tb)), 1.5);
    cairo_set_dash(cr, nullptr, 0, 0.0);
  }
  if (request.targetRelativeError > 0.0f) {
    const double y = l.pixel(1.0, request.targetRelativeError).y;
    p.colour(0.80, 0.15, 0.15);
    p.line({tl.x, y}, {br.x, y}, 1.5);
  }
  cairo_restore(cr);
  for (const ConvergenceCurve& curve : curves) {
    p.colour(curve.rgb[0] / 255.0, curve.rgb[1] / 255.0, curve.rgb[2] / 255.0);
    cairo_set_line_width(cr, 2.0 * p.unit);
    bool started = false;
    for (const ConvergencePoint& q : curve.history) {
      if (!plottable(q)) continue;
      const glm::dvec2 at = l.pixel(q.seconds, q.relativeErrorP95);
      started ? cairo_line_to(cr, at.x, at.y) : cairo_move_to(cr, at.x, at.y);
      started = true;
    }
    cairo_stroke(cr);
    for (const ConvergencePoint& q : curve.history) {
      if (!plottable(q)) continue;
      const glm::dvec2 at = l.pixel(q.seconds, q.relativeErrorP95);
      cairo_new_sub_path(cr);
      cairo_arc(cr, at.x, at.y, 5.0 * p.unit, 0.0, 2.0 * kPi);
    }
    cairo_fill(cr);
  }

  // Legend, top right inside the plot: the curves, the slope, the target.
  const glm::dvec2 at = {br.x - 330 * p.unit, tl.y + 20 * p.unit};
  const double step = 22 * p.unit, swatch = 30 * p.unit;
  double row = 0.0;
  for (const ConvergenceCurve& curve : curves) {
    p.colour(curve.rgb[0] / 255.0, curve.rgb[1] / 255.0, curve.rgb[2] / 255.0);
    p.line(at + glm::dvec2(0, row), at + glm::dvec2(swatch, row), 2.0);
    p.colour(0.13, 0.13, 0.13);
    p.text(curve.label, at + glm::dvec2(swatch + 8 * p.unit, row), 13, 0.0, 0.5);
    row += step;
  }
  p.colour(0.45, 0.45, 0.45);
  const double dash = 6.0 * p.unit;
  cairo_set_dash(cr, &dash, 1, 0.0);
  p.line(at + glm::dvec2(0, row), at + glm::dvec2(swatch, row), 1.5);
  cairo_set_dash(cr, nullptr, 0, 0.0);
  p.colour(0.13, 0.13, 0.13);
  // ASCII only: without fontconfig (a bare machine) cairo falls back to a font without ∝ and √.
  p.text("slope -1/2 (error ~ 1/sqrt(time))", at + glm::dvec2(swatch + 8 * p.unit, row), 13, 0.0, 0.5);
  row += step;
  if (request.targetRelativeError > 0.0f) {
    p.colour(0.80, 0.15, 0.15);
    p.line(at + glm::dvec2(0, row), at + glm::dvec2(swatch, row), 1.5);
    p.colour(0.13, 0.13, 0.13);
    p.text("target " + tickLabel(100.0 * double(request.targetRelativeError)) + " %",
           at + glm::dvec2(swatch + 8 * p.unit, row), 13, 0.0, 0.5);
  }

  writeCairoPng(surface.get(), cr, pngOut, "convergence plot", request.metadata);
}

}  // namespace fly::cli
