// convergence.png: the bake's estimated error against its run time, log-log, as `fly bake` writes it. Monte
// Carlo error falls as 1/√samples, so at a steady ray rate the points follow a line of slope −1/2, drawn for
// reference through the first point; a bake that falls faster is in its quasi-Monte Carlo regime, one that
// falls slower is still finding light (caustics, small emitters).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <glm/vec2.hpp>
#include <span>
#include <string>

#include "base/png_metadata.h"
#include "raytracer/baker.h"

namespace fly::cli {

struct ConvergencePlotRequest {
  int widthPx = 900;                 // [300, 8000]
  int heightPx = 600;                // [300, 8000]
  float targetRelativeError = 0.0f;  // drawn as a horizontal line when > 0
  PngMetadata metadata;              // settings and print resolution in the file (cli/image_metadata.h)
};

// Where the plot area lies and which decades it spans. Pixel coordinates: x right, y down, (0, 0) the
// top-left corner of the top-left pixel.
struct ConvergencePlotLayout {
  glm::dvec2 topLeftPx{0.0};
  glm::dvec2 sizePx{0.0};
  double log10SecondsMin = 0.0, log10SecondsMax = 1.0;  // whole decades, left to right
  double log10ErrorMin = -3.0, log10ErrorMax = 0.0;     // whole decades, bottom to top

  // The point (seconds > 0, relative error > 0), linear in log10 of either.
  glm::dvec2 pixel(double seconds, double relativeError) const;
};

// The layout drawConvergencePlot uses: the whole decades that hold every point with seconds > 0 and error > 0
// (others cannot be drawn on log axes and are left out), and the target; at least one decade on either axis.
ConvergencePlotLayout convergencePlotLayout(std::span<const raytracer::ConvergencePoint> history,
                                            const ConvergencePlotRequest& request);

// The colour (8-bit sRGB) of the points and of the line through them.
inline constexpr std::array<uint8_t, 3> kConvergencePointRgb{31, 119, 180};

// Draws the plot and writes it as an RGB PNG, atomically. std::invalid_argument for a size out of range;
// std::runtime_error when drawing or writing fails.
void drawConvergencePlot(std::span<const raytracer::ConvergencePoint> history,
                         const std::filesystem::path& pngOut, const ConvergencePlotRequest& request = {});

// One of several bakes drawn side by side: its history, its legend entry and colour (8-bit sRGB).
struct ConvergenceCurve {
  std::span<const raytracer::ConvergencePoint> history;
  std::string label;
  std::array<uint8_t, 3> rgb = kConvergencePointRgb;
};

// The same plot with several curves on common axes (the layout spans all of them; the slope −1/2 goes
// through the first curve's first point), and `title` above: a comparison of estimators.
void drawConvergencePlot(std::span<const ConvergenceCurve> curves, const std::string& title,
                         const std::filesystem::path& pngOut, const ConvergencePlotRequest& request = {});

}  // namespace fly::cli
