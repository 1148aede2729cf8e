#include "sunsky/cie_sky.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "base/error.h"

namespace fly::sunsky {

namespace {

// ISO 15469:2004 / CIE S 011/E:2003, Table 1: each type combines one of six gradation groups (a, b) with one
// of six indicatrix groups (c, d, e):
//   gradation  I (4.0, −0.70), II (1.1, −0.8), III (0, −1.0), IV (−1.0, −0.55), V (−1.0, −0.32),
//              VI (−1.0, −0.15)
//   indicatrix 1 (0, −1.0, 0), 2 (2, −1.5, 0.15), 3 (5, −2.5, 0.30), 4 (10, −3.0, 0.45), 5 (16, −3.0, 0.30),
//              6 (24, −2.8, 0.15)
constexpr std::array<CieSkyParameters, 15> kCieSkyTypes = {{
    {4.0, -0.70, 0.0, -1.0, 0.00},    // 1  I.1   overcast, steep gradation, azimuthal uniformity
    {4.0, -0.70, 2.0, -1.5, 0.15},    // 2  I.2   overcast, steep gradation, slightly brighter towards the sun
    {1.1, -0.80, 0.0, -1.0, 0.00},    // 3  II.1  overcast, moderately graded, azimuthal uniformity
    {1.1, -0.80, 2.0, -1.5, 0.15},    // 4  II.2  overcast, moderately graded, slightly brighter at the sun
    {0.0, -1.00, 0.0, -1.0, 0.00},    // 5  III.1 sky of uniform luminance
    {0.0, -1.00, 2.0, -1.5, 0.15},    // 6  III.2 partly cloudy, no gradation, slightly brighter at the sun
    {0.0, -1.00, 5.0, -2.5, 0.30},    // 7  III.3 partly cloudy, no gradation, brighter circumsolar region
    {0.0, -1.00, 10.0, -3.0, 0.45},   // 8  III.4 partly cloudy, no gradation, distinct solar corona
    {-1.0, -0.55, 2.0, -1.5, 0.15},   // 9  IV.2  partly cloudy, the sun obscured
    {-1.0, -0.55, 5.0, -2.5, 0.30},   // 10 IV.3  partly cloudy, brighter circumsolar region
    {-1.0, -0.55, 10.0, -3.0, 0.45},  // 11 IV.4  white-blue sky with distinct solar corona
    {-1.0, -0.32, 10.0, -3.0, 0.45},  // 12 V.4   CIE standard clear sky, low luminance turbidity
    {-1.0, -0.32, 16.0, -3.0, 0.30},  // 13 V.5   CIE standard clear sky, polluted atmosphere
    {-1.0, -0.15, 16.0, -3.0, 0.30},  // 14 VI.5  cloudless turbid sky with broad solar corona
    {-1.0, -0.15, 24.0, -2.8, 0.15},  // 15 VI.6  white-blue turbid sky with broad solar corona
}};

// φ(Z) with cosZ = cos Z; exp(b / cos Z) → 0 at the horizon since b < 0 for every type.
double gradation(const CieSkyParameters& p, double cosZ) {
  return cosZ > 0.0 ? 1.0 + p.a * std::exp(p.b / cosZ) : 1.0;
}

// f(χ) with χ in radians and cosChi = cos χ.
double indicatrix(const CieSkyParameters& p, double chi, double cosChi) {
  return 1.0 + p.c * (std::exp(p.d * chi) - std::exp(p.d * kPi / 2.0)) + p.e * cosChi * cosChi;
}

}  // namespace

const CieSkyParameters& cieSkyParameters(int type) {
  if (type < 1 || type > 15) {
    throw InputError(
        {}, "CIE sky type " + std::to_string(type) + " does not exist",
        "ISO 15469 defines types 1 (overcast) to 15 (turbid cloudless); the CIE clear sky is 12");
  }
  return kCieSkyTypes[type - 1];
}

CieSky::CieSky(int type, const dvec3& sunDir)
    : type_(type), params_(cieSkyParameters(type)), sunDir_(sunDir), zenithLuminanceCdM2_(0.0) {
  const double sunZenith = std::acos(std::clamp(sunDir.z, -1.0, 1.0));
  // Over all types and angles φ ≥ 1 + a·e^b ≥ 0.139 and f ≥ 1 + c·(e^{dπ} − e^{dπ/2}) ≥ 0.708 (type 15), so
  // the luminance is positive everywhere.
  inverseDenominator_ = 1.0 / (indicatrix(params_, sunZenith, sunDir.z) * gradation(params_, 1.0));
}

double CieSky::relativeLuminance(const dvec3& dirEnu) const {
  const double cosChi = std::clamp(glm::dot(dirEnu, sunDir_), -1.0, 1.0);
  return indicatrix(params_, std::acos(cosChi), cosChi) * gradation(params_, dirEnu.z) * inverseDenominator_;
}

Rgb CieSky::radianceCdM2(const dvec3& dirEnu) const {
  if (dirEnu.z < 0.0) return Rgb(0.0f);
  return Rgb(float(zenithLuminanceCdM2_ * relativeLuminance(dirEnu)));
}

CieSky makeCieSky(int type, double sunZenithDeg, double sunAzimuthDeg, CieNormalisation normalisation) {
  const bool zenith = normalisation.kind == CieNormalisation::Kind::kZenithLuminance;
  checkInputRange(zenith ? "CIE sky zenith luminance" : "CIE sky diffuse horizontal illuminance",
                  normalisation.value, 0.0, std::numeric_limits<double>::max(), zenith ? " cd/m²" : " lx",
                  "give a finite value ≥ 0");
  CieSky sky(type, sunDirectionEnu(sunZenithDeg, sunAzimuthDeg));
  if (normalisation.kind == CieNormalisation::Kind::kZenithLuminance) {
    sky.zenithLuminanceCdM2_ = normalisation.value;
  } else {
    // L/Lz > 0 everywhere (see the constructor), so the integral is positive.
    const double relativeIlluminance =
        integrateHemisphere([&sky](const dvec3& dir) { return sky.relativeLuminance(dir); }, sky.sunDir_);
    sky.zenithLuminanceCdM2_ = normalisation.value / relativeIlluminance;
  }
  return sky;
}

}  // namespace fly::sunsky
