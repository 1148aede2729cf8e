#include "base/blackbody.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "base/cie1931.h"

namespace fly {
namespace {

// 2hc² in W·m², from the exact SI values of h and c.
constexpr double kTwoHcSquared = 2.0 * 6.62607015e-34 * 299792458.0 * 299792458.0;

}  // namespace

double planckSpectralRadiance(double wavelengthNm, double temperatureK) {
  const double lambdaM = wavelengthNm * 1e-9;
  const double denominator = std::expm1(kPlanckC2MK / (lambdaM * temperatureK));
  if (!std::isfinite(denominator)) return 0.0;
  // Per metre of wavelength, then per nanometre.
  return kTwoHcSquared / (std::pow(lambdaM, 5.0) * denominator) * 1e-9;
}

dvec2 planckianChromaticity(double temperatureK) {
  return chromaticity(
      cie1931Tristimulus([temperatureK](double nm) { return planckSpectralRadiance(nm, temperatureK); }));
}

Rgb planckianRec709(double temperatureK) {
  assert(temperatureK >= kMinColourTemperatureK && temperatureK <= kMaxColourTemperatureK);
  const dvec3 xyz =
      cie1931Tristimulus([temperatureK](double nm) { return planckSpectralRadiance(nm, temperatureK); });
  dvec3 rgb = rec709FromXyz(xyz / xyz.y);
  // Desaturate towards white at Y = 1: c' = 1 + s (c − 1) keeps the luminance (luminance(1, 1, 1) = 1), and
  // the largest s ≤ 1 that leaves every channel ≥ 0 is min over negative channels of 1 / (1 − c).
  double s = 1.0;
  for (int i = 0; i < 3; ++i) {
    if (rgb[i] < 0.0) s = std::min(s, 1.0 / (1.0 - rgb[i]));
  }
  rgb = dvec3(1.0) + s * (rgb - dvec3(1.0));
  rgb = glm::max(rgb, dvec3(0.0));  // the channel that set s, exactly 0 rather than −1e-17
  // fly's luminance weights are BT.709's rounded ones; scale so that they give exactly 1.
  const Rgb c(rgb);
  return c / luminance(c);
}

}  // namespace fly
