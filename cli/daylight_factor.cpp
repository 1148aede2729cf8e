#include "cli/daylight_factor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "base/color.h"
#include "base/math.h"

namespace fly::cli {

double overcastZenithLuminanceCdM2(double horizontalLux) {
  return 9.0 * horizontalLux / (7.0 * kPi);
}

rdb::TraceSky overcastSky(uint32_t resolution, double zenithLuminanceCdM2) {
  if (resolution < 1 || resolution > 1024 || !(zenithLuminanceCdM2 >= 0.0)) {
    throw std::invalid_argument("overcastSky: resolution outside [1, 1024] or a negative luminance");
  }
  rdb::TraceSky sky;
  sky.resolution = resolution;
  sky.radianceCdM2.resize(size_t(resolution) * resolution);
  for (uint32_t j = 0; j < resolution; ++j) {
    const double muCentre = 1.0 - (j + 0.5) / resolution;
    const Rgb l(float(zenithLuminanceCdM2 * (1.0 + 2.0 * muCentre) / 3.0));
    std::fill_n(sky.radianceCdM2.begin() + ptrdiff_t(j) * resolution, resolution, l);
  }
  return sky;
}

void turnOffDaylight(sdb::Scene& scene) {
  sdb::SkySettings sky = scene.sky();
  sky.model = sdb::SkyModel::kNone;
  sky.sun = false;
  scene.setSky(sky);
}

void keepSkyOnly(rdb::TraceRdb& rdb) {
  rdb.punctualLights.clear();
  rdb.goniometricTables.clear();
  rdb.emissiveTriangles.clear();
  for (rdb::TraceMaterial& m : rdb.materials) {
    m.emissionCdM2 = Rgb(0.0f);
    m.emissionTexture = {};
  }
  rdb.hasSun = false;
}

double unobstructedHorizontalLux(const rdb::TraceSky& sky) {
  const uint32_t n = sky.resolution;
  double sum = 0.0;
  for (uint32_t j = 0; j < n; ++j) {
    const double muCentre = 1.0 - (j + 0.5) / n;
    for (uint32_t i = 0; i < n; ++i) sum += double(luminance(sky.radianceCdM2[size_t(j) * n + i])) * muCentre;
  }
  return n > 0 ? sum * 2.0 * kPi / (double(n) * n) : 0.0;
}

DaylightFactorSummary summarizeDaylightFactors(std::span<const double> percent,
                                               std::span<const double> stdErrorPercent) {
  if (percent.empty() || percent.size() != stdErrorPercent.size()) {
    throw std::invalid_argument("summarizeDaylightFactors: no points, or errors not one per point");
  }
  DaylightFactorSummary s;
  double variance = 0.0;
  s.minPercent = percent[0];
  for (size_t i = 0; i < percent.size(); ++i) {
    s.meanPercent += percent[i];
    variance += stdErrorPercent[i] * stdErrorPercent[i];
    s.minPercent = std::min(s.minPercent, percent[i]);
  }
  const double n = double(percent.size());
  s.meanPercent /= n;
  s.meanStdErrorPercent = std::sqrt(variance) / n;
  s.uniformity = s.meanPercent > 0.0 ? s.minPercent / s.meanPercent : 0.0;
  return s;
}

}  // namespace fly::cli
