// The CIE standard general sky (ISO 15469:2004 / CIE S 011/E:2003, "Spatial distribution of daylight — CIE
// standard general sky"): 15 relative luminance distributions from the heavily overcast sky (type 1) to the
// turbid cloudless sky (type 15), made absolute by a zenith luminance or a diffuse horizontal illuminance.
//
// Relative luminance of a sky element at zenith angle Z and angular distance χ from the sun (sun at Zs):
//   L/Lz = f(χ)·φ(Z) / (f(Zs)·φ(0))
//   gradation  φ(Z) = 1 + a·exp(b / cos Z)            (φ = 1 at the horizon, Z = 90°)
//   indicatrix f(χ) = 1 + c·(exp(d·χ) − exp(d·π/2)) + e·cos²χ
// The sky is neutral in colour (R = G = B = L).
#pragma once

#include "sunsky/sky.h"

namespace fly::sunsky {

// The gradation (a, b) and indicatrix (c, d, e) parameters of one sky type (ISO 15469, Table 1).
struct CieSkyParameters {
  double a, b, c, d, e;
};

// Parameters of sky type 1..15; InputError for any other type.
const CieSkyParameters& cieSkyParameters(int type);

// How the relative distribution is made absolute. `value` is finite and ≥ 0 (0 gives a black sky).
struct CieNormalisation {
  enum class Kind {
    kZenithLuminance,               // value = Lz, cd/m²
    kDiffuseHorizontalIlluminance,  // value = ∫ L cos θ dω over the sky, lux
  };
  Kind kind = Kind::kDiffuseHorizontalIlluminance;
  double value = 0.0;

  static CieNormalisation zenithLuminanceCdM2(double cdM2) { return {Kind::kZenithLuminance, cdM2}; }
  static CieNormalisation diffuseHorizontalLux(double lux) {
    return {Kind::kDiffuseHorizontalIlluminance, lux};
  }
};

class CieSky final : public Sky {
 public:
  Rgb radianceCdM2(const dvec3& dirEnu) const override;
  dvec3 sunDirEnu() const override { return sunDir_; }

  int type() const { return type_; }
  const CieSkyParameters& parameters() const { return params_; }
  // L/Lz towards dirEnu (unit, z ≥ 0).
  double relativeLuminance(const dvec3& dirEnu) const;

 private:
  friend CieSky makeCieSky(int, double, double, CieNormalisation);
  CieSky(int type, const dvec3& sunDir);

  int type_;
  CieSkyParameters params_;
  dvec3 sunDir_;
  double inverseDenominator_;   // 1 / (f(Zs)·φ(0))
  double zenithLuminanceCdM2_;  // Lz
};

// A CIE sky of `type` (1..15) for the sun at apparent zenith angle sunZenithDeg ([0, 180]; the formulas stay
// positive with the sun below the horizon, so such a sky is defined too) and azimuth sunAzimuthDeg (degrees
// clockwise from north, any finite value). InputError for a type outside 1..15, an angle out of range or not
// finite, or a negative or non-finite normalisation value.
CieSky makeCieSky(int type, double sunZenithDeg, double sunAzimuthDeg, CieNormalisation normalisation);

}  // namespace fly::sunsky
