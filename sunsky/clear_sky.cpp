#include "sunsky/clear_sky.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "sunsky/site_frame.h"
#include "sunsky/sun_disc.h"

namespace fly::sunsky {

namespace {

// Preetham, Shirley & Smits 1999, appendix A.2: the Perez coefficients A, B, C, D, E of the luminance Y and
// of the chromaticities x and y, each {slope, intercept} of a line in the turbidity T.
constexpr double kLuminanceCoefficients[5][2] = {
    {0.1787, -1.4630}, {-0.3554, 0.4275}, {-0.0227, 5.3251}, {0.1206, -2.5771}, {-0.0670, 0.3703}};
constexpr double kChromaXCoefficients[5][2] = {
    {-0.0193, -0.2592}, {-0.0665, 0.0008}, {-0.0004, 0.2125}, {-0.0641, -0.8989}, {-0.0033, 0.0452}};
constexpr double kChromaYCoefficients[5][2] = {
    {-0.0167, -0.2608}, {-0.0950, 0.0092}, {-0.0079, 0.2102}, {-0.0441, -1.6537}, {-0.0109, 0.0529}};

// Zenith chromaticity (appendix A.2): x_z = [T² T 1]·M·[θs³ θs² θs 1]ᵀ, θs in radians; likewise y_z.
constexpr double kZenithX[3][4] = {{0.00166, -0.00375, 0.00209, 0.0},
                                   {-0.02903, 0.06377, -0.03202, 0.00394},
                                   {0.11693, -0.21196, 0.06052, 0.25886}};
constexpr double kZenithY[3][4] = {{0.00275, -0.00610, 0.00317, 0.0},
                                   {-0.04214, 0.08970, -0.04153, 0.00516},
                                   {0.15346, -0.26756, 0.06670, 0.26688}};

// Chromaticity of the night sky (clear_sky.h).
constexpr double kNightX = 0.25;
constexpr double kNightY = 0.25;

// Clear-sky twilight: horizontal illuminance at the end of civil twilight (sun 6° below the horizon) and of
// nautical twilight (12°), lux (AMS Glossary of Meteorology, see clear_sky.h).
constexpr double kCivilTwilightEndLux = 3.0;
constexpr double kNauticalTwilightEndLux = 0.008;
constexpr double kTwilightStepDeg = 6.0;

// F(θ, γ) = (1 + A·e^{B / cos θ})·(1 + C·e^{Dγ} + E·cos²γ). B < 0 for every coefficient set and turbidity in
// range, so the gradation factor tends to 1 at the horizon.
double perezF(const ClearSky::Distribution& p, double cosTheta, double gamma, double cosGamma) {
  const double gradation = cosTheta > 0.0 ? 1.0 + p.a * std::exp(p.b / cosTheta) : 1.0;
  return gradation * (1.0 + p.c * std::exp(p.d * gamma) + p.e * cosGamma * cosGamma);
}

// The distribution's value towards a direction at cos θ = cosTheta and angle γ from the sun.
double valueOf(const ClearSky::Distribution& p, double cosTheta, double gamma, double cosGamma) {
  return p.zenithValue * perezF(p, cosTheta, gamma, cosGamma) * p.inverseZenithF;
}

ClearSky::Distribution distribution(const double (&k)[5][2], double turbidity, double zenithValue,
                                    double sunTheta) {
  const auto line = [&](int i) { return k[i][0] * turbidity + k[i][1]; };
  ClearSky::Distribution p{line(0), line(1), line(2), line(3), line(4), zenithValue, 1.0};
  p.inverseZenithF = 1.0 / perezF(p, 1.0, sunTheta, std::cos(sunTheta));
  return p;
}

double zenithChromaticity(const double (&m)[3][4], double turbidity, double sunTheta) {
  const double t[3] = {turbidity * turbidity, turbidity, 1.0};
  const double s[4] = {sunTheta * sunTheta * sunTheta, sunTheta * sunTheta, sunTheta, 1.0};
  double value = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) value += t[i] * m[i][j] * s[j];
  }
  return value;
}

// Preetham's zenith luminance Yz(T, θs) in kcd/m² (appendix A.2), > 0 for T in range and θs in [0, π/2].
double zenithLuminanceKcdM2(double turbidity, double sunTheta) {
  const double chi = (4.0 / 9.0 - turbidity / 120.0) * (kPi - 2.0 * sunTheta);
  return (4.0453 * turbidity - 4.9710) * std::tan(chi) - 0.2155 * turbidity + 2.4192;
}

}  // namespace

