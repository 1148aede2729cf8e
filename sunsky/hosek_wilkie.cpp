#include "sunsky/hosek_wilkie.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/cie1931.h"
#include "sunsky/clear_sky.h"
#include "sunsky/hosek_wilkie_data.inc"
#include "sunsky/site_frame.h"

namespace fly::sunsky {

namespace {

namespace data = hosek_wilkie_data;

// Maximum luminous efficacy, lm/W (CIE 015:2018), for the W-based tables.
constexpr double kKm = 683.0;

// Radius of the solar disc the solar radiance function was fitted with, radians (0.51° / 2).
constexpr double kModelSunRadiusRad = 0.51 / 2.0 * kPi / 180.0;

constexpr int kParameters = 9, kControlPoints = 6, kTurbidities = 10;
constexpr int kSolarPieces = 45, kSolarOrder = 4, kSolarBands = 11;
constexpr double kSolarFirstNm = 320.0, kSolarStepNm = 40.0;

// The quintic Bézier weights of the six control points at x = (elevation / 90°)^{1/3}.
std::array<double, kControlPoints> bezierWeights(double elevationRad) {
  const double x = std::cbrt(std::clamp(elevationRad / (kPi / 2.0), 0.0, 1.0));
  const double y = 1.0 - x;
  return {y * y * y * y * y,         5.0 * y * y * y * y * x, 10.0 * y * y * y * x * x,
          10.0 * y * y * x * x * x, 5.0 * y * x * x * x * x, x * x * x * x * x};
}

// Visits the (albedo table, turbidity table) corners of the bilinear interpolation with their weights.
template <typename F>
void forEachCorner(double turbidity, double albedo, F&& visit) {
  const int low = std::min(static_cast<int>(turbidity), kTurbidities);  // table index + 1
  const double frac = turbidity - low;
  for (int a = 0; a < 2; ++a) {
    const double wa = a == 0 ? 1.0 - albedo : albedo;
    visit(a, low - 1, wa * (1.0 - frac));
    if (low < kTurbidities) visit(a, low, wa * frac);
  }
}

// Centre radiance of the solar disc in band `band` (0..10) for turbidity table `t` (0..9), W/(m² sr nm).
double solarCentre(int band, int t, double elevationRad) {
  const int piece = std::min(static_cast<int>(std::cbrt(2.0 * elevationRad / kPi) * kSolarPieces), kSolarPieces - 1);
  const double start = std::pow(double(piece) / kSolarPieces, 3.0) * (kPi / 2.0);
  const double x = elevationRad - start;
  const double* c = data::kSolarRadiance + ((band * kTurbidities + t) * kSolarPieces + piece) * kSolarOrder;
  return ((c[0] * x + c[1]) * x + c[2]) * x + c[3];
}

// Mean of the limb darkening over the disc in band `band`: ∫₀¹ ld(μ)·2μ dμ = Σ c_k·2/(k + 2).
double meanLimbDarkening(int band) {
  double mean = 0.0;
  for (int k = 0; k < 6; ++k) mean += data::kLimbDarkening[band * 6 + k] * 2.0 / (k + 2);
  return mean;
}

// Spectral radiance of the disc averaged over it, W/(m² sr nm), at `wavelengthNm` in [320, 720]:
// both factors interpolated linearly between bands and in the turbidity, as the model defines them.
double meanSolarRadiance(double wavelengthNm, double turbidity, double elevationRad) {
  int tLow = static_cast<int>(turbidity) - 1;
  double tFrac = turbidity - (tLow + 1);
  if (tLow == kTurbidities - 1) tLow = kTurbidities - 2, tFrac = 1.0;
  const double u = (wavelengthNm - kSolarFirstNm) / kSolarStepNm;
  const int band = std::min(static_cast<int>(u), kSolarBands - 2);
  const double bFrac = u - band;
  const auto centre = [&](int b) {
    return (1.0 - tFrac) * solarCentre(b, tLow, elevationRad) + tFrac * solarCentre(b, tLow + 1, elevationRad);
  };
  const double radiance = (1.0 - bFrac) * centre(band) + bFrac * centre(band + 1);
  const double darkening = (1.0 - bFrac) * meanLimbDarkening(band) + bFrac * meanLimbDarkening(band + 1);
  return std::max(0.0, radiance * darkening);
}

void checkTurbidity(double turbidity) {
  checkInputRange("turbidity", turbidity, kMinTurbidity, kMaxTurbidity, "",
                  "Linke turbidity: 2 = very clear, 3 = clear, 6 = hazy, 10 = very hazy");
}

}  // namespace

HosekWilkieSky::HosekWilkieSky(double turbidity, double groundAlbedo, double sunZenithDeg, double sunAzimuthDeg)
    : turbidity_(turbidity),
      groundAlbedo_(groundAlbedo),
      modelSunDir_(sunZenithDeg <= 90.0 ? sunDirectionEnu(sunZenithDeg, sunAzimuthDeg)
                                        : directionFromAzimuthElevation(sunAzimuthDeg, 0.0)),
      nightRadiance_(nightSkyRadianceCdM2()) {
  const double elevationRad = std::asin(std::clamp(modelSunDir_.z, 0.0, 1.0));
  const std::array<double, kControlPoints> w = bezierWeights(elevationRad);
  for (int c = 0; c < 3; ++c) {
    forEachCorner(turbidity, groundAlbedo, [&](int a, int t, double weight) {
      const int table = (c * 2 + a) * kTurbidities + t;
      for (int k = 0; k < kControlPoints; ++k) {
        const double* p = data::kSkyXyzParameters + (table * kControlPoints + k) * kParameters;
        for (int i = 0; i < kParameters; ++i) parameters_[c][i] += weight * w[k] * p[i];
        channelRadiance_[c] += weight * w[k] * data::kSkyXyzRadiance[table * kControlPoints + k];
      }
    });
  }
}

dvec3 HosekWilkieSky::modelXyz(const dvec3& dirEnu) const {
  const double cosTheta = std::clamp(dirEnu.z, 0.0, 1.0);
  const double cosGamma = std::clamp(glm::dot(dirEnu, modelSunDir_), -1.0, 1.0);
  const double gamma = std::acos(cosGamma);
  const double sqrtCosTheta = std::sqrt(cosTheta);
  dvec3 xyz;
  for (int c = 0; c < 3; ++c) {
    const std::array<double, 9>& p = parameters_[c];
    const double mie = (1.0 + cosGamma * cosGamma) / std::pow(1.0 + p[8] * p[8] - 2.0 * p[8] * cosGamma, 1.5);
    const double value = (1.0 + p[0] * std::exp(p[1] / (cosTheta + 0.01))) *
                         (p[2] + p[3] * std::exp(p[4] * gamma) + p[5] * cosGamma * cosGamma + p[6] * mie +
                          p[7] * sqrtCosTheta);
    xyz[c] = std::max(0.0, value * channelRadiance_[c]);
  }
  return xyz;
}

double HosekWilkieSky::modelLuminanceCdM2(const dvec3& dirEnu) const {
  return dirEnu.z < 0.0 ? 0.0 : kKm * modelXyz(dirEnu).y;
}

Rgb HosekWilkieSky::radianceCdM2(const dvec3& dirEnu) const {
  if (dirEnu.z < 0.0) return Rgb(0.0f);
  const dvec3 xyz = modelXyz(dirEnu);
  const double sum = xyz.x + xyz.y + xyz.z;
  const Rgb night = nightRadiance_ * float(nightScale_);
  if (!(sum > 0.0)) return night;
  return rec709FromChromaticity(xyz.x / sum, xyz.y / sum, kKm * xyz.y * daylightScale_) + night;
}

HosekWilkieSky makeHosekWilkieSky(double turbidity, double groundAlbedo, double sunZenithDeg,
                                  double sunAzimuthDeg, int dayOfYear,
                                  std::optional<double> diffuseHorizontalLux) {
  checkTurbidity(turbidity);
  checkInputRange("ground albedo", groundAlbedo, 0.0, 1.0, "", "give the ground's reflectance, 0.2 for grass");
  if (diffuseHorizontalLux) {
    checkInputRange("clear sky diffuse horizontal illuminance", *diffuseHorizontalLux, 0.0,
                    std::numeric_limits<double>::max(), " lx", "give a finite illuminance ≥ 0 in lux");
  }
  sunDirectionEnu(sunZenithDeg, sunAzimuthDeg);  // validates the angles
  HosekWilkieSky sky(turbidity, groundAlbedo, sunZenithDeg, sunAzimuthDeg);
  sky.daylightScale_ = eccentricityCorrection(dayOfYear);
  if (sunZenithDeg > 90.0) {
    const double sunsetLux = sky.daylightScale_ * integrateHemisphere(
                                                      [&sky](const dvec3& dir) { return sky.modelLuminanceCdM2(dir); },
                                                      sky.modelSunDir_);
    sky.daylightScale_ *= twilightFactor(sunsetLux, sunZenithDeg - 90.0);
  }
  if (diffuseHorizontalLux) {
    const double s = *diffuseHorizontalLux / horizontalIlluminanceLux(sky);
    sky.daylightScale_ *= s;
    sky.nightScale_ *= s;
  }
  return sky;
}

SunDisc hosekWilkieSunDisc(const SunDiscInput& in) {
  checkTurbidity(in.turbidity);
  checkInputRange("day of year", in.dayOfYear, 1.0, 366.0, "", "give the day of the year, 1 = 1 January");
  SunDisc disc{sunDirectionEnu(in.zenithDeg, in.azimuthDeg)};
  if (in.zenithDeg >= 90.0) return disc;  // on or below the horizon: no light
  const double elevationRad = degToRad(90.0 - in.zenithDeg);
  const double modelSolidAngleSr = 2.0 * kPi * (1.0 - std::cos(kModelSunRadiusRad));
  // W/(m² nm) → XYZ in W/m², CIE-weighted; beyond the model's 320–720 nm the eye is nearly blind.
  const dvec3 xyz = cie1931Tristimulus([&](double nm) {
    if (nm < kSolarFirstNm || nm > kSolarFirstNm + kSolarStepNm * (kSolarBands - 1)) return 0.0;
    return meanSolarRadiance(nm, in.turbidity, elevationRad) * modelSolidAngleSr;
  });
  const double sum = xyz.x + xyz.y + xyz.z;
  if (!(sum > 0.0)) return disc;
  const double directNormalLux = kKm * xyz.y * eccentricityCorrection(in.dayOfYear);
  disc.normalIlluminanceLux = rec709FromChromaticity(xyz.x / sum, xyz.y / sum, directNormalLux);
  disc.radianceCdM2 = disc.normalIlluminanceLux / float(sunDiscSolidAngleSr());
  return disc;
}

}  // namespace fly::sunsky
