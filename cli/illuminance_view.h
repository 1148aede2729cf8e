// `fly render BAKED --false-colour lux`: a perspective view of the illuminance a bake's light maps hold, in
// false colour with a legend in lux — what lands on each visible surface, not its luminance.
//
// How: the vertex light maps and light textures hold irradiance E (lux, per channel); the GL engine's
// light-map mode shows L = albedo · E / π + emission (raster/renderer.h). Rendered with every surface a white
// Lambertian reflector (albedo 1, no textures, no reflection) that emits a marker luminance of
// kIlluminanceMarkerCdM2, and clear glass made fully transparent (so that it neither dims nor hides what lies
// behind it), under no sky and no sun, a pixel's luminance is E/π + marker on a surface and 0 where the view
// sees nothing: E = π·(Y − marker), Y the pixel's luminance. Alpha cut-outs (leaves) lose their texture and
// show as solid cards.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "base/png_metadata.h"
#include "cli/false_colour.h"
#include "cli/false_colour_legend.h"
#include "sdb/scene.h"

namespace fly::cli {

// The marker luminance of every surface, cd/m²: far below any lit surface's E/π, far above 0.
inline constexpr float kIlluminanceMarkerCdM2 = 1e-3f;

// Prepares `scene` as above: two materials added (white, clear pane), every mesh given one of them, the sky
// and the sun turned off.
void showIlluminance(sdb::Scene& scene);

// Per pixel, lux from the rendered linear RGB (3 floats a pixel, cd/m²): π·(Y − marker), NaN where nothing is
// seen (Y below half the marker), never negative.
std::vector<double> illuminanceFromRender(std::span<const float> rgb);

struct IlluminanceView {
  int widthPx = 0;  // the render's size; the image adds a legend column to its right
  int heightPx = 0;
  std::vector<double> lux;  // widthPx · heightPx, rows from the top; NaN = nothing seen (drawn white)
  FalseColourScale scale;
  PngMetadata metadata;
};

// Where the legend bar lies in the image of a render widthPx × heightPx: in a column 16 % of the render's
// width (at least 160 pixels) to its right.
LegendBox illuminanceLegendBox(int widthPx, int heightPx);

// Writes the view with its legend as an RGB PNG, atomically. std::invalid_argument for a size that does not
// match, std::runtime_error when drawing or writing fails.
void drawIlluminanceView(const IlluminanceView& view, const std::filesystem::path& pngOut);

}  // namespace fly::cli
