// Clear glass's transmittance (base/clear_pane.h): against the slab of two Fresnel faces written out
// independently (tests/support/slab_reference.h, double precision), at its extremes (grazing incidence,
// indices near 1 and high, no transmission, full transmission) finite and within the energy rule's bounds,
// and equal to the rule at normal incidence.
#include "base/clear_pane.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "base/math.h"
#include "../support/slab_reference.h"

namespace fly {
namespace {

using test::bisectedTau0;
using test::slab;

double schlick(double c, double f0) {
  return f0 + (1.0 - f0) * std::pow(1.0 - c, 5.0);
}

float f0Of(double n) {
  return static_cast<float>(std::pow((n - 1.0) / (n + 1.0), 2.0));
}

TEST(ClearPane, FollowsTheSlabOfTwoFresnelFacesWithAbsorption) {
  for (const double n : {1.33, 1.5, 1.526, 1.9}) {
    const float f0 = f0Of(n);
    for (const float t : {0.2f, 0.6f, 0.92f, 1.0f}) {
      const ClearPane pane(f0, Rgb(t), Rgb(1.0f));
      const double normalT = t * (1.0 - f0);
      EXPECT_NEAR(pane.normalTransmittance().g, normalT, 1e-6);
      const double tau0 = bisectedTau0(n, normalT);
      EXPECT_NEAR(slabInternalTransmittance(f0, float(normalT)), tau0, 2e-6) << n << " " << t;
      double previous = 2.0;
      for (const double deg : {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0}) {
        const double c = std::cos(degToRad(deg));
        const double expected = normalT * slab(c, n, tau0) / slab(1.0, n, tau0);
        const float got = pane.at(float(c)).g;
        EXPECT_NEAR(got, expected, 2e-6) << "n " << n << ", t " << t << ", " << deg << "°";
        EXPECT_LE(got, t * (1.0 - schlick(c, f0)) + 1e-6) << "n " << n << ", t " << t << ", " << deg << "°";
        EXPECT_LE(got, previous);  // falls from normal incidence to grazing
        previous = got;
        EXPECT_EQ(pane.at(float(-c)), pane.at(float(c)));  // either face
      }
    }
  }
}

// τ0's closed form is S(0)'s inverse below the lossless slab's (1 − R0)/(1 + R0), and 1 above, where the
// lossless slab's shape is scaled to T_n.
TEST(ClearPane, InternalTransmittanceInvertsTheSlabAtNormalIncidence) {
  for (const double n : {1.0001, 1.5, 2.5, 4.0}) {
    const float r0 = f0Of(n);
    const double lossless = (1.0 - r0) / (1.0 + r0);
    for (const float normalT : {0.0f, 1e-6f, 0.3f, 0.8f, 0.9166f, 0.999f, 1.0f}) {
      const float tau0 = slabInternalTransmittance(r0, normalT);
      ASSERT_TRUE(std::isfinite(tau0));
      EXPECT_GE(tau0, 0.0f);
      EXPECT_LE(tau0, 1.0f);
      if (normalT < lossless - 1e-6) {
        EXPECT_NEAR(slabTransmittance(1.0f, float(n), tau0), normalT, 2e-6) << n << " " << normalT;
      } else {
        EXPECT_EQ(tau0, 1.0f) << n << " " << normalT;
      }
    }
  }
  // Full transmission without reflection colour: T_n = 1 at normal incidence, the lossless slab's fall-off
  // beyond.
  const ClearPane clear(f0Of(1.5), Rgb(1.0f), Rgb(0.0f));
  EXPECT_NEAR(clear.at(1.0f).g, 1.0f, 1e-6f);
  const double c = std::cos(degToRad(60.0));
  EXPECT_NEAR(clear.at(float(c)).g, slab(c, 1.5, 1.0) / slab(1.0, 1.5, 1.0), 2e-6);
}

// The extremes: every angle up to grazing (89.9°, 90°), indices from 1.0001 to 2.5, T_n from 0 to 1: T is
// finite, in [0, 1], T_n at normal incidence, 0 at grazing (both faces reflect all there), and never above
// the energy rule's t (1 − r F(θ)), so never above 1 − R(θ), R = r F(θ) what the pane reflects.
TEST(ClearPane, StaysFiniteAndWithinTheEnergyRuleAtItsExtremes) {
  for (const double n : {1.0001, 1.5, 2.5}) {
    const float f0 = f0Of(n);
    for (const float normalT : {0.0f, 0.5f, 0.9166f, 1.0f}) {
      // Colours that give T_n = t (1 − r F0): white reflection where it can, less where T_n > 1 − F0.
      const float r = normalT > 1.0f - f0 ? (1.0f - normalT) / f0 : 1.0f;
      const float t = normalT > 1.0f - f0 ? 1.0f : normalT / (1.0f - f0);
      const ClearPane pane(f0, Rgb(t, 0.5f * t, 0.0f), Rgb(r));
      EXPECT_NEAR(pane.normalTransmittance().r, normalT, 1e-6f);
      for (const double deg : {0.0, 30.0, 60.0, 89.0, 89.9, 90.0}) {
        const float c = deg == 90.0 ? 0.0f : float(std::cos(degToRad(deg)));
        const std::string label =
            "n " + std::to_string(n) + ", T_n " + std::to_string(normalT) + ", " + std::to_string(deg) + "°";
        const Rgb got = pane.at(c);
        ASSERT_TRUE(isFinite(got)) << label;
        EXPECT_GE(got.r, 0.0f) << label;
        EXPECT_LE(got.r, 1.0f) << label;
        const double reflected = r * schlick(c, f0);
        EXPECT_LE(got.r, 1.0 - reflected + 1e-6) << label;
        EXPECT_LE(got.r, t * (1.0 - reflected) + 1e-6) << label;
        EXPECT_LE(got.g, 0.5 * t * (1.0 - reflected) + 1e-6) << label;
        EXPECT_EQ(got.b, 0.0f) << label;
        if (deg == 0.0) EXPECT_NEAR(got.r, normalT, 1e-6f) << label;
        if (deg == 90.0) EXPECT_EQ(got.r, 0.0f) << label;
      }
    }
  }
  // Index 1 (F0 = 0) and the largest: no reflection at the faces, or nearly all.
  for (const float f0 : {0.0f, 1.0f}) {
    const ClearPane pane(f0, Rgb(0.7f), Rgb(1.0f));
    for (const float c : {1.0f, 0.5f, 1e-3f, 0.0f}) ASSERT_TRUE(isFinite(pane.at(c))) << f0 << " " << c;
  }
}

// Uniform reflection has no index: T = t (1 − r) at every angle, the energy rule's.
TEST(ClearPane, UniformReflectionTransmitsTheSameAtEveryAngle) {
  const ClearPane pane(-1.0f, Rgb(0.9f, 0.8f, 0.7f), Rgb(0.1f, 0.2f, 0.3f));
  for (const float c : {1.0f, 0.5f, 0.0f}) {
    const Rgb t = pane.at(c);
    EXPECT_NEAR(t.r, 0.9f * 0.9f, 1e-6f);
    EXPECT_NEAR(t.g, 0.8f * 0.8f, 1e-6f);
    EXPECT_NEAR(t.b, 0.7f * 0.7f, 1e-6f);
  }
}

}  // namespace
}  // namespace fly
