// A clear sky whose colour follows the sun: Preetham, Shirley & Smits, "A practical analytic model for
// daylight", SIGGRAPH 1999 (appendix A.2). Luminance Y and chromaticity x, y each follow a Perez-form
// distribution F(θ, γ) = (1 + A·e^{B / cos θ})·(1 + C·e^{Dγ} + E·cos²γ) with coefficients linear in the
// turbidity T, scaled by zenith values: Y = Yz·F_Y(θ, γ)/F_Y(0, θs), likewise x and y. Yz (T, θs) is
// Preetham's zenith luminance in kcd/m², multiplied by 1000 here to give cd/m²; xyY is converted to linear
// Rec.709 RGB (sky.h, rec709FromChromaticity).
//
// Valid range: turbidity [kMinTurbidity, kMaxTurbidity] = [1.7, 10] (InputError outside; below 1.7 F_Y turns
// negative at the zenith), sun zenith angle 0..90°. Preetham's absolute luminance is high at low sun and at
// low turbidity (e.g. T = 3: diffuse horizontal illuminance ≈ 32 klx with the sun at 22° from the zenith,
// ≈ 8.8 klx with the sun on the horizon, where clear skies give 410–585 lx by the AMS Glossary cited below);
// pass a measured diffuse horizontal illuminance to use the model's distribution and colour only.
//
// Twilight and night (sun below the horizon, elevation h < 0, depression δ = −h): the distribution and colour
// are Preetham's with the sun placed on the horizon at its azimuth; its diffuse horizontal illuminance E
// falls log-linearly in δ from the model's value at sunset through the clear-sky twilight illuminances of the
// AMS Glossary of Meteorology (2nd ed., "civil twilight", "astronomical twilight"): ≈ 3 lx at the end of
// civil twilight (δ = 6°) and ≈ 0.008 lx at the end of nautical twilight (δ = 12°), and on at that rate (0.43
// decades per degree). To that is added, at every sun position, the natural moonless night sky:
// 1.7·10⁻⁴ cd/m² (22 mag/arcsec² in V; Falchi et al., "The new world atlas of artificial night sky
// brightness", Science Advances 2 (2016) e1600377), uniform, in a bluish white (x, y) = (0.25, 0.25): a
// rendering choice for how night looks to scotopic vision, not a measured colour. The sky thus darkens
// monotonically with depression, is never negative and never NaN.
#pragma once

#include <optional>

#include "sunsky/sky.h"

namespace fly::sunsky {

// Luminance of the natural moonless night sky, cd/m² (see above).
inline constexpr double kNightSkyLuminanceCdM2 = 1.7e-4;

// Where the absolute level of a clear sky comes from when no diffuse horizontal illuminance is given.
enum class ClearSkyLevel {
  // Preetham et al.'s zenith luminance Yz(T, θs). It overestimates measured clear skies about twofold (sky
  // alone ≈ 32 klx at T = 3, sun zenith 22°; ≈ 8.8 klx at sunset, where 0.4–0.6 klx are measured).
  kPreetham,
  // The clear-sky diffuse horizontal illuminance of the IES Lighting Handbook (9th ed., ch. 8 "Daylighting",
  // daylight availability): Dv = 0.8 + 15.5·√(sin α) klx for solar elevation α ≥ 0, so 0.8 klx at sunset.
  // Preetham's distribution keeps the shape and colour; below the horizon twilight fades from 0.8 klx.
  kIesHandbook,
};

// The factor by which twilight scales a sky whose diffuse horizontal illuminance at sunset is sunsetLux
// (> 3 lx) at solar depression depressionDeg > 0: log-linear through sunsetLux (0°), 3 lx (6°) and 0.008 lx
// (12°), extrapolated beyond (see above).
double twilightFactor(double sunsetLux, double depressionDeg);

// The moonless night sky's radiance: kNightSkyLuminanceCdM2 in its bluish white (see above).
Rgb nightSkyRadianceCdM2();

// The IES Lighting Handbook's clear-sky diffuse horizontal illuminance (above), lux, for a solar elevation
// in degrees (clamped to [0, 90]).
double iesClearSkyDiffuseLux(double sunElevationDeg);

class ClearSky final : public Sky {
 public:
  Rgb radianceCdM2(const dvec3& dirEnu) const override;
  // The sun as given, or placed on the horizon at its azimuth when it is below it.
  dvec3 sunDirEnu() const override { return modelSunDir_; }

  double turbidity() const { return turbidity_; }

  // Perez-form coefficients A..E and zenith value of one quantity (Y in cd/m², x, y).
  struct Distribution {
    double a, b, c, d, e;
    double zenithValue;
    double inverseZenithF;  // 1 / F(0, θs)
  };

 private:
  friend ClearSky makeClearSky(double, double, double, std::optional<double>, ClearSkyLevel);
  ClearSky(double turbidity, double sunZenithDeg, double sunAzimuthDeg);

  double turbidity_;
  dvec3 modelSunDir_;
  Distribution luminance_, chromaX_, chromaY_;
  double daylightScale_ = 1.0;  // twilight fade × normalisation, applied to Preetham's part
  double nightScale_ = 1.0;     // normalisation, applied to the night sky
  Rgb nightRadiance_;           // kNightSkyLuminanceCdM2 with the night chromaticity
};

// A clear sky of turbidity `turbidity` ([1.7, 10]) for the sun at apparent zenith angle sunZenithDeg
// ([0, 180]; beyond 90° the twilight and night sky described above) and azimuth sunAzimuthDeg (degrees
// clockwise from north). With diffuseHorizontalLux (finite, ≥ 0) the whole sky is scaled so that
// ∫ L cos θ dω equals it; without, the level is `level`'s, in cd/m².
// InputError for an input out of range.
ClearSky makeClearSky(double turbidity, double sunZenithDeg, double sunAzimuthDeg,
                      std::optional<double> diffuseHorizontalLux = std::nullopt,
                      ClearSkyLevel level = ClearSkyLevel::kPreetham);

}  // namespace fly::sunsky
