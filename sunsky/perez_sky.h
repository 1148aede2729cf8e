// The Perez all-weather sky (Perez, Seals & Michalsky, "All-weather model for sky luminance distribution —
// preliminary configuration and validation", Solar Energy 50(3) (1993) 235–245), driven by the direct normal
// and diffuse horizontal irradiance (W/m²) or illuminance (lux) of a weather record, with the luminous
// efficacy models of Perez, Ineichen, Seals, Michalsky & Stewart, "Modeling daylight availability and
// irradiance components from direct and global irradiance", Solar Energy 44(5) (1990) 271–289.
//
// Relative luminance of a sky element at zenith angle ζ and angle γ from the sun (sun zenith angle Z):
//   lv = (1 + a·exp(b / cos ζ))·(1 + c·exp(d·γ) + e·cos²γ)
// with a..e from the sky clearness ε and brightness Δ (defined in Perez et al. 1990, below) through the
// 1993 paper's Table 1: per ε bin x = x1 + x2·Z + Δ·(x3 + x4·Z) (Z in radians), except in bin 1
// c = exp((Δ·(c1 + c2·Z))^c3) − c4 and d = −exp(Δ·(d1 + d2·Z)) + d3 + Δ·d4. The sky is scaled so that ∫ L cos
// θ dω = the diffuse horizontal illuminance, and is neutral in colour.
//
// Guards (the fitted coefficients misbehave outside the data they were fitted to):
// - Δ is limited to [0.01, 0.6], and to ≥ 0.2 in bins 2–5 (1.065 ≤ ε < 2.8), where lower values were not
//   observed and they turn most of the sky negative; Radiance's gendaylit (Delaunay 1994) applies the same
//   limits.
// - Where b > 0 the gradation grows without bound towards the horizon; there it is evaluated no lower than
//   6° above the horizon (ζ ≤ 84°), the centre of the lowest band of the 145-patch sky scans the model was
//   fitted to.
// - Negative luminance is clamped to 0 before normalising. If the clamped sky keeps less than half of the
//   absolute integral (more of the sky negative than positive), the coefficients are meaningless for these
//   inputs and the sky is uniform (L = Dv/π).
// - A diffuse horizontal value of 0 gives a black sky. With the sun below the horizon the sky is evaluated
//   with the sun on the horizon at its azimuth and no direct beam (ε = 1, the overcast bin).
#pragma once

#include <array>

#include "sunsky/sky.h"

namespace fly::sunsky {

// Sky clearness ε and brightness Δ (Perez et al. 1990):
//   ε = ((Dh + I)/Dh + 1.041·Z³) / (1 + 1.041·Z³), Z in radians
//   Δ = Dh·m / I0, m the relative air mass (sun_disc.h), I0 the extraterrestrial normal irradiance
struct PerezSkyCondition {
  double clearness = 1.0;   // ε ≥ 1
  double brightness = 0.0;  // Δ ≥ 0, as computed (the limits above apply where it is used)
  int bin = 1;              // 1..8: ε in [1, 1.065), [1.065, 1.23), [1.23, 1.5), [1.5, 1.95), [1.95, 2.8),
                            // [2.8, 4.5), [4.5, 6.2), [6.2, ∞)
};

// The condition of a sky with the sun at apparent zenith angle sunZenithDeg (clamped to [0, 90]), direct
// normal irradiance I and diffuse horizontal irradiance Dh (W/m², ≥ 0; a Dh below 0.01 W/m² counts as 0.01,
// where ε stops meaning anything) on day `dayOfYear` (1..366).
PerezSkyCondition perezSkyCondition(double sunZenithDeg, double directNormalWm2, double diffuseHorizontalWm2,
                                    int dayOfYear);

// Atmospheric precipitable water, cm, from the surface dew point temperature, °C:
// W = exp(0.07·Td − 0.075) (Perez et al. 1990, after Wright, Perez & Michalsky 1989).
double precipitableWaterCm(double dewPointC);

// Luminous efficacy of the direct and diffuse components, lm/W (Perez et al. 1990):
//   direct  Kb = max(0, a + b·W + c·exp(5.73·Z − 5) + d·Δ)
//   diffuse Kd = max(0, a + b·W + c·cos Z + d·ln Δ)
// per ε bin, Z in radians (clamped to [0, π/2]), W in cm, Δ limited to [0.01, 0.6].
struct PerezEfficacy {
  double directLmPerW = 0.0;
  double diffuseLmPerW = 0.0;
};
PerezEfficacy perezLuminousEfficacy(const PerezSkyCondition& condition, double sunZenithDeg,
                                    double precipitableWaterCm);

struct PerezSkyInput {
  enum class Units {
    kIrradianceWm2,   // converted to lux with perezLuminousEfficacy
    kIlluminanceLux,  // ε and Δ from irradiances found by inverting the efficacy models (fixed point)
  };
  double sunZenithDeg = 0.0;   // apparent, degrees, [0, 180]
  double sunAzimuthDeg = 0.0;  // degrees clockwise from north, finite
  Units units = Units::kIrradianceWm2;
  double directNormal = 0.0;  // ≥ 0, at most the extraterrestrial value (1367 W/m² or 133.8 klx × (r0/r)²)
  double diffuseHorizontal = 0.0;  // ≥ 0, likewise
  int dayOfYear = 172;             // 1..366, for the extraterrestrial irradiance
  double dewPointC = 10.0;         // [−90, 60] °C, for the precipitable water (10 °C: W = 1.87 cm)
};

class PerezSky final : public Sky {
 public:
  Rgb radianceCdM2(const dvec3& dirEnu) const override;
  // The sun as given, or on the horizon at its azimuth when it is below it.
  dvec3 sunDirEnu() const override { return sunDir_; }

  const PerezSkyCondition& condition() const { return condition_; }
  // The distribution's coefficients a..e after the guards on Δ.
  const std::array<double, 5>& coefficients() const { return coefficients_; }
  // The direct normal and diffuse horizontal illuminance, lux (converted when given in W/m²). The direct one
  // is for the sun's disc (sun_disc.h, sunDiscWithIlluminance); 0 with the sun below the horizon.
  double directNormalLux() const { return directNormalLux_; }
  double diffuseHorizontalLux() const { return diffuseHorizontalLux_; }
  // True when the coefficients gave a mostly negative sky and the uniform fallback is used.
  bool uniformFallback() const { return uniformFallback_; }
  // lv towards dirEnu (unit, z ≥ 0), clamped to ≥ 0.
  double relativeLuminance(const dvec3& dirEnu) const;

 private:
  friend PerezSky makePerezSky(const PerezSkyInput&);
  PerezSky() = default;
  double unclampedLuminance(const dvec3& dirEnu) const;  // lv as the coefficients give it

  dvec3 sunDir_{0.0, 0.0, 1.0};
  PerezSkyCondition condition_;
  std::array<double, 5> coefficients_{};
  double directNormalLux_ = 0.0;
  double diffuseHorizontalLux_ = 0.0;
  double scaleCdM2_ = 0.0;  // cd/m² per unit of lv (or the uniform luminance in the fallback)
  bool uniformFallback_ = false;
};

// InputError for an input out of range.
PerezSky makePerezSky(const PerezSkyInput& in);

}  // namespace fly::sunsky
