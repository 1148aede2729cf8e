#include "sunsky/clear_sky.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "base/error.h"
#include "sky_reference.h"
#include "sunsky/sun_disc.h"

namespace fly::sunsky {
namespace {

bool finiteAndNonNegative(const Rgb& c) {
  return isFinite(c) && c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f;
}

TEST(ClearSky, IntegratesToTheDiffuseIlluminanceItWasNormalisedTo) {
  for (double turbidity : {1.7, 3.0, 6.0, 10.0}) {
    for (double sunZenith : {0.0, 22.0, 60.0, 89.0, 90.0, 95.0, 100.0}) {
      const ClearSky sky = makeClearSky(turbidity, sunZenith, 200.0, 15000.0);
      EXPECT_NEAR(testing::referenceHorizontalIlluminanceLux(sky) / 15000.0, 1.0, 0.005)
          << "T " << turbidity << ", sun zenith " << sunZenith;
    }
  }
}

TEST(ClearSky, PreethamsAbsoluteLuminanceIsIntegratedAccurately) {
  for (double turbidity : {2.0, 3.0, 8.0}) {
    for (double sunZenith : {10.0, 45.0, 80.0}) {
      const ClearSky sky = makeClearSky(turbidity, sunZenith, 90.0);
      EXPECT_NEAR(horizontalIlluminanceLux(sky) / testing::referenceHorizontalIlluminanceLux(sky), 1.0,
                  0.005);
    }
  }
}

TEST(ClearSky, ZenithLuminanceIsPreethamsInCandelaPerSquareMetre) {
  // Yz(T = 3, θs = 22°): χ = (4/9 − 3/120)(π − 2·0.3839724) = 0.9956134, tan χ = 1.5424831,
  // Yz = (4.0453·3 − 4.9710)·1.5424831 − 0.2155·3 + 2.4192 = 12.824437 kcd/m² (+ the night sky, 1.7e-4
  // cd/m²).
  const ClearSky sky = makeClearSky(3.0, 22.0, 180.0);
  EXPECT_NEAR(zenithLuminanceCdM2(sky), 12824.437, 0.01);
}

TEST(ClearSky, ColourFollowsTheSun) {
  // Noon: a blue zenith. Low sun: the sky next to the sun on the horizon turns warmer than at noon.
  const ClearSky noon = makeClearSky(3.0, 25.0, 180.0);
  const Rgb zenith = noon.radianceCdM2(dvec3(0, 0, 1));
  EXPECT_GT(zenith.b, 1.5f * zenith.r);
  const ClearSky dusk = makeClearSky(3.0, 88.0, 270.0);
  const Rgb nearSunDusk = dusk.radianceCdM2(sunDirectionEnu(85.0, 270.0));
  const Rgb nearSunNoon = noon.radianceCdM2(sunDirectionEnu(30.0, 180.0));
  EXPECT_GT(nearSunDusk.r / nearSunDusk.b, 1.3f * (nearSunNoon.r / nearSunNoon.b));
}

TEST(ClearSky, TwilightDarkensMonotonicallyToTheNightSky) {
  for (double turbidity : {kMinTurbidity, 3.0, kMaxTurbidity}) {
    double previousIlluminance = std::numeric_limits<double>::infinity();
    double previousZenith = std::numeric_limits<double>::infinity();
    for (double sunZenith = 88.0; sunZenith <= 180.0; sunZenith += 0.5) {
      const ClearSky sky = makeClearSky(turbidity, sunZenith, 300.0);
      const double e = horizontalIlluminanceLux(sky);
      const double lz = zenithLuminanceCdM2(sky);
      ASSERT_TRUE(std::isfinite(e) && e > 0.0) << sunZenith;
      EXPECT_LE(e, previousIlluminance) << "T " << turbidity << ", sun zenith " << sunZenith;
      EXPECT_LE(lz, previousZenith * (1.0 + 1e-6)) << "T " << turbidity << ", sun zenith " << sunZenith;
      for (double z = 0.0; z <= 90.0; z += 15.0) {
        for (double a = 0.0; a < 360.0; a += 60.0) {
          EXPECT_TRUE(finiteAndNonNegative(sky.radianceCdM2(sunDirectionEnu(z, a))));
        }
      }
      previousIlluminance = e;
      previousZenith = lz;
    }
    // End of civil twilight ≈ 3 lx, end of nautical ≈ 0.008 lx (AMS Glossary), plus the night sky π·1.7e-4.
    const double night = kPi * kNightSkyLuminanceCdM2;
    EXPECT_NEAR(horizontalIlluminanceLux(makeClearSky(turbidity, 96.0, 0.0)), 3.0 + night, 1e-3);
    EXPECT_NEAR(horizontalIlluminanceLux(makeClearSky(turbidity, 102.0, 0.0)), 0.008 + night, 1e-5);
    // Deep night: the natural night sky alone, bluish.
    const ClearSky night180 = makeClearSky(turbidity, 180.0, 0.0);
    EXPECT_NEAR(zenithLuminanceCdM2(night180), kNightSkyLuminanceCdM2, 1e-9);
    const Rgb n = night180.radianceCdM2(dvec3(0, 0, 1));
    EXPECT_GT(n.b, n.r);
  }
}

TEST(ClearSky, ContinuousAcrossTheHorizon) {
  // Twilight falls by 0.58 decades per degree at first (T = 3: 8.8 klx at sunset to 3 lx at 6°), so 10⁻⁴°
  // away the sky may differ by 1.3·10⁻⁴.
  const double above = horizontalIlluminanceLux(makeClearSky(3.0, 89.9999, 90.0));
  const double at = horizontalIlluminanceLux(makeClearSky(3.0, 90.0, 90.0));
  const double below = horizontalIlluminanceLux(makeClearSky(3.0, 90.0001, 90.0));
  EXPECT_NEAR(above / at, 1.0, 1e-3);
  EXPECT_NEAR(below / at, 1.0, 1e-3);
}

TEST(ClearSky, TurbidityAtTheEndsOfItsRangeAndSunAtZenithAndHorizon) {
  for (double turbidity : {kMinTurbidity, kMaxTurbidity}) {
    for (double sunZenith : {0.0, 45.0, 90.0, 100.0}) {
      const ClearSky sky = makeClearSky(turbidity, sunZenith, 45.0);
      for (double z = 0.0; z <= 90.0; z += 5.0) {
        for (double a = 0.0; a < 360.0; a += 20.0) {
          const Rgb l = sky.radianceCdM2(sunDirectionEnu(z, a));
          EXPECT_TRUE(finiteAndNonNegative(l)) << turbidity << " " << sunZenith << " " << z << " " << a;
          EXPECT_GT(luminance(l), 0.0f);
        }
      }
      EXPECT_TRUE(std::isfinite(horizontalIlluminanceLux(sky)));
    }
  }
}

TEST(ClearSky, BlackBelowTheHorizon) {
  EXPECT_EQ(makeClearSky(3.0, 40.0, 0.0).radianceCdM2(dvec3(0.0, 0.8, -0.6)), Rgb(0.0f));
}

TEST(ClearSky, RejectsInvalidInput) {
  EXPECT_THROW(makeClearSky(1.69, 30.0, 0.0), InputError);
  EXPECT_THROW(makeClearSky(10.01, 30.0, 0.0), InputError);
  EXPECT_THROW(makeClearSky(std::nan(""), 30.0, 0.0), InputError);
  EXPECT_THROW(makeClearSky(3.0, -1.0, 0.0), InputError);
  EXPECT_THROW(makeClearSky(3.0, 30.0, 0.0, -5.0), InputError);
  try {
    makeClearSky(12.0, 30.0, 0.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.message(), "turbidity 12 is outside [1.7, 10]");
  }
}

}  // namespace
}  // namespace fly::sunsky

