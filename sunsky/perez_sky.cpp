#include "sunsky/perez_sky.h"

#include <algorithm>
#include <cmath>

#include "sunsky/site_frame.h"
#include "sunsky/sun_disc.h"

namespace fly::sunsky {

namespace {

// Upper ε bounds of bins 1..7 (Perez et al. 1990, Table 1; the same bins in 1993).
constexpr double kBinUpperClearness[7] = {1.065, 1.230, 1.500, 1.950, 2.800, 4.500, 6.200};

// Perez, Seals & Michalsky 1993, Table 1: per ε bin the coefficients {x1, x2, x3, x4} of a, b, c, d and e
// (cross-checked against the table in Radiance's gendaylit).
constexpr double kLuminanceTable[8][5][4] = {
    {{1.3525, -0.2576, -0.2690, -1.4366},
     {-0.7670, 0.0007, 1.2734, -0.1233},
     {2.8000, 0.6004, 1.2375, 1.0000},
     {1.8734, 0.6297, 0.9738, 0.2809},
     {0.0356, -0.1246, -0.5718, 0.9938}},
    {{-1.2219, -0.7730, 1.4148, 1.1016},
     {-0.2054, 0.0367, -3.9128, 0.9156},
     {6.9750, 0.1774, 6.4477, -0.1239},
     {-1.5798, -0.5081, -1.7812, 0.1080},
     {0.2624, 0.0672, -0.2190, -0.4285}},
    {{-1.1000, -0.2515, 0.8952, 0.0156},
     {0.2782, -0.1812, -4.5000, 1.1766},
     {24.7219, -13.0812, -37.7000, 34.8438},
     {-5.0000, 1.5218, 3.9229, -2.6204},
     {-0.0156, 0.1597, 0.4199, -0.5562}},
    {{-0.5484, -0.6654, -0.2672, 0.7117},
     {0.7234, -0.6219, -5.6812, 2.6297},
     {33.3389, -18.3000, -62.2500, 52.0781},
     {-3.5000, 0.0016, 1.1477, 0.1062},
     {0.4659, -0.3296, -0.0876, -0.0329}},
    {{-0.6000, -0.3566, -2.5000, 2.3250},
     {0.2937, 0.0496, -5.6812, 1.8415},
     {21.0000, -4.7656, -21.5906, 7.2492},
     {-3.5000, -0.1554, 1.4062, 0.3988},
     {0.0032, 0.0766, -0.0656, -0.1294}},
    {{-1.0156, -0.3670, 1.0078, 1.4051},
     {0.2875, -0.5328, -3.8500, 3.3750},
     {14.0000, -0.9999, -7.1406, 7.5469},
     {-3.4000, -0.1078, -1.0750, 1.5702},
     {-0.0672, 0.4016, 0.3017, -0.4844}},
    {{-1.0000, 0.0211, 0.5025, -0.5119},
     {-0.3000, 0.1922, 0.7023, -1.6317},
     {19.0000, -5.0000, 1.2438, -1.9094},
     {-4.0000, 0.0250, 0.3844, 0.2656},
     {1.0468, -0.3788, -2.4517, 1.4656}},
    {{-1.0500, 0.0289, 0.4260, 0.3590},
     {-0.3250, 0.1156, 0.7781, 0.0025},
     {31.0625, -14.5000, -46.1148, 55.3750},
     {-7.2312, 0.4050, 13.3500, 0.6234},
     {1.5000, -0.6426, 1.8564, 0.5636}},
};

// Perez et al. 1990, the luminous efficacy table: per ε bin {a, b, c, d} of the direct normal and of the
// diffuse horizontal efficacy, lm/W.
constexpr double kDirectEfficacy[8][4] = {{57.20, -4.55, -2.98, 117.12}, {98.99, -3.46, -1.21, 12.38},
                                          {109.83, -4.90, -1.71, -8.81}, {110.34, -5.84, -1.99, -4.56},
                                          {106.36, -3.97, -1.75, -6.16}, {107.19, -1.25, -1.51, -26.73},
                                          {105.75, 0.77, -1.26, -34.44}, {101.18, 1.58, -1.10, -8.29}};
constexpr double kDiffuseEfficacy[8][4] = {{97.24, -0.46, 12.00, -8.91},   {107.22, 1.15, 0.59, -3.95},
                                           {104.97, 2.96, -5.53, -8.77},   {102.39, 5.59, -13.95, -13.90},
                                           {100.71, 5.94, -22.75, -23.74}, {106.42, 3.83, -36.15, -28.83},
                                           {141.88, 1.90, -53.24, -14.03}, {152.23, 0.35, -45.27, -7.98}};

// The Δ limits (perez_sky.h, "Guards").
constexpr double kMinBrightness = 0.01;
constexpr double kMaxBrightness = 0.6;
constexpr double kMinBrightnessBins2To5 = 0.2;
// cos 84°: where b > 0 the gradation is evaluated no lower than 6° above the horizon.
constexpr double kMinGradationCos = 0.10452846326765347;
// Below this diffuse horizontal irradiance (W/m²) ε is computed as if it were this.
constexpr double kMinDiffuseWm2 = 0.01;
// Floor of the efficacies when illuminance is turned back into irradiance, lm/W: far below any daylight's, it
// only keeps the division finite where a fitted efficacy reaches 0 (the direct one does, for bin 1 near the
// horizon).
constexpr double kMinInversionEfficacy = 20.0;

double limitedBrightness(double brightness) {
  return std::clamp(brightness, kMinBrightness, kMaxBrightness);
}

int clearnessBin(double clearness) {
  int bin = 1;
  while (bin < 8 && clearness >= kBinUpperClearness[bin - 1]) ++bin;
  return bin;
}

// a..e for a condition and the sun at zenith angle zenithRad (Perez et al. 1993, Table 1 and perez_sky.h).
std::array<double, 5> luminanceCoefficients(const PerezSkyCondition& condition, double zenithRad) {
  const auto& t = kLuminanceTable[condition.bin - 1];
  double delta = limitedBrightness(condition.brightness);
  if (condition.bin >= 2 && condition.bin <= 5) delta = std::max(delta, kMinBrightnessBins2To5);
  std::array<double, 5> x{};
  for (int k = 0; k < 5; ++k) x[k] = t[k][0] + t[k][1] * zenithRad + delta * (t[k][2] + t[k][3] * zenithRad);
  if (condition.bin == 1) {
    x[2] = std::exp(std::pow(delta * (t[2][0] + t[2][1] * zenithRad), t[2][2])) - t[2][3];
    x[3] = -std::exp(delta * (t[3][0] + t[3][1] * zenithRad)) + t[3][2] + delta * t[3][3];
  }
  return x;
}

}  // namespace

PerezSkyCondition perezSkyCondition(double sunZenithDeg, double directNormalWm2, double diffuseHorizontalWm2,
                                    int dayOfYear) {
  const double zenithDeg = std::clamp(sunZenithDeg, 0.0, 90.0);
  const double z = degToRad(zenithDeg);
  const double kz3 = 1.041 * z * z * z;
  const double diffuse = std::max(diffuseHorizontalWm2, kMinDiffuseWm2);
  PerezSkyCondition c;
  c.clearness = ((diffuse + std::max(directNormalWm2, 0.0)) / diffuse + kz3) / (1.0 + kz3);
  c.brightness = std::max(diffuseHorizontalWm2, 0.0) * relativeAirMass(zenithDeg) /
                 (kSolarConstantWm2 * eccentricityCorrection(dayOfYear));
  c.bin = clearnessBin(c.clearness);
  return c;
}

double precipitableWaterCm(double dewPointC) {
  checkInputRange("dew point", dewPointC, -90.0, 60.0, " °C", "give the dew point temperature in °C");
  return std::exp(0.07 * dewPointC - 0.075);
}

PerezEfficacy perezLuminousEfficacy(const PerezSkyCondition& condition, double sunZenithDeg,
                                    double precipitableWaterCm) {
  const double z = degToRad(std::clamp(sunZenithDeg, 0.0, 90.0));
  const double delta = limitedBrightness(condition.brightness);
  const auto& b = kDirectEfficacy[condition.bin - 1];
  const auto& d = kDiffuseEfficacy[condition.bin - 1];
  const double w = precipitableWaterCm;
  return {std::max(0.0, b[0] + b[1] * w + b[2] * std::exp(5.73 * z - 5.0) + b[3] * delta),
          std::max(0.0, d[0] + d[1] * w + d[2] * std::cos(z) + d[3] * std::log(delta))};
}

double PerezSky::unclampedLuminance(const dvec3& dirEnu) const {
  const auto& [a, b, c, d, e] = coefficients_;
  const double mu = b > 0.0 ? std::max(dirEnu.z, kMinGradationCos) : dirEnu.z;
  const double gradation = mu > 0.0 ? 1.0 + a * std::exp(b / mu) : 1.0;
  const double cosGamma = std::clamp(glm::dot(dirEnu, sunDir_), -1.0, 1.0);
  return gradation * (1.0 + c * std::exp(d * std::acos(cosGamma)) + e * cosGamma * cosGamma);
}

double PerezSky::relativeLuminance(const dvec3& dirEnu) const {
  return std::max(0.0, unclampedLuminance(dirEnu));
}

Rgb PerezSky::radianceCdM2(const dvec3& dirEnu) const {
  if (dirEnu.z < 0.0) return Rgb(0.0f);
  return Rgb(float(uniformFallback_ ? scaleCdM2_ : scaleCdM2_ * relativeLuminance(dirEnu)));
}

PerezSky makePerezSky(const PerezSkyInput& in) {
  const dvec3 sunDir = sunDirectionEnu(in.sunZenithDeg, in.sunAzimuthDeg);
  const double ecc = eccentricityCorrection(in.dayOfYear);
  const double w = precipitableWaterCm(in.dewPointC);
  const bool lux = in.units == PerezSkyInput::Units::kIlluminanceLux;
  const double extraterrestrial = (lux ? kLuminousSolarConstantLux : kSolarConstantWm2) * ecc;
  const char* unit = lux ? " lx" : " W/m²";
  const char* hint = "direct normal and diffuse horizontal values cannot exceed the extraterrestrial one";
  checkInputRange("direct normal", in.directNormal, 0.0, extraterrestrial, unit, hint);
  checkInputRange("diffuse horizontal", in.diffuseHorizontal, 0.0, extraterrestrial, unit, hint);

  PerezSky sky;
  const bool sunUp = in.sunZenithDeg <= 90.0;
  const double zenithDeg = std::min(in.sunZenithDeg, 90.0);
  sky.sunDir_ = sunUp ? sunDir : directionFromAzimuthElevation(in.sunAzimuthDeg, 0.0);
  const double directNormal = sunUp ? in.directNormal : 0.0;

  if (!lux) {
    sky.condition_ = perezSkyCondition(zenithDeg, directNormal, in.diffuseHorizontal, in.dayOfYear);
    const PerezEfficacy k = perezLuminousEfficacy(sky.condition_, zenithDeg, w);
    sky.directNormalLux_ = directNormal * k.directLmPerW;
    sky.diffuseHorizontalLux_ = in.diffuseHorizontal * k.diffuseLmPerW;
  } else {
    // ε and Δ need irradiances: start from the ratio of the solar constants and iterate
    // E = illuminance / efficacy(ε(E), Δ(E)) to its fixed point (a few steps; bins can only alternate at a
    // bin boundary, where either answer is as good, so the iteration is capped).
    sky.directNormalLux_ = directNormal;
    sky.diffuseHorizontalLux_ = in.diffuseHorizontal;
    const double extraterrestrialEfficacy = kLuminousSolarConstantLux / kSolarConstantWm2;
    double directWm2 = directNormal / extraterrestrialEfficacy;
    double diffuseWm2 = in.diffuseHorizontal / extraterrestrialEfficacy;
    for (int iteration = 0; iteration < 20; ++iteration) {
      const PerezEfficacy k = perezLuminousEfficacy(
          perezSkyCondition(zenithDeg, directWm2, diffuseWm2, in.dayOfYear), zenithDeg, w);
      const double nextDirect = directNormal / std::max(k.directLmPerW, kMinInversionEfficacy);
      const double nextDiffuse = in.diffuseHorizontal / std::max(k.diffuseLmPerW, kMinInversionEfficacy);
      const bool converged = std::abs(nextDirect - directWm2) <= 1e-6 * (1.0 + directWm2) &&
                             std::abs(nextDiffuse - diffuseWm2) <= 1e-6 * (1.0 + diffuseWm2);
      directWm2 = nextDirect;
      diffuseWm2 = nextDiffuse;
      if (converged) break;
    }
    sky.condition_ = perezSkyCondition(zenithDeg, directWm2, diffuseWm2, in.dayOfYear);
  }
  sky.coefficients_ = luminanceCoefficients(sky.condition_, degToRad(zenithDeg));
  if (!(sky.diffuseHorizontalLux_ > 0.0)) return sky;  // black sky

  const double positive =
      integrateHemisphere([&sky](const dvec3& dir) { return sky.relativeLuminance(dir); }, sky.sunDir_);
  const double absolute = integrateHemisphere(
      [&sky](const dvec3& dir) { return std::abs(sky.unclampedLuminance(dir)); }, sky.sunDir_);
  sky.uniformFallback_ = !(positive >= 0.5 * absolute && positive > 0.0);
  sky.scaleCdM2_ =
      sky.uniformFallback_ ? sky.diffuseHorizontalLux_ / kPi : sky.diffuseHorizontalLux_ / positive;
  return sky;
}

}  // namespace fly::sunsky
