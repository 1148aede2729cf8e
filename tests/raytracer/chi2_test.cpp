#include "chi2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "raytracer/sampler.h"
#include "raytracer/warp.h"

namespace fly::raytracer::test {
namespace {

TEST(Chi2, IncompleteGammaAgreesWithClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0}) {
    EXPECT_NEAR(regularizedGammaQ(1.0, x), std::exp(-x), 1e-13 + 1e-12 * std::exp(-x)) << x;
    EXPECT_NEAR(regularizedGammaQ(0.5, x), std::erfc(std::sqrt(x)), 1e-13 + 1e-11 * std::erfc(std::sqrt(x)))
        << x;
    // Q(3, x) = e^−x (1 + x + x²/2).
    EXPECT_NEAR(regularizedGammaQ(3.0, x), std::exp(-x) * (1.0 + x + 0.5 * x * x), 1e-12) << x;
  }
  EXPECT_EQ(regularizedGammaQ(2.0, 0.0), 1.0);
}

TEST(Chi2, CriticalValuesAgreeWithTables) {
  // Upper 1 % points of the chi-square distribution (Abramowitz & Stegun, table 26.8).
  EXPECT_NEAR(chi2Critical(0.01, 1), 6.63490, 1e-4);
  EXPECT_NEAR(chi2Critical(0.01, 10), 23.2093, 1e-3);
  EXPECT_NEAR(chi2Critical(0.01, 100), 135.807, 1e-2);
  EXPECT_NEAR(chi2Survival(chi2Critical(1e-4, 2047), 2047), 1e-4, 1e-9);
}

TEST(Chi2, PoolsSparseCellsAndFailsOnSamplesWhereTheDensityIsZero) {
  // Cells expected below 5 are pooled: observed 3 + 1 against expected 3 + 3 is one cell.
  const std::vector<double> observed = {48, 52, 3, 1};
  const std::vector<double> expected = {50, 50, 3, 3};
  const Chi2Result r = chi2Test(observed, expected, 0.01);
  EXPECT_EQ(r.dof, 2);
  EXPECT_NEAR(r.statistic, 4.0 / 50 + 4.0 / 50 + 4.0 / 6, 1e-12);
  EXPECT_TRUE(r.passed());
  const std::vector<double> stray = {50, 49, 1};
  const std::vector<double> none = {50, 50, 0};
  EXPECT_FALSE(chi2Test(stray, none, 0.01).passed());
}

TEST(Chi2, RejectsAWrongDensity) {
  // Uniform directions tested against the cosine-weighted density; and a cone 2 % too wide against its own.
  Chi2Grid hemisphere(32, 64);
  Chi2Grid cone(32, 64);
  RandomSampler sampler(11);
  for (uint32_t i = 0; i < 200'000; ++i) {
    sampler.startSample(i);
    const vec2 u = sampler.next2D();
    const dvec2 a = sphereChart(sampleUniformHemisphere(u));
    hemisphere.add(a.x, a.y);
    const dvec2 b = sphereChart(sampleUniformCone(u, 1.0f * 1.02f));
    cone.add(b.x, b.y);
  }
  const Chi2Result wrongShape = hemisphere.test([](double s, double t) {
    return static_cast<double>(cosineHemispherePdf(static_cast<float>(sphereChartDirection(s, t).z))) *
           kSphereChartJacobian;
  });
  EXPECT_FALSE(wrongShape.passed()) << wrongShape.describe();
  const Chi2Result wrongSupport = cone.test([](double s, double) {
    return s >= 0.5 ? static_cast<double>(uniformConePdf(1.0f)) * kSphereChartJacobian : 0.0;
  });
  EXPECT_FALSE(wrongSupport.passed()) << wrongSupport.describe();
}

}  // namespace
}  // namespace fly::raytracer::test
