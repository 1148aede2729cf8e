#include "sunsky/sun_disc.h"

#include <gtest/gtest.h>

#include <cmath>

#include "base/error.h"
#include "sunsky/clear_sky.h"
#include "sunsky/sky.h"

namespace fly::sunsky {
namespace {

SunDiscInput sunAt(double zenithDeg, double turbidity = 3.0) {
  SunDiscInput in;
  in.zenithDeg = zenithDeg;
  in.azimuthDeg = 180.0;
  in.turbidity = turbidity;
  return in;
}

TEST(SunDisc, AirMassAgreesWithKastenYoung) {
  // m = 1/(cos Z + 0.50572 (96.07995 − Z)^−1.6364): m(0) = 0.9997120, m(30°) = 1.1539922, m(60°) = 1.9942929,
  // m(90°) = 1/(0.50572·6.07995^−1.6364) = 37.9196084.
  EXPECT_NEAR(relativeAirMass(0.0), 0.9997120, 1e-7);
  EXPECT_NEAR(relativeAirMass(30.0), 1.1539922, 1e-7);
  EXPECT_NEAR(relativeAirMass(60.0), 1.9942929, 1e-7);
  EXPECT_NEAR(relativeAirMass(90.0), 37.9196084, 1e-6);
  EXPECT_NEAR(relativeAirMass(120.0), relativeAirMass(90.0), 1e-12);
}

TEST(SunDisc, EccentricityAndSolidAngle) {
  // Spencer 1971 on 1 January (Γ = 0): 1.000110 + 0.034221 + 0.000719 = 1.035050; on 1 July (day 182):
  // 0.9666475. Disc: 2π(1 − cos 0.2665°) = 6.7967·10⁻⁵ sr.
  EXPECT_NEAR(eccentricityCorrection(1), 1.035050, 1e-9);
  EXPECT_NEAR(eccentricityCorrection(182), 0.9666475, 1e-7);
  EXPECT_NEAR(sunDiscSolidAngleSr(), 6.7967e-5, 1e-9);
  EXPECT_THROW(eccentricityCorrection(0), InputError);
}

TEST(SunDisc, RadianceIsIlluminanceOverTheDiscSolidAngle) {
  const SunDisc sun = clearSkySunDisc(sunAt(30.0));
  EXPECT_NEAR(sun.dirEnu.z, std::cos(degToRad(30.0)), 1e-12);
  EXPECT_NEAR(luminance(sun.radianceCdM2) * sunDiscSolidAngleSr() / luminance(sun.normalIlluminanceLux), 1.0,
              1e-6);
  // The sun's mean luminance is of the order of 1.6·10⁹ cd/m² at high sun.
  EXPECT_GT(luminance(sun.radianceCdM2), 1.0e9f);
  EXPECT_LT(luminance(sun.radianceCdM2), 2.0e9f);
}

TEST(SunDisc, IlluminanceFallsWithAirMassAndTurbidityAndRisesWithAltitude) {
  double previous = kLuminousSolarConstantLux;
  for (double zenith = 0.0; zenith <= 90.0; zenith += 5.0) {
    const double e = luminance(clearSkySunDisc(sunAt(zenith)).normalIlluminanceLux);
    EXPECT_LT(e, previous) << zenith;
    EXPECT_GT(e, 0.0) << zenith;
    previous = e;
  }
  EXPECT_GT(luminance(clearSkySunDisc(sunAt(30.0, 2.0)).normalIlluminanceLux),
            luminance(clearSkySunDisc(sunAt(30.0, 6.0)).normalIlluminanceLux));
  SunDiscInput mountain = sunAt(30.0);
  mountain.pressureHpa = 700.0;
  EXPECT_GT(luminance(clearSkySunDisc(mountain).normalIlluminanceLux),
            luminance(clearSkySunDisc(sunAt(30.0)).normalIlluminanceLux));
}

TEST(SunDisc, ReddensTowardsTheHorizon) {
  // Elevation 60°: near white (R/B ≈ 1.6, a ≈ 5000 K sun); elevation 5°: orange-red (R/B ≈ 26).
  const Rgb high = clearSkySunDisc(sunAt(30.0)).normalIlluminanceLux;
  const Rgb low = clearSkySunDisc(sunAt(85.0)).normalIlluminanceLux;
  EXPECT_LT(high.r / high.b, 2.0f);
  EXPECT_GT(high.g / high.r, 0.75f);
  EXPECT_GT(low.r / low.b, 10.0f * (high.r / high.b));
  EXPECT_LT(low.g / low.r, 0.5f);
}

TEST(SunDisc, BelowTheHorizonIsDarkAndAtTheHorizonFinite) {
  for (double zenith : {90.5, 120.0, 180.0}) {
    const SunDisc sun = clearSkySunDisc(sunAt(zenith));
    EXPECT_EQ(sun.normalIlluminanceLux, Rgb(0.0f));
    EXPECT_EQ(sun.radianceCdM2, Rgb(0.0f));
    EXPECT_LT(sun.dirEnu.z, 0.0);
  }
  for (double turbidity : {kMinTurbidity, kMaxTurbidity}) {
    for (double zenith : {0.0, 90.0}) {
      const SunDisc sun = clearSkySunDisc(sunAt(zenith, turbidity));
      EXPECT_TRUE(isFinite(sun.normalIlluminanceLux) && isFinite(sun.radianceCdM2));
      EXPECT_GE(sun.normalIlluminanceLux.b, 0.0f);
      EXPECT_GT(luminance(sun.normalIlluminanceLux), 0.0f);
      EXPECT_LT(luminance(sun.normalIlluminanceLux), kLuminousSolarConstantLux * eccentricityCorrection(172));
    }
  }
}

TEST(SunDisc, MeasuredIlluminanceKeepsTheModelsColour) {
  const SunDisc model = clearSkySunDisc(sunAt(70.0));
  const SunDisc measured = sunDiscWithIlluminance(sunAt(70.0), 40000.0);
  EXPECT_NEAR(luminance(measured.normalIlluminanceLux), 40000.0f, 0.5f);
  EXPECT_NEAR(measured.normalIlluminanceLux.r / measured.normalIlluminanceLux.b,
              model.normalIlluminanceLux.r / model.normalIlluminanceLux.b, 1e-4);
  EXPECT_EQ(sunDiscWithIlluminance(sunAt(95.0), 40000.0).normalIlluminanceLux, Rgb(0.0f));
  EXPECT_THROW(sunDiscWithIlluminance(sunAt(30.0), 200000.0), InputError);
  EXPECT_THROW(sunDiscWithIlluminance(sunAt(30.0), -1.0), InputError);
}

TEST(SunDisc, RejectsInvalidInput) {
  EXPECT_THROW(clearSkySunDisc(sunAt(30.0, 1.0)), InputError);
  EXPECT_THROW(clearSkySunDisc(sunAt(30.0, 11.0)), InputError);
  EXPECT_THROW(clearSkySunDisc(sunAt(-5.0)), InputError);
  SunDiscInput in = sunAt(30.0);
  in.pressureHpa = 50.0;
  EXPECT_THROW(clearSkySunDisc(in), InputError);
  in = sunAt(30.0);
  in.dayOfYear = 400;
  EXPECT_THROW(clearSkySunDisc(in), InputError);
}

TEST(ClearSkyAndSun, SummerNoonAtMidLatitudeGivesEightyToHundredTwentyKilolux) {
  // 45° N on 21 June (day 172): the sun transits at zenith 45° − 23.44° ≈ 22°; turbidity 3.
  SunDiscInput in = sunAt(22.0);
  in.dayOfYear = 172;
  const double sunOnHorizontal =
      luminance(clearSkySunDisc(in).normalIlluminanceLux) * std::cos(degToRad(22.0));
  const double sky = horizontalIlluminanceLux(makeClearSky(3.0, 22.0, 180.0));
  const double global = sunOnHorizontal + sky;
  EXPECT_GT(global, 80000.0);
  EXPECT_LT(global, 120000.0);
  EXPECT_GT(sunOnHorizontal, sky);
}

}  // namespace
}  // namespace fly::sunsky
