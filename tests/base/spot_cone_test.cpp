#include "base/spot_cone.h"

#include <gtest/gtest.h>

#include <cmath>

#include "base/math.h"

namespace fly {
namespace {

// ∫ spotConeAttenuation dω over the sphere by the midpoint rule in θ (dω = 2π sin θ dθ, the cone being
// symmetric about its axis), evaluating the very function the baker uses.
double integrateAttenuationSr(double innerRad, double outerRad, int steps) {
  const float cosInner = static_cast<float>(std::cos(innerRad));
  const float cosOuter = static_cast<float>(std::cos(outerRad));
  double sum = 0.0;
  const double dTheta = kPi / steps;
  for (int i = 0; i < steps; ++i) {
    const double theta = (i + 0.5) * dTheta;
    sum += spotConeAttenuation(static_cast<float>(std::cos(theta)), cosInner, cosOuter) * std::sin(theta);
  }
  return 2.0 * kPi * sum * dTheta;
}

TEST(SpotCone, SolidAngleMatchesNumericalIntegration) {
  const struct {
    double innerDeg, outerDeg;
  } cones[] = {{0, 45}, {20, 30}, {0, 90}, {60, 90}, {10, 10.01}, {44.99, 45}, {0, 1}, {0.5, 2}, {5, 80}};
  for (const auto& c : cones) {
    SCOPED_TRACE(::testing::Message() << c.innerDeg << "° – " << c.outerDeg << "°");
    const double cosInner = std::cos(degToRad(c.innerDeg));
    const double cosOuter = std::cos(degToRad(c.outerDeg));
    const double exact = spotConeSolidAngleSr(static_cast<float>(cosInner), static_cast<float>(cosOuter));
    const double numeric = integrateAttenuationSr(degToRad(c.innerDeg), degToRad(c.outerDeg), 400000);
    EXPECT_NEAR(exact, numeric, 1e-4 * exact + 1e-9);
  }
}

TEST(SpotCone, ClosedFormsOfSimpleCones) {
  // A hemisphere ramp, inner 0, outer 90°: the attenuation is cos² θ, ∫ cos² θ dω = 2π/3.
  EXPECT_NEAR(spotConeSolidAngleSr(1.0, 0.0), 2.0 * kPi / 3.0, 1e-12);
  // inner 20°, outer 30°: 2π [(1 − cos 20°) + (cos 20° − cos 30°)/3].
  const double ci = std::cos(degToRad(20.0));
  const double co = std::cos(degToRad(30.0));
  EXPECT_NEAR(spotConeSolidAngleSr(ci, co), 2.0 * kPi * ((1.0 - ci) + (ci - co) / 3.0), 1e-12);
  // A very narrow cone (outer 1°, less than the 0.001 ramp): still positive and below the cone's own solid
  // angle 2π (1 − cos 1°).
  const double narrow = spotConeSolidAngleSr(1.0, std::cos(degToRad(1.0)));
  EXPECT_GT(narrow, 0.0);
  EXPECT_LT(narrow, 2.0 * kPi * (1.0 - std::cos(degToRad(1.0))));
}

TEST(SpotCone, AttenuationEnds) {
  const float ci = std::cos(0.3f), co = std::cos(0.5f);
  EXPECT_EQ(spotConeAttenuation(1.0f, ci, co), 1.0f);
  EXPECT_EQ(spotConeAttenuation(ci, ci, co), 1.0f);
  EXPECT_EQ(spotConeAttenuation(co, ci, co), 0.0f);
  EXPECT_EQ(spotConeAttenuation(-1.0f, ci, co), 0.0f);
  EXPECT_NEAR(spotConeAttenuation(0.5f * (ci + co), ci, co), 0.25f, 1e-6f);
}

}  // namespace
}  // namespace fly
