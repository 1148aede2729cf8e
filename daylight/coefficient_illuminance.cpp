#include "daylight/coefficient_illuminance.h"

#include <cmath>
#include <string>

#include "base/error.h"

namespace fly::daylight {

std::vector<IlluminanceSeries> coefficientIlluminance(const DaylightCoefficients& c, const sunsky::SkyMatrix& sky,
                                                      const SunDirectIlluminance* sun) {
  const std::size_t patches = static_cast<std::size_t>(sky.patches.count());
  const std::size_t sensors = c.sensorCount;
  const std::size_t hours = sky.hourCount();
  const std::size_t k = c.replicates < 1 ? 0 : static_cast<std::size_t>(c.replicates);
  if (c.patchCount != sky.patches.count()) {
    throw InputError({}, "the daylight coefficients have " + std::to_string(c.patchCount) +
                             " patches and the sky matrix " + std::to_string(patches),
                     "compute both with the same sky subdivision (--sky-patches)");
  }
  if (k == 0 || c.luxPerCdM2.size() != k * sensors * patches) {
    throw InputError({}, "the daylight coefficients hold " + std::to_string(c.luxPerCdM2.size()) +
                             " values for " + std::to_string(c.replicates) + " replicates of " +
                             std::to_string(sensors) + " sensors and " + std::to_string(patches) + " patches");
  }
  for (const Rgb& v : c.luxPerCdM2) {
    for (int ch = 0; ch < 3; ++ch) {
      if (!std::isfinite(v[ch]) || v[ch] < 0.0f) {
        throw InputError({}, "a daylight coefficient is negative or not finite");
      }
    }
  }
  if (sun) {
    const bool errors = !sun->standardErrorLux.empty();
    if (sun->lux.size() != hours * sensors || (errors && sun->standardErrorLux.size() != hours * sensors)) {
      throw InputError({}, "the sun's direct illuminance has " + std::to_string(sun->lux.size()) +
                               " values for " + std::to_string(hours) + " hours of " + std::to_string(sensors) +
                               " sensors");
    }
    for (std::size_t i = 0; i < sun->lux.size(); ++i) {
      if (!std::isfinite(sun->lux[i]) || sun->lux[i] < 0.0 ||
          (errors && !(std::isfinite(sun->standardErrorLux[i]) && sun->standardErrorLux[i] >= 0.0))) {
        throw InputError({}, "the sun's direct illuminance at hour " + std::to_string(i / sensors) +
                                 ", sensor " + std::to_string(i % sensors) + " is negative or not finite");
      }
    }
  }
  const bool withErrors = k >= 2 || (sun && !sun->standardErrorLux.empty());
  std::vector<IlluminanceSeries> out(sensors);
  for (IlluminanceSeries& s : out) {
    s.illuminanceLux.assign(hours, 0.0);
    if (withErrors) s.standardErrorLux.assign(hours, 0.0);
  }
  std::vector<double> replicate(k);
  for (std::size_t h = 0; h < hours; ++h) {
    const Rgb* radiance = sky.row(h);
    bool dark = true;
    for (std::size_t p = 0; p < patches && dark; ++p) dark = radiance[p] == Rgb(0.0f);
    for (std::size_t s = 0; s < sensors; ++s) {
      double mean = 0.0, variance = 0.0;
      if (!dark) {
        for (std::size_t r = 0; r < k; ++r) {
          const Rgb* dc = c.luxPerCdM2.data() + (r * sensors + s) * patches;
          dvec3 e(0.0);
          for (std::size_t p = 0; p < patches; ++p) e += dvec3(dc[p]) * dvec3(radiance[p]);
          replicate[r] = 0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z;  // Rec.709 luminance
          mean += replicate[r];
        }
        mean /= double(k);
        if (k >= 2) {
          for (std::size_t r = 0; r < k; ++r) variance += (replicate[r] - mean) * (replicate[r] - mean);
          variance /= double(k - 1) * double(k);  // of the mean: s² / K
        }
      }
      if (sun) {
        mean += sun->lux[h * sensors + s];
        if (!sun->standardErrorLux.empty()) variance += std::pow(sun->standardErrorLux[h * sensors + s], 2.0);
      }
      out[s].illuminanceLux[h] = mean;
      if (withErrors) out[s].standardErrorLux[h] = std::sqrt(variance);
    }
  }
  return out;
}

}  // namespace fly::daylight
