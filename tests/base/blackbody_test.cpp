#include "base/blackbody.h"

#include <gtest/gtest.h>

#include <cmath>

#include "base/cie1931.h"

namespace fly {
namespace {

// Kim, Kang and Hong, "Design of advanced color temperature control system for HDTV applications",
// J. Korean Phys. Soc. 41 (2002): a cubic-spline fit of the Planckian locus for 1667–25000 K, an independent
// computation of the same curve (it agrees with a 1 nm integration to about 5e-4).
dvec2 kimPlanckianLocus(double t) {
  const double x = t <= 4000.0
                       ? -0.2661239e9 / (t * t * t) - 0.2343589e6 / (t * t) + 0.8776956e3 / t + 0.179910
                       : -3.0258469e9 / (t * t * t) + 2.1070379e6 / (t * t) + 0.2226347e3 / t + 0.240390;
  const double y = t <= 2222.0   ? -1.1063814 * x * x * x - 1.34811020 * x * x + 2.18555832 * x - 0.20219683
                   : t <= 4000.0 ? -0.9549476 * x * x * x - 1.37418593 * x * x + 2.09137015 * x - 0.16748867
                                 : 3.0817580 * x * x * x - 5.87338670 * x * x + 3.75112997 * x - 0.37001483;
  return {x, y};
}

// XYZ of a linear Rec.709 colour (the forward matrix of BT.709's primaries and D65).
dvec3 xyzFromRec709(const Rgb& c) {
  const dvec3 r(c);
  return {0.4124564 * r.x + 0.3575761 * r.y + 0.1804375 * r.z,
          0.2126729 * r.x + 0.7151522 * r.y + 0.0721750 * r.z,
          0.0193339 * r.x + 0.1191920 * r.y + 0.9503041 * r.z};
}

TEST(Blackbody, PlanckMatchesTheLawAndWien) {
  // At the peak of Wien's displacement law, λ_max T = 2.897771955e-3 m·K (CODATA 2018), the radiance is
  // largest: its neighbours 1 % away are smaller.
  const double t = 5000.0;
  const double peakNm = 2.897771955e-3 / t * 1e9;
  const double peak = planckSpectralRadiance(peakNm, t);
  EXPECT_GT(peak, planckSpectralRadiance(peakNm * 0.99, t));
  EXPECT_GT(peak, planckSpectralRadiance(peakNm * 1.01, t));
  // The value itself: 2hc²/λ⁵ / (exp(c₂/(λT)) − 1) at 500 nm and 5000 K is 1.21072e13 W m⁻² sr⁻¹ m⁻¹.
  EXPECT_NEAR(planckSpectralRadiance(500.0, 5000.0), 1.21072e13 * 1e-9, 0.00001e13 * 1e-9);
  // Far in the Wien tail exp overflows: 0, not NaN.
  EXPECT_EQ(planckSpectralRadiance(1.0, 1.0), 0.0);
}

TEST(Blackbody, IlluminantAIsThePlanckianRadiatorAt2856K) {
  // Illuminant A is a black body at 2848 K with c₂ = 1.435e-2 m·K (CIE 015:2018 §3.1); with today's c₂ that
  // is T = 2848 × c₂ / 1.435e-2 = 2855.5 K, and its chromaticity is A's published (0.44757, 0.40745).
  const dvec2 xy = planckianChromaticity(2848.0 * kPlanckC2MK / 1.435e-2);
  EXPECT_NEAR(xy.x, 0.44757, 2e-5);
  EXPECT_NEAR(xy.y, 0.40745, 2e-5);
}

TEST(Blackbody, ChromaticityFollowsThePublishedLocus) {
  for (double t = 1667.0; t <= 25000.0; t *= 1.1) {
    SCOPED_TRACE(t);
    const dvec2 xy = planckianChromaticity(t);
    const dvec2 fit = kimPlanckianLocus(t);
    EXPECT_NEAR(xy.x, fit.x, 6e-4);
    EXPECT_NEAR(xy.y, fit.y, 6e-4);
  }
  // A black body at 6504 K is not D65 (0.3127, 0.3290): daylight lies above the Planckian locus.
  const dvec2 p6504 = planckianChromaticity(6504.0);
  EXPECT_NEAR(p6504.x, 0.3135, 1e-4);
  EXPECT_NEAR(p6504.y, 0.3236, 1e-4);
  EXPECT_GT(0.3290 - p6504.y, 0.004);
}

TEST(Blackbody, Rec709ColourHasUnitLuminanceAndTheLocusChromaticity) {
  for (double t = kMinColourTemperatureK; t <= kMaxColourTemperatureK; t *= 1.05) {
    SCOPED_TRACE(t);
    const Rgb c = planckianRec709(t);
    ASSERT_TRUE(isFinite(c));
    EXPECT_NEAR(luminance(c), 1.0f, 1e-6f);
    EXPECT_GE(std::min({c.r, c.g, c.b}), 0.0f);
    if (t >= 2000.0) {  // inside the Rec.709 gamut: the colour is the black body's exactly
      const dvec2 xy = chromaticity(xyzFromRec709(c));
      const dvec2 locus = planckianChromaticity(t);
      EXPECT_NEAR(xy.x, locus.x, 2e-5);
      EXPECT_NEAR(xy.y, locus.y, 2e-5);
    }
  }
  // Warm light is red-heavy, cold light blue-heavy; 2700 K (a warm-white lamp) has R > G > B.
  const Rgb warm = planckianRec709(2700.0);
  EXPECT_GT(warm.r, warm.g);
  EXPECT_GT(warm.g, warm.b);
  const Rgb cold = planckianRec709(20000.0);
  EXPECT_GT(cold.b, cold.g);
}

TEST(Blackbody, OutOfGamutTemperaturesAreDesaturatedTowardsWhite) {
  // At 1000 K the locus lies outside Rec.709 (blue < 0): the colour lies on the line from white (1, 1, 1)
  // through the black body's own colour, where blue reaches 0.
  const Rgb c = planckianRec709(1000.0);
  EXPECT_EQ(c.b, 0.0f);
  const dvec2 white(0.3127, 0.3290);
  const dvec2 locus = planckianChromaticity(1000.0);
  const dvec2 mapped = chromaticity(xyzFromRec709(c));
  // Collinear: the cross product of (locus − white) and (mapped − white) is 0; mapped lies between them.
  const dvec2 a = locus - white;
  const dvec2 b = mapped - white;
  EXPECT_NEAR(a.x * b.y - a.y * b.x, 0.0, 2e-5);
  EXPECT_GT(glm::length(b), 0.8 * glm::length(a));
  EXPECT_LT(glm::length(b), glm::length(a));
}

}  // namespace
}  // namespace fly
