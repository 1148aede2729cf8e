// A false-colour plan of a quantity measured on a horizontal sensor grid (`fly illuminance --grid …
// --image plan.png`, `fly daylight-factor … --image`), as lighting designers read them: the plan seen from
// above (x to the right, −z up, so the scene's −Z "forward" is up), each pixel coloured by the value
// interpolated bilinearly between the four sensors around it (the nearest sensor's value where one of them is
// missing; white where no sensor lies within half a spacing), iso-lines at the legend's ticks inside its
// range (marching squares, cli/iso_contours.h), the scene's section at the sensors' height
// (cli/plan_section.h), a north arrow, a scale bar in metres and a legend bar with the scale's ticks
// (cli/false_colour.h).
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "base/math.h"
#include "base/png_metadata.h"
#include "cli/false_colour.h"
#include "cli/iso_contours.h"

namespace fly::cli {

// The sensors on their lattice: sample (column, row) stands at originM + spacingM·(column, row) in plan
// coordinates (x, z), metres.
struct PlanGrid {
  ScalarGrid values;  // NaN where there is no sensor
  dvec2 originM{0.0};
  double spacingM = 1.0;  // > 0
};

struct PlanDrawing {
  std::string title;     // e.g. "Illuminance, lux, 0.85 m above the floor at y = 0 m"
  std::string subtitle;  // e.g. the scene and its daylight
  std::string caption;   // below the plan, e.g. "mean 412 lx · min 88 lx · uniformity 0.21"
  std::string unit;      // the legend's unit, e.g. "lx", "%"
  FalseColourScale scale;
  std::vector<std::array<dvec2, 2>> outlineM;  // segments (x, z), metres
  // Where north points in the plan, a unit vector (x, z); none: no north arrow.
  std::optional<dvec2> northPlan;
  int widthPx = 1600;  // [400, 20000]
  PngMetadata metadata;
};

// Where things lie in the image. Pixel coordinates: x to the right, y down, (0, 0) the top-left corner of
// the top-left pixel.
struct PlanLayout {
  int widthPx = 0;
  int heightPx = 0;
  dvec2 planMinM{0.0};       // the plan's (x, z) at planTopLeftPx
  dvec2 planTopLeftPx{0.0};  // whole pixels
  int planWidthPx = 0;
  int planHeightPx = 0;
  double pxPerMetre = 1.0;
  double legendLeftPx = 0.0;  // the legend bar: [left, left + width] × [top, bottom]
  double legendWidthPx = 0.0;
  double legendTopPx = 0.0;     // the scale's maximum
  double legendBottomPx = 0.0;  // the scale's minimum

  dvec2 pixel(dvec2 planM) const { return planTopLeftPx + (planM - planMinM) * pxPerMetre; }
  // The legend bar's row (y, pixels) of scale fraction t ∈ [0, 1].
  double legendY(double t) const { return legendBottomPx - t * (legendBottomPx - legendTopPx); }
};

// The layout drawFalseColourPlan uses. std::invalid_argument for an empty grid, a spacing ≤ 0 or a width out
// of range.
PlanLayout falseColourPlanLayout(const PlanGrid& grid, const PlanDrawing& drawing);

// Draws the plan and writes it as an RGB PNG with the drawing's metadata, atomically. std::runtime_error when
// drawing or writing fails (nothing is written then).
void drawFalseColourPlan(const PlanGrid& grid, const PlanDrawing& drawing,
                         const std::filesystem::path& pngOut);

}  // namespace fly::cli
