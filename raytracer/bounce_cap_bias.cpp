#include "raytracer/bounce_cap_bias.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "base/color.h"
#include "raytracer/progressive.h"

namespace fly::raytracer {

namespace {

// One sample of a pilot point: the capped and the uncapped integrator from the same sampler state. The
// result's channels carry two luminances, not a colour: r = E_uncapped − E_capped (the missing light) and
// g = E_uncapped, so that the progressive driver gives the mean and standard error of both.
class MissingLightSource final : public SampleSourceOf<MissingLightSource> {
  friend SampleSourceOf<MissingLightSource>;

 public:
  MissingLightSource(const Integrator& capped, const Integrator& uncapped, std::vector<vec3> points,
                     std::vector<vec3> normals, std::vector<float> magnitudesM)
      : capped_(capped),
        uncapped_(uncapped),
        points_(std::move(points)),
        normals_(std::move(normals)),
        magnitudesM_(std::move(magnitudesM)) {}

  size_t pointCount() const override { return points_.size(); }

 private:
  template <class S>
  Rgb sampleAt(size_t i, S& sampler, uint64_t& rays) const {
    S same = sampler;  // the state after startSample: both paths draw the same numbers
    const float full = luminance(uncapped_.sampleIrradiance(points_[i], normals_[i], sampler, rays, magnitudesM_[i]));
    const float cut = luminance(capped_.sampleIrradiance(points_[i], normals_[i], same, rays, magnitudesM_[i]));
    return Rgb(full - cut, full, 0.0f);
  }

  const Integrator& capped_;
  const Integrator& uncapped_;
  std::vector<vec3> points_;
  std::vector<vec3> normals_;
  std::vector<float> magnitudesM_;
};

BounceCapBias estimateAt(const rdb::TraceRdb& rdb, const EmbreeScene& scene, const IntegratorSettings& capped,
                         std::vector<vec3> points, std::vector<vec3> normals, std::vector<float> magnitudesM,
                         uint32_t threads, uint64_t seed) {
  BounceCapBias bias;
  bias.maxBounces = capped.maxBounces;
  if (points.empty()) return bias;
  IntegratorSettings uncappedSettings = capped;
  uncappedSettings.maxBounces = kPathLengthGuard;
  const Integrator cappedIntegrator(rdb, scene, capped);
  const Integrator uncappedIntegrator(rdb, scene, uncappedSettings);
  const MissingLightSource source(cappedIntegrator, uncappedIntegrator, std::move(points), std::move(normals),
                                  std::move(magnitudesM));
  EstimateSettings settings;
  settings.firstPassSamples = kBounceCapPilotSamples;
  settings.maxSamples = kBounceCapPilotSamples;
  settings.threads = threads;
  settings.seed = seed;
  const EstimateResult result = estimateProgressively(source, settings);

  bias.points = static_cast<uint32_t>(result.points.size());
  bias.samplesPerPoint = result.samplesPerPoint;
  bias.seconds = result.seconds;
  double missing = 0.0, full = 0.0, missingVariance = 0.0;
  for (const IrradianceEstimate& e : result.points) {
    missing += e.meanLux.r;
    full += e.meanLux.g;
    missingVariance += double(e.stdErrorLux.r) * e.stdErrorLux.r;
    if (e.meanLux.g > 0.0f) bias.missingRelMax = std::max(bias.missingRelMax, double(e.meanLux.r / e.meanLux.g));
  }
  if (full > 0.0 && std::isfinite(full) && std::isfinite(missing)) {
    bias.missingRel = missing / full;
    bias.missingRelStdError = std::sqrt(missingVariance) / full;
  }
  return bias;
}

}  // namespace

BounceCapBias estimateBounceCapBias(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                    const IntegratorSettings& capped, std::span<const vec3> points,
                                    std::span<const vec3> normals, std::span<const float> surfaceMagnitudesM,
                                    uint32_t threads, uint64_t seed) {
  if (normals.size() != points.size() || (!surfaceMagnitudesM.empty() && surfaceMagnitudesM.size() != points.size())) {
    throw std::invalid_argument("estimateBounceCapBias: points, normals and magnitudes differ in size");
  }
  const size_t n = points.size();
  const size_t pilot = std::min<size_t>(n, kBounceCapPilotPoints);
  std::vector<vec3> p, nn;
  std::vector<float> m;
  for (size_t k = 0; k < pilot; ++k) {
    const size_t i = k * n / pilot;
    p.push_back(points[i]);
    nn.push_back(normals[i]);
    m.push_back(surfaceMagnitudesM.empty() ? 0.0f : surfaceMagnitudesM[i]);
  }
  return estimateAt(rdb, scene, capped, std::move(p), std::move(nn), std::move(m), threads, seed);
}

BounceCapBias estimateBounceCapBiasOnSurfaces(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                              const IntegratorSettings& capped, uint32_t threads, uint64_t seed) {
  std::vector<uint32_t> valid;
  for (uint32_t t = 0; t < rdb.triangleCount(); ++t) {
    if (scene.triangleAreaM2(t) > 0.0f) valid.push_back(t);
  }
  const size_t pilot = std::min<size_t>(valid.size(), kBounceCapPilotPoints);
  std::vector<vec3> p, nn;
  std::vector<float> m;
  for (size_t k = 0; k < pilot; ++k) {
    const uint32_t t = valid[k * valid.size() / pilot];
    const vec3 centroid = (rdb.positionsM[rdb.indices[3 * t]] + rdb.positionsM[rdb.indices[3 * t + 1]] +
                           rdb.positionsM[rdb.indices[3 * t + 2]]) /
                          3.0f;
    p.push_back(centroid);
    nn.push_back(scene.triangleNormal(t));
    m.push_back(scene.triangleMagnitudeM(t));
  }
  return estimateAt(rdb, scene, capped, std::move(p), std::move(nn), std::move(m), threads, seed);
}

}  // namespace fly::raytracer
