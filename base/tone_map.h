// Tone mapping on the CPU for previews the CLI writes (sky images, diagrams): luminance in cd/m² stays linear
// until this last step. Exposure follows the photographic EV100 convention of Lagarde & de Rousiers, "Moving
// Frostbite to Physically Based Rendering" (SIGGRAPH 2014 course notes, §5.1): a luminance L is displayed as
// L / Lmax with Lmax = 1.2 · 2^EV100 (saturation-based sensitivity, ISO 12232).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "base/color.h"

namespace fly {

enum class ToneOperator {
  kLinear,    // clip at 1
  kReinhard,  // x / (1 + x) (Reinhard et al. 2002, eq. 3)
};

// EV100 that maps the scene's log-average luminance to middle grey: EV100 = log2(Lavg · S / K) with S = 100 and
// the reflected-light meter calibration K = 12.5 (ISO 2720; Lagarde & de Rousiers eq. 70). Lavg is the
// geometric mean of the luminances between the 5th and 95th percentiles, so a tiny bright sun disc or a few
// black pixels do not swing it. Values ≤ 0 or non-finite are ignored; with none left, EV100 = 0.
double autoExposureEv100(std::span<const float> luminanceCdM2);

// Display value in [0,1] for a linear colour (cd/m²) at exposure EV100, before sRGB encoding.
Rgb toneMap(const Rgb& radianceCdM2, double ev100, ToneOperator op);

// sRGB-encoded 8-bit value of a display value in [0,1] (IEC 61966-2-1), rounded.
uint8_t encodeSrgb8(float displayValue);

// Tone-maps linear RGB pixels (3 floats each, cd/m²) to sRGB-encoded RGB8.
std::vector<uint8_t> toneMapToSrgb8(std::span<const float> rgb, double ev100, ToneOperator op);

}  // namespace fly
