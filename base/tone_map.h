// Tone mapping: luminance in cd/m² stays linear floating point until this last step, on the CPU (previews the
// CLI writes) and in the GL engine (toneMapGlsl, generated from the same constants, so both compute the
// same). Exposure follows the photographic EV100 convention of Lagarde & de Rousiers, "Moving Frostbite to
// Physically Based Rendering" (SIGGRAPH 2014 course notes, §5.1): a luminance L is exposed as x = L / Lmax
// with Lmax = 1.2 · 2^EV100 (saturation-based sensitivity, ISO 12232); an operator maps x to a display value
// in [0,1], which is then sRGB-encoded. Operators act on each RGB channel.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "base/color.h"

namespace fly {

// The values are the `op` numbers of the GLSL function flyToneMap (toneMapGlsl).
enum class ToneOperator : int {
  kLinear = 0,    // min(x, 1)
  kReinhard = 1,  // x (1 + x / Lw²) / (1 + x), Lw = white point (Reinhard et al. 2002, eq. 4); Lw = ∞: eq. 3
  kFilmic =
      2,  // Hable's "Uncharted 2" filmic curve (see kHableFilmic), normalised so that its white maps to 1
};

// Hable, "Filmic Tonemapping Operators" (filmicworlds.com, 2010) and "Uncharted 2: HDR Lighting" (GDC 2010):
// f(x) = (x (A x + C B) + D E) / (x (A x + B) + D F) − E / F, display = f(bias · x) / f(W).
struct HableFilmicConstants {
  float a = 0.15f;  // shoulder strength
  float b = 0.50f;  // linear strength
  float c = 0.10f;  // linear angle
  float d = 0.20f;  // toe strength
  float e = 0.02f;  // toe numerator
  float f = 0.30f;  // toe denominator
  float w = 11.2f;  // linear white point: bias · x = W displays as 1
  // Calibrated as a camera's tone curve: the luminance a reflected-light meter reads as middle grey (ISO 2720,
  // K = 12.5: L = K · 2^EV100 / 100, so x = K / (100 · 1.2) = 0.1042 of Lmax) displays at 0.18 of white
  // (sRGB 0.461, 118 of 255), where a camera's JPEG shows an evenly lit 18 % grey card; Hable's bias of 2
  // would show it at 0.077 (sRGB 78), 1.3 EV darker. White is reached at x = W / bias = 2.21 (4.4 EV above
  // grey).
  float exposureBias = 5.0588f;
};
// The display value (linear, [0, 1]) of the metered middle grey under the filmic operator (above).
inline constexpr float kDisplayMiddleGrey = 0.18f;
inline constexpr HableFilmicConstants kHableFilmic{};

// Exposed values x are clamped to [0, kMaxExposedValue] before an operator; every operator is saturated there
// (Reinhard without white point: 1 − 1e-6), and no intermediate overflows a float.
inline constexpr float kMaxExposedValue = 1.0e6f;

// "linear", "reinhard" or "filmic": the operator's name as the command line and the viewer give it.
const char* toneOperatorName(ToneOperator op);

struct ToneMapSettings {
  ToneOperator op = ToneOperator::kReinhard;
  double ev100 = 0.0;  // exposure value at ISO 100; Lmax = 1.2 · 2^EV100 cd/m² is exposed as x = 1
  float whitePoint =
      4.0f;  // Reinhard: the exposed value x that maps to 1 (Reinhard 2002 eq. 4); ≤ 0 or +∞: none
};

// 1 / Lmax = 1 / (1.2 · 2^EV100), in m²/cd: the factor that turns cd/m² into exposed values (flyToneMap's
// exposureScale).
float exposureScale(double ev100);

// Display value in [0,1] per channel for a linear colour in cd/m². NaN and negative channels display as 0,
// +∞ as the operator's maximum.
Rgb toneMap(const Rgb& cdM2, const ToneMapSettings& settings);

// The same with Reinhard's eq. 3 (no white point) for kReinhard.
Rgb toneMap(const Rgb& radianceCdM2, double ev100, ToneOperator op);

// sRGB encoding (IEC 61966-2-1) of a display value, clamped to [0,1] first (NaN → 0).
float encodeSrgb(float displayValue);

// sRGB-encoded 8-bit value of a display value in [0,1], rounded.
uint8_t encodeSrgb8(float displayValue);

// Tone-maps linear RGB pixels (3 floats each, cd/m²) to sRGB-encoded RGB8.
std::vector<uint8_t> toneMapToSrgb8(std::span<const float> rgb, const ToneMapSettings& settings);
std::vector<uint8_t> toneMapToSrgb8(std::span<const float> rgb, double ev100, ToneOperator op);

// EV100 that maps the scene's log-average luminance to middle grey: EV100 = log2(Lavg · S / K) with S = 100
// and the reflected-light meter calibration K = 12.5 (ISO 2720; Lagarde & de Rousiers eq. 70). Lavg is the
// geometric mean of the luminances between the 5th and 95th percentiles (sorted). Values ≤ 0 or non-finite
// are ignored; with none left, EV100 = 0.
double autoExposureEv100(std::span<const float> luminanceCdM2);

struct AutoExposureSettings {
  // Log2 luminance range of the histogram (cd/m²: 2^-20 ≈ 1e-6, starlight is ~1e-4; 2^32 ≈ 4e9, above the
  // sun's disc at ~1.6e9); luminances outside are clamped into the first or last bin.
  float minLog2CdM2 = -20.0f;
  float maxLog2CdM2 = 32.0f;
  uint32_t binCount = 256;  // 0.2 EV per bin
  // The mean log-luminance is taken over the pixels between these fractions of the luminance-sorted pixels
  // (a trimmed mean): the darkest 10 % (black corners, shadows) and the brightest 10 % (sun disc, lamps,
  // specular highlights) do not move the exposure.
  float lowPercentile = 0.10f;
  float highPercentile = 0.90f;
  double emptyEv100 = 0.0;  // returned when no pixel has a finite luminance > 0 (Lmax = 1.2 cd/m²)
};

// EV100 = log2(Lavg · 100 / 12.5) as autoExposureEv100, with Lavg from a histogram over log2 luminance (as a
// GPU reduction would compute it) instead of a sort. Each bin keeps its pixel count and the sum of their log2
// luminances, so a uniform image of L gives exactly log2(L · 100 / 12.5); a bin cut by a percentile
// contributes its mean in proportion. Pixels ≤ 0 or non-finite are ignored.
double autoExposureEv100Histogram(std::span<const float> luminanceCdM2,
                                  const AutoExposureSettings& settings = {});

// GLSL 4.50 source (no #version line) defining
//   vec3 flyToneMap(vec3 cdM2, int op, float exposureScale, float whitePoint)  // display values in [0,1]
//   vec3 flyEncodeSrgb(vec3 displayValue)                                        // sRGB-encoded, in [0,1]
// that compute what toneMap and encodeSrgb compute: op is a ToneOperator value, exposureScale =
// exposureScale(ev100), and the constants are printed from the C++ ones above.
const char* toneMapGlsl();

}  // namespace fly
