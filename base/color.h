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

// sRGB transfer function (IEC 61966-2-1): encoded value in [0,1] → linear.
inline float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}
inline Rgb srgbToLinear(const Rgb& c) { return {srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b)}; }

// Largest component, e.g. to check a reflectance colour stays within [0,1].
inline float maxComponent(const Rgb& c) { return std::max({c.r, c.g, c.b}); }

}  // namespace fly
