// The false-colour scale of illuminance and daylight-factor plans: a value range mapped linearly or
// logarithmically onto a perceptual colour map, with the legend's tick values.
//
// The colour map is D. A. Green's "cubehelix" (Bull. Astr. Soc. India 39 (2011) 289, eq. 2): a helix through
// the RGB cube around the grey diagonal whose perceived brightness rises monotonically, so that a plan reads
// correctly in grey too and every colour of the map is distinct. Parameters: start colour 0.5 (purple), −1.5
// rotations (through blue and green to yellow), hue 1.0, γ = 1; lightness λ from 0.15 to 0.92 of the helix
// (no pure black or white, so that contour lines and text stay visible on every colour).
#pragma once

#include <optional>
#include <span>
#include <vector>

namespace fly::cli {

// An 8-bit sRGB colour of the map.
struct Rgb8 {
  int r = 0, g = 0, b = 0;
};

// The map's colour at fraction t ∈ [0, 1] of the scale (clamped).
Rgb8 falseColour(double t);

struct FalseColourScale {
  double minValue = 1.0;   // bottom of the legend; > 0 when logarithmic
  double maxValue = 10.0;  // top of the legend; > minValue
  bool logarithmic = true;

  // Where `value` lies on the scale, [0, 1]: clamped below the minimum (0 and negative values on a log scale
  // included) and above the maximum.
  double fraction(double value) const;
  // The value at fraction t ∈ [0, 1].
  double valueAt(double t) const;
  // The legend's ticks and the contour levels: the 1-2-5 series (…, 1, 2, 5, 10, …) within [min, max] on a
  // log scale; on a linear scale steps of 1, 2 or 5 × 10^k, giving 4 to 10 ticks from the minimum.
  std::vector<double> ticks() const;
};

// The scale for `values` (non-finite ones ignored): `range` when given (min < max, min > 0 on a log scale),
// else the data's range widened to the 1-2-5 values around it (log: from the smallest positive value; linear:
// from 0). A data set with no positive value gets [1, 10] on a log scale, [0, 1] on a linear one.
FalseColourScale falseColourScale(std::span<const double> values, bool logarithmic,
                                  std::optional<std::pair<double, double>> range = std::nullopt);

}  // namespace fly::cli
