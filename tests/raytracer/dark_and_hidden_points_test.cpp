// The progressive driver's stopping rule with points that nobody sees (SampleSource::isHidden) and points far
// darker than the rest (kDarkShare): neither holds an estimate back, and neither changes what is reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "raytracer/progressive.h"

namespace fly::raytracer {
namespace {

// Points 0 … 89 bright (1000 lx, ±10 % per sample), 90 … 94 dark (10⁻⁶ lx, ±100 % per sample), 95 … 99
// hidden (10 lx, ±100 %).
class MixedSource final : public SampleSourceOf<MixedSource> {
  friend SampleSourceOf<MixedSource>;

 public:
  size_t pointCount() const override { return 100; }
  bool isHidden(size_t point) const override { return point >= 95; }

 private:
  template <class S>
  Rgb sampleAt(size_t point, S& sampler, uint64_t& rays) const {
    sampler.startGroup(0);
    const float u = sampler.next1D();
    ++rays;
    if (point < 90) return Rgb(1000.0f * (0.9f + 0.2f * u));
    if (point < 95) return Rgb(2e-6f * u);
    return Rgb(20.0f * u);
  }
};

TEST(DarkAndHiddenPoints, NeitherHoldsTheEstimateBack) {
  const MixedSource source;
  EstimateSettings settings;
  settings.firstPassSamples = 16;
  settings.maxSamples = 4096;
  settings.replicates = 8;
  settings.sampler = SamplerKind::kRandom;  // plain Monte Carlo: errors fall as 1/√n
  settings.targetRelativeError = 0.01f;
  settings.threads = 2;
  const EstimateResult r = estimateProgressively(source, settings);
  // The floor: kDarkShare of the 95th percentile of the visible points' irradiance (1000 lx).
  EXPECT_NEAR(r.darkFloorLux, kDarkShare * 1000.0f, 0.05f * kDarkShare * 1000.0f);
  // The bright points' relative error per sample is 0.2/√12 / 1 ≈ 5.8 %: 1 % takes about 34 samples, so the
  // estimate stops at 64, although the dark points' own relative error (58 % per sample) would need 3 000×
  // more and the hidden ones are never refined.
  EXPECT_LE(r.samplesPerPoint, 128u);
  EXPECT_LE(r.relativeErrorP95, 0.01f);
  for (size_t i = 95; i < 100; ++i) EXPECT_EQ(r.points[i].samples, 16u) << "hidden point " << i;
  for (size_t i = 0; i < 95; ++i) EXPECT_EQ(r.points[i].samples, r.samplesPerPoint) << "point " << i;
  // The reported errors are each point's own: the dark points' relative error stays large.
  for (size_t i = 90; i < 95; ++i) {
    EXPECT_GT(luminance(r.points[i].stdErrorLux) / luminance(r.points[i].meanLux), 0.02f) << "dark point " << i;
  }
  // The percentile recomputed here: over the 95 visible points, errors of the dark ones against the floor.
  std::vector<float> rel;
  for (size_t i = 0; i < 95; ++i) {
    rel.push_back(luminance(r.points[i].stdErrorLux) /
                  std::max(luminance(r.points[i].meanLux), r.darkFloorLux));
  }
  std::sort(rel.begin(), rel.end());
  EXPECT_FLOAT_EQ(r.relativeErrorP95, rel[size_t(std::ceil(0.95 * 95.0)) - 1]);
}

}  // namespace
}  // namespace fly::raytracer
