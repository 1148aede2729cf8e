#include "cli/false_colour_legend.h"

#include <cstdint>
#include <cstdio>
#include <memory>

namespace fly::cli {

namespace {

void text(cairo_t* cr, const std::string& s, double x, double y, double sizePx, bool bold) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, sizePx);
  cairo_font_extents_t f;
  cairo_font_extents(cr, &f);
  cairo_move_to(cr, x, y + 0.5 * (f.ascent - f.descent));
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_show_text(cr, s.c_str());
}

}  // namespace

void drawFalseColourLegend(cairo_t* cr, const FalseColourScale& scale, const std::string& unit,
                           const LegendBox& box, double u) {
  const int width = int(box.widthPx), top = int(box.topPx), bottom = int(box.bottomPx);
  const std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> bar(
      cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, bottom - top), &cairo_surface_destroy);
  cairo_surface_flush(bar.get());
  unsigned char* data = cairo_image_surface_get_data(bar.get());
  const int stride = cairo_image_surface_get_stride(bar.get());
  for (int y = top; y < bottom; ++y) {
    const Rgb8 c = falseColour((box.bottomPx - (y + 0.5)) / (box.bottomPx - box.topPx));
    auto* row = reinterpret_cast<uint32_t*>(data + (y - top) * stride);
    for (int x = 0; x < width; ++x) {
      row[x] = 0xFF000000u | uint32_t(c.r) << 16 | uint32_t(c.g) << 8 | uint32_t(c.b);
    }
  }
  cairo_surface_mark_dirty(bar.get());
  cairo_set_source_surface(cr, bar.get(), box.leftPx, box.topPx);
  cairo_paint(cr);
  cairo_rectangle(cr, box.leftPx - 0.5, box.topPx - 0.5, width + 1.0, bottom - top + 1.0);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);

  const double right = box.leftPx + width;
  for (const double tick : scale.ticks()) {
    const double y = box.y(scale.fraction(tick));
    cairo_move_to(cr, right, y);
    cairo_line_to(cr, right + 8.0 * u, y);
    char label[32];
    std::snprintf(label, sizeof label, "%g", tick);
    text(cr, label, right + 13.0 * u, y, 14.0 * u, false);
  }
  cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
  cairo_set_line_width(cr, 1.3 * u);
  cairo_stroke(cr);
  text(cr, unit, box.leftPx, box.topPx - 20.0 * u, 16.0 * u, true);
  text(cr, scale.logarithmic ? "log scale" : "linear scale", box.leftPx, box.bottomPx + 20.0 * u, 13.0 * u,
       false);
}

}  // namespace fly::cli