namespace fly::sunsky {
namespace {

TEST(ClearSky, IesHandbookLevelAboveAndBelowTheHorizon) {
  // IES Lighting Handbook clear sky: Dv = 0.8 + 15.5·√(sin α) klx. At α = 68°: 0.8 + 15.5·√0.92718 = 15.725 klx.
  EXPECT_NEAR(iesClearSkyDiffuseLux(68.0), 800.0 + 15500.0 * std::sqrt(std::sin(degToRad(68.0))), 1e-9);
  EXPECT_NEAR(iesClearSkyDiffuseLux(68.0), 15725.1, 0.5);
  EXPECT_EQ(iesClearSkyDiffuseLux(-3.0), 800.0);
  const ClearSky noon = makeClearSky(3.0, 22.0, 180.0, std::nullopt, ClearSkyLevel::kIesHandbook);
  EXPECT_NEAR(horizontalIlluminanceLux(noon), iesClearSkyDiffuseLux(68.0), iesClearSkyDiffuseLux(68.0) * 0.005);
  // The same shape as Preetham's: only the level differs.
  const ClearSky preetham = makeClearSky(3.0, 22.0, 180.0);
  const double ratio = zenithLuminanceCdM2(noon) / zenithLuminanceCdM2(preetham);
  const dvec3 east(1.0, 0.0, 0.2);
  EXPECT_NEAR(luminance(noon.radianceCdM2(glm::normalize(east))) /
                  luminance(preetham.radianceCdM2(glm::normalize(east))),
              ratio, ratio * 1e-4);
  // Continuous across the horizon: twilight starts from the IES sunset value, 0.8 klx.
  const double above = horizontalIlluminanceLux(makeClearSky(3.0, 90.0 - 1e-4, 0.0, std::nullopt, ClearSkyLevel::kIesHandbook));
  const double below = horizontalIlluminanceLux(makeClearSky(3.0, 90.0 + 1e-4, 0.0, std::nullopt, ClearSkyLevel::kIesHandbook));
  // (√(sin α) rises steeply: 10⁻⁴° above the horizon the formula already gives 820 lx.)
  EXPECT_NEAR(above, iesClearSkyDiffuseLux(1e-4), 800.0 * 0.005);
  EXPECT_NEAR(below, 800.0, 800.0 * 0.005);
  EXPECT_LT(above / below, 1.03);
  // End of civil twilight (sun 6° below the horizon): 3 lx (AMS Glossary), plus the night sky.
  const double civil = horizontalIlluminanceLux(makeClearSky(3.0, 96.0, 0.0, std::nullopt, ClearSkyLevel::kIesHandbook));
  EXPECT_NEAR(civil, 3.0 + kPi * kNightSkyLuminanceCdM2, 0.03);
}

}  // namespace
}  // namespace fly::sunsky
