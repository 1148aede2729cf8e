// The default clear sky and its sun: Hosek & Wilkie, "An Analytic Model for Full Spectral Sky-Dome Radiance"
// (SIGGRAPH 2012) and "Adding a Solar-Radiance Function to the Hosek-Wilkie Skylight Model" (IEEE CG&A 2013).
// Both were fitted to brute-force simulations of one atmosphere, so turbidity moves light between them: at a
// solar elevation of 45° the sky's diffuse horizontal illuminance rises from 14 klx (T = 2) to 54 klx (T = 9.8)
// while the sun's direct normal illuminance falls from 78 to 44 klx.
//
// Sky (eq. 9 of the 2012 paper): per CIE 1931 tristimulus channel c,
//   L_c(θ, γ) = R_c · (1 + A·e^{B/(cos θ + 0.01)}) · (C + D·e^{Eγ} + F·cos²γ + G·χ(H, γ) + I·√cos θ),
//   χ(H, γ) = (1 + cos²γ) / (1 + H² − 2H·cos γ)^{3/2},
// θ the view zenith angle, γ the angle from the sun. A..I and R_c are quintic Bézier curves in
// (elevation / 90°)^{1/3} over six control points, interpolated linearly in the turbidity (tables at 1..10)
// and the ground albedo (tables at 0 and 1); the tables are data (sunsky/hosek_wilkie_data.inc). R_c is in
// W/(m² sr) weighted by the CIE functions, so 683 lm/W · L_Y is the luminance in cd/m². A channel the fit
// drives below 0 (near the horizon at turbidity ≥ 9 and low sun) is set to 0.
//
// Sun: the solar radiance function gives the spectral radiance at the disc centre (11 bands, 320–720 nm,
// piecewise cubic in the elevation) times a fifth-order limb darkening in the cosine μ on the disc. Its direct
// normal illuminance is ∫ over the disc, i.e. L_centre(λ)·Ω·∫₀¹ ld(λ, μ)·2μ dμ, integrated against the CIE
// 1931 functions for luminance and colour. The models' disc has a radius of 0.255°; fly draws the same
// illuminance over its 0.533° disc (sun_disc.h). Both scale with the Earth–Sun distance
// (eccentricityCorrection). The simulation was at sea level: the station pressure is not used.
//
// Below the horizon the sky is the model's at elevation 0 faded through twilight as ClearSky's is
// (clear_sky.h: log-linear through 3 lx at −6° and 0.008 lx at −12°), plus the moonless night sky.
#pragma once

#include <array>
#include <optional>

#include "sunsky/sky.h"
#include "sunsky/sun_disc.h"

namespace fly::sunsky {

// Ground albedo assumed by the sky when none is given: 0.2, grass, soil and pavement (and the ground the
// GL engine draws below the horizon).
inline constexpr double kDefaultGroundAlbedo = 0.2;

class HosekWilkieSky final : public Sky {
 public:
  Rgb radianceCdM2(const dvec3& dirEnu) const override;
  // The sun as given, or placed on the horizon at its azimuth when it is below it.
  dvec3 sunDirEnu() const override { return modelSunDir_; }

  double turbidity() const { return turbidity_; }
  double groundAlbedo() const { return groundAlbedo_; }

  // The model's luminance towards `dirEnu`, cd/m², before twilight fading and normalisation and without
  // the night sky: 683·L_Y. For checking the evaluation against the model's reference implementation.
  double modelLuminanceCdM2(const dvec3& dirEnu) const;

 private:
  friend HosekWilkieSky makeHosekWilkieSky(double, double, double, double, int, std::optional<double>);
  HosekWilkieSky(double turbidity, double groundAlbedo, double sunZenithDeg, double sunAzimuthDeg);
  dvec3 modelXyz(const dvec3& dirEnu) const;  // CIE XYZ radiance, W/(m² sr)-weighted, ≥ 0 per channel

  double turbidity_, groundAlbedo_;
  dvec3 modelSunDir_;
  std::array<std::array<double, 9>, 3> parameters_{};  // A..I per channel X, Y, Z
  dvec3 channelRadiance_{0.0};                         // R_c per channel
  double daylightScale_ = 1.0;  // Earth–Sun distance × twilight fade × normalisation
  double nightScale_ = 1.0;     // normalisation, applied to the night sky
  Rgb nightRadiance_;
};

// The Hosek–Wilkie sky of turbidity `turbidity` ([kMinTurbidity, kMaxTurbidity]) and ground albedo
// `groundAlbedo` ([0, 1]) for the sun at apparent zenith angle sunZenithDeg ([0, 180]) and azimuth
// sunAzimuthDeg (degrees clockwise from north), on day `dayOfYear` (1..366, for the Earth–Sun distance).
// With diffuseHorizontalLux (finite, ≥ 0) the whole sky is scaled so that ∫ L cos θ dω equals it.
// InputError for an input out of range.
HosekWilkieSky makeHosekWilkieSky(double turbidity, double groundAlbedo, double sunZenithDeg,
                                  double sunAzimuthDeg, int dayOfYear,
                                  std::optional<double> diffuseHorizontalLux = std::nullopt);

// The sun of the Hosek–Wilkie model for `in` (its pressure is not used). 0 below the horizon.
SunDisc hosekWilkieSunDisc(const SunDiscInput& in);

}  // namespace fly::sunsky
