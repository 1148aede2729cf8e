// The colour of a black body (Planckian radiator) at a given temperature: Planck's law, its chromaticity
// through the CIE 1931 2° observer (base/cie1931.h) and its linear Rec.709 colour at unit luminance, the
// colour a lamp of that correlated colour temperature gets. Planckian at every temperature: the CIE daylight
// illuminants (D65 …), which lie slightly above the Planckian locus, are not used.
#pragma once

#include "base/color.h"
#include "base/math.h"

namespace fly {

// The range of colour temperatures fly accepts, K: from a candle flame's 1900 K with margin down to 1000 K,
// up to 40000 K (a clear blue sky's light); CIE 015:2018 tabulates the Planckian locus over this range too.
inline constexpr double kMinColourTemperatureK = 1000.0;
inline constexpr double kMaxColourTemperatureK = 40000.0;

// The second radiation constant c₂ = hc/k in m·K (CODATA 2018, exact from h, c and k).
inline constexpr double kPlanckC2MK = 1.438776877e-2;

// Spectral radiance of a black body, Planck's law L(λ, T) = 2hc²/λ⁵ / (exp(c₂/(λT)) − 1), in
// W·m⁻²·sr⁻¹·nm⁻¹. 0 where exp overflows (λT below about 2e-5 m·K).
double planckSpectralRadiance(double wavelengthNm, double temperatureK);

// CIE 1931 chromaticity (x, y) of a black body at `temperatureK` (> 0).
dvec2 planckianChromaticity(double temperatureK);

// Linear Rec.709 colour of a black body at `temperatureK` in [kMinColourTemperatureK,
// kMaxColourTemperatureK], scaled to luminance(c) = 1. Below about 1900 K the Planckian locus leaves the
// Rec.709 gamut (blue < 0): the colour is then desaturated towards white (1, 1, 1) at constant luminance,
// just enough to bring every channel to ≥ 0 (at 1000 K by 8 %).
Rgb planckianRec709(double temperatureK);

}  // namespace fly
