// Colour and photometry. fly carries light as linear RGB with Rec.709 primaries, scaled so that the luminance
// Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6, item 3.3) is photometric: cd/m², lux, cd, lm.
#pragma once

#include <algorithm>
#include <cmath>

#include "base/math.h"

namespace fly {

// Linear RGB, Rec.709 primaries. Units depend on use (reflectance: 0..1; radiance: cd/m² ...).
using Rgb = vec3;

// Photometric luminance of a linear Rec.709 colour (BT.709-6; the Y row of the RGB→XYZ matrix).
inline float luminance(const Rgb& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// Linear Rec.709 RGB of CIE 1931 XYZ: the inverse of the matrix that BT.709's primaries (0.64, 0.33),
// (0.30, 0.60), (0.15, 0.06) and D65 white (0.3127, 0.3290) define, to 7 decimals, so that D65's XYZ at
// Y = 1 gives (1, 1, 1). Colours outside the gamut get negative channels.
inline dvec3 rec709FromXyz(const dvec3& xyz) {
  return {3.2404542 * xyz.x - 1.5371385 * xyz.y - 0.4985314 * xyz.z,
          -0.9692660 * xyz.x + 1.8760108 * xyz.y + 0.0415560 * xyz.z,
          0.0556434 * xyz.x - 0.2040259 * xyz.y + 1.0572252 * xyz.z};
}

// sRGB transfer function (IEC 61966-2-1): encoded value in [0,1] → linear.
inline float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}
inline Rgb srgbToLinear(const Rgb& c) { return {srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b)}; }

// Largest component, e.g. to check a reflectance colour stays within [0,1].
inline float maxComponent(const Rgb& c) { return std::max({c.r, c.g, c.b}); }

}  // namespace fly
