// The sun as a light source: a disc of 0.533° whose direct normal illuminance and colour follow from the air
// mass and the turbidity of a clear atmosphere, plus the solar constants and air mass the sky models share.
//
// Optical model (sun_disc.cpp), after Preetham, Shirley & Smits 1999 (appendix) and Iqbal 1983: the
// extraterrestrial spectrum, approximated by a black body at the Sun's effective temperature, is attenuated
// along the relative optical air mass m (Kasten & Young 1989) by Rayleigh scattering (Leckner 1978, scaled by
// station pressure), Ångström aerosol extinction with Preetham et al.'s turbidity-to-β relation and ozone
// absorption (0.35 atm-cm), then integrated against the CIE 1931 colour-matching functions (380–780 nm, 10 nm
// steps). The luminance-weighted transmittance scales the luminous solar constant; the chromaticity gives the
// colour, so the disc reddens towards the horizon. Water vapour and the oxygen A band absorb only beyond
// 690 nm, where the eye is nearly blind; they are left out.
#pragma once

#include "base/color.h"
#include "base/math.h"

namespace fly::sunsky {

// Mean angular diameter of the solar disc, degrees (32′ at 1 AU).
inline constexpr double kSunAngularDiameterDeg = 0.533;

// Solid angle of the disc, 2π·(1 − cos(kSunAngularDiameterDeg / 2)) ≈ 6.80·10⁻⁵ sr.
double sunDiscSolidAngleSr();

// Luminous solar constant: extraterrestrial normal illuminance at 1 AU, lux (Darula, Kittler & Gueymard,
// "Reference luminous solar constant and solar luminance for illuminance calculations", Solar Energy 79
// (2005) 559–565).
inline constexpr double kLuminousSolarConstantLux = 133'800.0;

// Solar constant, W/m², as used by Perez et al. 1990 for the sky brightness Δ.
inline constexpr double kSolarConstantWm2 = 1367.0;

// Eccentricity correction (r0/r)² of the extraterrestrial irradiance on day `dayOfYear` (1..366, InputError
// outside): Spencer, "Fourier series representation of the position of the sun", Search 2(5) (1971) 172.
double eccentricityCorrection(int dayOfYear);

// Relative optical air mass at apparent zenith angle zenithDeg (degrees; clamped to [0, 90], m(90°) ≈ 37.9):
// m = 1 / (cos Z + 0.50572·(96.07995° − Z)^−1.6364), Kasten & Young, "Revised optical air mass tables and
// approximation formula", Applied Optics 28(22) (1989) 4735–4738, eq. 3. Not pressure-corrected.
double relativeAirMass(double zenithDeg);

// Valid turbidity range of the clear-sky models (Preetham et al. 1999's sky and this sun), [1.7, 10]: below
// 1.7 Preetham's luminance distribution turns negative at the zenith.
inline constexpr double kMinTurbidity = 1.7;
inline constexpr double kMaxTurbidity = 10.0;

struct SunDiscInput {
  double zenithDeg = 0.0;        // apparent zenith angle, degrees, [0, 180]; > 90: below the horizon
  double azimuthDeg = 0.0;       // degrees clockwise from north, finite
  double turbidity = 3.0;        // [kMinTurbidity, kMaxTurbidity]; 2 = very clear, 3 = clear, 6+ = hazy
  double pressureHpa = 1013.25;  // station pressure, hPa, [300, 1100]; scales the Rayleigh optical depth
  int dayOfYear = 172;           // 1..366, for the Earth–Sun distance (172 = 21 June)
};

struct SunDisc {
  dvec3 dirEnu{0.0, 0.0, 1.0};  // unit vector towards the disc centre (ENU)
  // Illuminance on a surface facing the sun, lux per channel; luminance() of it is the direct normal
  // illuminance. 0 when the sun is below the horizon.
  Rgb normalIlluminanceLux{0.0f};
  // Mean radiance of the disc, cd/m² per channel: normalIlluminanceLux / sunDiscSolidAngleSr().
  Rgb radianceCdM2{0.0f};
};

// The sun through a clear atmosphere of the given turbidity. InputError for an input out of range.
SunDisc clearSkySunDisc(const SunDiscInput& in);

// The sun with a measured direct normal illuminance (lux, finite, ≥ 0; e.g. a weather file's through the
// Perez sky), coloured by the clear-atmosphere model of `in`. 0 when the sun is below the horizon.
SunDisc sunDiscWithIlluminance(const SunDiscInput& in, double directNormalLux);

}  // namespace fly::sunsky