ClearSky::ClearSky(double turbidity, double sunZenithDeg, double sunAzimuthDeg)
    : turbidity_(turbidity),
      modelSunDir_(sunZenithDeg <= 90.0 ? sunDirectionEnu(sunZenithDeg, sunAzimuthDeg)
                                        : directionFromAzimuthElevation(sunAzimuthDeg, 0.0)),
      nightRadiance_(nightSkyRadianceCdM2()) {
  const double sunTheta = std::acos(std::clamp(modelSunDir_.z, 0.0, 1.0));
  luminance_ = distribution(kLuminanceCoefficients, turbidity,
                            1000.0 * zenithLuminanceKcdM2(turbidity, sunTheta), sunTheta);
  chromaX_ = distribution(kChromaXCoefficients, turbidity, zenithChromaticity(kZenithX, turbidity, sunTheta),
                          sunTheta);
  chromaY_ = distribution(kChromaYCoefficients, turbidity, zenithChromaticity(kZenithY, turbidity, sunTheta),
                          sunTheta);
}

Rgb ClearSky::radianceCdM2(const dvec3& dirEnu) const {
  if (dirEnu.z < 0.0) return Rgb(0.0f);
  const double cosGamma = std::clamp(glm::dot(dirEnu, modelSunDir_), -1.0, 1.0);
  const double gamma = std::acos(cosGamma);
  return rec709FromChromaticity(valueOf(chromaX_, dirEnu.z, gamma, cosGamma),
                                valueOf(chromaY_, dirEnu.z, gamma, cosGamma),
                                valueOf(luminance_, dirEnu.z, gamma, cosGamma) * daylightScale_) +
         nightRadiance_ * float(nightScale_);
}

double twilightFactor(double sunsetLux, double depressionDeg) {
  assert(sunsetLux > kCivilTwilightEndLux);  // ≥ 0.8 klx for every turbidity in range
  const double logSunset = std::log10(sunsetLux);
  const double logCivil = std::log10(kCivilTwilightEndLux);
  const double logNautical = std::log10(kNauticalTwilightEndLux);
  const double logLux = depressionDeg <= kTwilightStepDeg
                            ? logSunset + (logCivil - logSunset) * depressionDeg / kTwilightStepDeg
                            : logCivil + (logNautical - logCivil) * (depressionDeg / kTwilightStepDeg - 1.0);
  return std::pow(10.0, logLux - logSunset);
}

Rgb nightSkyRadianceCdM2() { return rec709FromChromaticity(kNightX, kNightY, kNightSkyLuminanceCdM2); }

double iesClearSkyDiffuseLux(double sunElevationDeg) {
  const double alpha = degToRad(std::clamp(sunElevationDeg, 0.0, 90.0));
  return 800.0 + 15500.0 * std::sqrt(std::sin(alpha));
}

ClearSky makeClearSky(double turbidity, double sunZenithDeg, double sunAzimuthDeg,
                      std::optional<double> diffuseHorizontalLux, ClearSkyLevel level) {
  checkInputRange("turbidity", turbidity, kMinTurbidity, kMaxTurbidity, "",
                  "Preetham's turbidity: 2 = very clear, 3 = clear, 6 = hazy, 10 = very hazy");
  if (diffuseHorizontalLux) {
    checkInputRange("clear sky diffuse horizontal illuminance", *diffuseHorizontalLux, 0.0,
                    std::numeric_limits<double>::max(), " lx", "give a finite illuminance ≥ 0 in lux");
  }
  sunDirectionEnu(sunZenithDeg, sunAzimuthDeg);  // validates the angles
  ClearSky sky(turbidity, sunZenithDeg, sunAzimuthDeg);
  if (sunZenithDeg > 90.0) {
    // Preetham's part alone (the night sky is added on top).
    const double sunsetLux = integrateHemisphere(
        [&sky](const dvec3& dir) {
          const double cosGamma = std::clamp(glm::dot(dir, sky.modelSunDir_), -1.0, 1.0);
          return valueOf(sky.luminance_, dir.z, std::acos(cosGamma), cosGamma);
        },
        sky.modelSunDir_);
    // The IES level starts twilight from its own sunset value instead of Preetham's.
    const double startLux = level == ClearSkyLevel::kIesHandbook ? iesClearSkyDiffuseLux(0.0) : sunsetLux;
    sky.daylightScale_ = startLux / sunsetLux * twilightFactor(startLux, sunZenithDeg - 90.0);
  } else if (level == ClearSkyLevel::kIesHandbook && !diffuseHorizontalLux) {
    diffuseHorizontalLux = iesClearSkyDiffuseLux(90.0 - sunZenithDeg);
  }
  if (diffuseHorizontalLux) {
    // > 0: the night sky alone gives π·kNightSkyLuminanceCdM2.
    const double s = *diffuseHorizontalLux / horizontalIlluminanceLux(sky);
    sky.daylightScale_ *= s;
    sky.nightScale_ *= s;
  }
  return sky;
}

}  // namespace fly::sunsky
