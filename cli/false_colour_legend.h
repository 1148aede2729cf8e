// The legend bar of a false-colour image (plans, perspective views): the colour map drawn row by row at each
// row's centre (cli/false_colour.h), the scale's ticks with their values, the unit above and the scale's kind
// below, drawn with cairo.
#pragma once

#include <cairo.h>

#include <string>

#include "cli/false_colour.h"

namespace fly::cli {

// Where the bar lies, pixels (x right, y down): [leftPx, leftPx + widthPx] × [topPx, bottomPx], whole pixels;
// the scale's maximum at the top.
struct LegendBox {
  double leftPx = 0.0;
  double topPx = 0.0;
  double widthPx = 0.0;
  double bottomPx = 0.0;

  // The bar's row (y, pixels) of scale fraction t ∈ [0, 1].
  double y(double t) const { return bottomPx - t * (bottomPx - topPx); }
};

// Draws the legend; sizes of text and marks in units of `unitPx` pixels (1/1200 of the image's width).
void drawFalseColourLegend(cairo_t* cr, const FalseColourScale& scale, const std::string& unit,
                           const LegendBox& box, double unitPx);

}  // namespace fly::cli
