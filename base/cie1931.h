// The CIE 1931 2° standard colorimetric observer: the colour-matching functions x̄(λ), ȳ(λ), z̄(λ) and the
// tristimulus values XYZ and chromaticity (x, y) of a spectral power distribution.
//
// Data: the CIE data set "Colour-matching functions of CIE 1931 standard colorimetric observer" (CIE 2019,
// DOI 10.25039/CIE.DS.xvudnb9b), sampled every 5 nm from 360 to 830 nm and rounded to 6 decimals, which is
// CIE 015:2018's abridged table. Tristimulus values are sums at 5 nm, the practice CIE 015:2018 §7.2
// recommends; the chromaticity of CIE illuminant A computed this way is (0.44757, 0.40744) against the
// published (0.44757, 0.40745).
#pragma once

#include <functional>

#include "base/math.h"

namespace fly {

inline constexpr double kCie1931FirstNm = 360.0;
inline constexpr double kCie1931LastNm = 830.0;
inline constexpr double kCie1931StepNm = 5.0;

// (x̄, ȳ, z̄) at `wavelengthNm`, interpolated linearly between the tabulated wavelengths; 0 outside
// [360, 830] nm. ȳ is the photopic luminous efficiency V(λ), 1 at 555 nm.
dvec3 cie1931ColourMatching(double wavelengthNm);

// XYZ = Σ S(λ) (x̄, ȳ, z̄)(λ) Δλ over the table's wavelengths (Δλ = 5 nm), for a spectral power distribution
// S(λ) in any unit per nanometre; the result is in that unit times nm. Multiply Y by Km = 683.002 lm/W for
// a luminous quantity when S is radiometric in W/nm.
dvec3 cie1931Tristimulus(const std::function<double(double wavelengthNm)>& spectrum);

// Chromaticity (x, y) = (X, Y) / (X + Y + Z); (0, 0) when X + Y + Z is not positive.
dvec2 chromaticity(const dvec3& xyz);

}  // namespace fly
