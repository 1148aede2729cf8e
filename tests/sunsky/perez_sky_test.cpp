#include "sunsky/perez_sky.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "base/error.h"
#include "sky_reference.h"
#include "sunsky/sun_disc.h"

namespace fly::sunsky {
namespace {

PerezSkyInput irradiance(double zenithDeg, double directNormalWm2, double diffuseHorizontalWm2) {
  PerezSkyInput in;
  in.sunZenithDeg = zenithDeg;
  in.sunAzimuthDeg = 160.0;
  in.directNormal = directNormalWm2;
  in.diffuseHorizontal = diffuseHorizontalWm2;
  return in;
}

// Every ε bin, at several sun heights: at Z = 40° (1.041·Z³ = 0.354) the pairs below give
// ε = 1, 1.10, 1.30, 1.74, 2.48, 3.95, 5.43, 8.85.
constexpr double kDirectDiffusePairs[8][2] = {{0, 150},   {20, 150},  {60, 150},  {150, 150},
                                              {300, 150}, {400, 100}, {600, 100}, {850, 80}};

TEST(PerezSky, EveryBinIntegratesToTheDiffuseIlluminanceItWasNormalisedTo) {
  std::set<int> bins;
  for (double zenith : {10.0, 40.0, 70.0, 85.0}) {
    for (const auto& [direct, diffuse] : kDirectDiffusePairs) {
      const PerezSky sky = makePerezSky(irradiance(zenith, direct, diffuse));
      bins.insert(sky.condition().bin);
      const double lux = testing::referenceHorizontalIlluminanceLux(sky);
      EXPECT_NEAR(lux / sky.diffuseHorizontalLux(), 1.0, 0.005)
          << "Z " << zenith << " I " << direct << " Dh " << diffuse << " bin " << sky.condition().bin;
    }
  }
  EXPECT_EQ(bins.size(), 8u);
}

TEST(PerezSky, ConditionAgreesWithHandComputation) {
  // Z = 30° = 0.5235988 rad: 1.041·Z³ = 0.1494330; I = 600, Dh = 100 W/m² on 1 January:
  //   ε = ((100 + 600)/100 + 0.1494330) / 1.1494330 = 6.2199648 (bin 8: ε ≥ 6.2)
  //   m(30°) = 1/(cos 30° + 0.50572·66.07995^−1.6364) = 1.1539922; (r0/r)² on day 1 = 1.03505
  //   Δ = 100 · 1.1539922 / (1367 · 1.03505) = 0.0815592
  const PerezSkyCondition c = perezSkyCondition(30.0, 600.0, 100.0, 1);
  EXPECT_NEAR(c.clearness, 6.2199648, 1e-6);
  EXPECT_NEAR(c.brightness, 0.0815592, 1e-7);
  EXPECT_EQ(c.bin, 8);
  EXPECT_EQ(perezSkyCondition(30.0, 0.0, 100.0, 1).bin, 1);
  EXPECT_DOUBLE_EQ(perezSkyCondition(30.0, 0.0, 100.0, 1).clearness, 1.0);
}

TEST(PerezEfficacy, AgreesWithHandComputation) {
  // Bin 1, Z = 60°, W = 2 cm, Δ = 0.2:
  //   Kd = 97.24 − 0.46·2 + 12.00·cos 60° − 8.91·ln 0.2 = 116.6600918
  //   Kb = 57.20 − 4.55·2 − 2.98·e^{5.73·1.0471976 − 5} + 117.12·0.2 = 63.4199392
  PerezEfficacy k = perezLuminousEfficacy({1.0, 0.2, 1}, 60.0, 2.0);
  EXPECT_NEAR(k.diffuseLmPerW, 116.6600918, 1e-6);
  EXPECT_NEAR(k.directLmPerW, 63.4199392, 1e-6);
  // Bin 8, Z = 30°, W = 1.5 cm, Δ = 0.1:
  //   Kd = 152.23 + 0.35·1.5 − 45.27·cos 30° − 7.98·ln 0.1 = 131.9246590
  //   Kb = 101.18 + 1.58·1.5 − 1.10·e^{5.73·0.5235988 − 5} − 8.29·0.1 = 102.5720983
  k = perezLuminousEfficacy({8.0, 0.1, 8}, 30.0, 1.5);
  EXPECT_NEAR(k.diffuseLmPerW, 131.9246590, 1e-6);
  EXPECT_NEAR(k.directLmPerW, 102.5720983, 1e-6);
  // Bin 5, Z = 45°, W = 3 cm, Δ = 0.3:
  //   Kd = 100.71 + 5.94·3 − 22.75·cos 45° − 23.74·ln 0.3 = 131.0256351
  //   Kb = 106.36 − 3.97·3 − 1.75·e^{5.73·0.7853982 − 5} − 6.16·0.3 = 91.5402194
  k = perezLuminousEfficacy({2.0, 0.3, 5}, 45.0, 3.0);
  EXPECT_NEAR(k.diffuseLmPerW, 131.0256351, 1e-6);
  EXPECT_NEAR(k.directLmPerW, 91.5402194, 1e-6);
  // Δ is limited to ≥ 0.01, so ln Δ stays finite.
  EXPECT_TRUE(std::isfinite(perezLuminousEfficacy({1.0, 0.0, 1}, 60.0, 2.0).diffuseLmPerW));
}

TEST(PerezEfficacy, PrecipitableWaterFromDewPoint) {
  // W = exp(0.07·10 − 0.075) = e^{0.625} = 1.8682460 cm.
  EXPECT_NEAR(precipitableWaterCm(10.0), 1.8682460, 1e-7);
  EXPECT_THROW(precipitableWaterCm(100.0), InputError);
}

TEST(PerezSky, IrradianceIsConvertedWithTheEfficacyModel) {
  PerezSkyInput in = irradiance(35.0, 700.0, 110.0);
  in.dewPointC = 10.0;
  const PerezSky sky = makePerezSky(in);
  const PerezEfficacy k = perezLuminousEfficacy(sky.condition(), 35.0, precipitableWaterCm(10.0));
  EXPECT_DOUBLE_EQ(sky.directNormalLux(), 700.0 * k.directLmPerW);
  EXPECT_DOUBLE_EQ(sky.diffuseHorizontalLux(), 110.0 * k.diffuseLmPerW);
  EXPECT_NEAR(horizontalIlluminanceLux(sky) / sky.diffuseHorizontalLux(), 1.0, 1e-6);
  // A clear sky: brighter towards the sun than away from it, and neutral in colour.
  const Rgb nearSun = sky.radianceCdM2(sunDirectionEnu(45.0, 160.0));
  EXPECT_GT(luminance(nearSun), 2.0f * luminance(sky.radianceCdM2(sunDirectionEnu(45.0, 340.0))));
  EXPECT_EQ(nearSun.r, nearSun.b);
}

TEST(PerezSky, IlluminanceInputGivesTheSameSkyAsTheIrradianceItCameFrom) {
  for (const auto& [direct, diffuse] : kDirectDiffusePairs) {
    const PerezSky fromWm2 = makePerezSky(irradiance(40.0, direct, diffuse));
    PerezSkyInput lux = irradiance(40.0, fromWm2.directNormalLux(), fromWm2.diffuseHorizontalLux());
    lux.units = PerezSkyInput::Units::kIlluminanceLux;
    const PerezSky fromLux = makePerezSky(lux);
    EXPECT_EQ(fromLux.condition().bin, fromWm2.condition().bin);
    EXPECT_NEAR(fromLux.condition().clearness, fromWm2.condition().clearness, 1e-4);
    EXPECT_NEAR(fromLux.condition().brightness, fromWm2.condition().brightness, 1e-5);
    EXPECT_DOUBLE_EQ(fromLux.diffuseHorizontalLux(), fromWm2.diffuseHorizontalLux());
    EXPECT_NEAR(
        luminance(fromLux.radianceCdM2(dvec3(0, 0, 1))) / luminance(fromWm2.radianceCdM2(dvec3(0, 0, 1))),
        1.0, 1e-4);
  }
}

TEST(PerezSky, NegativeLuminanceIsClampedBeforeNormalising) {
  // Bin 6 with a low brightness (Z = 30°, Δ ≈ 0.05, ε ≈ 3.5): the fitted coefficients give a sky negative
  // over about a third of the hemisphere, near the horizon; it is clamped to 0 and the rest carries Dv.
  const PerezSky sky = makePerezSky(irradiance(30.0, 165.0, 57.3));
  ASSERT_EQ(sky.condition().bin, 6);
  ASSERT_FALSE(sky.uniformFallback());
  int black = 0;
  for (double z = 0.0; z <= 90.0; z += 5.0) {
    for (double a = 0.0; a < 360.0; a += 30.0) {
      const float l = luminance(sky.radianceCdM2(sunDirectionEnu(z, a)));
      EXPECT_GE(l, 0.0f);
      black += l == 0.0f;
    }
  }
  EXPECT_GT(black, 0);
  EXPECT_NEAR(testing::referenceHorizontalIlluminanceLux(sky) / sky.diffuseHorizontalLux(), 1.0, 0.005);
}

TEST(PerezSky, MostlyNegativeSkyFallsBackToUniform) {
  // Z = 45°, I = 50, Dh = 10 W/m²: ε = 4.3 (bin 6) with Δ at its floor 0.01; the model is negative over most
  // of the sky.
  const PerezSky sky = makePerezSky(irradiance(45.0, 50.0, 10.0));
  ASSERT_TRUE(sky.uniformFallback());
  const float expected = float(sky.diffuseHorizontalLux() / kPi);
  EXPECT_FLOAT_EQ(luminance(sky.radianceCdM2(dvec3(0, 0, 1))), expected);
  EXPECT_FLOAT_EQ(luminance(sky.radianceCdM2(sunDirectionEnu(80.0, 10.0))), expected);
  EXPECT_NEAR(horizontalIlluminanceLux(sky) / sky.diffuseHorizontalLux(), 1.0, 1e-6);
}

TEST(PerezSky, ZeroDiffuseGivesABlackSky) {
  const PerezSky sky = makePerezSky(irradiance(30.0, 800.0, 0.0));
  EXPECT_GT(sky.directNormalLux(), 50000.0);
  EXPECT_EQ(sky.diffuseHorizontalLux(), 0.0);
  EXPECT_EQ(sky.radianceCdM2(dvec3(0, 0, 1)), Rgb(0.0f));
  EXPECT_EQ(horizontalIlluminanceLux(sky), 0.0);
}

TEST(PerezSky, SunBelowTheHorizonIsOvercastWithTheSunOnTheHorizon) {
  const PerezSky sky = makePerezSky(irradiance(93.0, 100.0, 20.0));
  EXPECT_EQ(sky.condition().bin, 1);
  EXPECT_EQ(sky.directNormalLux(), 0.0);
  EXPECT_NEAR(sky.sunDirEnu().z, 0.0, 1e-12);
  EXPECT_GT(sky.diffuseHorizontalLux(), 0.0);
  EXPECT_NEAR(testing::referenceHorizontalIlluminanceLux(sky) / sky.diffuseHorizontalLux(), 1.0, 0.005);
}

TEST(PerezSky, SunAtTheZenithAndAtTheHorizon) {
  for (double zenith : {0.0, 90.0}) {
    for (const auto& [direct, diffuse] : kDirectDiffusePairs) {
      const PerezSky sky = makePerezSky(irradiance(zenith, direct, diffuse));
      for (double z = 0.0; z <= 90.0; z += 10.0) {
        for (double a = 0.0; a < 360.0; a += 40.0) {
          const float l = luminance(sky.radianceCdM2(sunDirectionEnu(z, a)));
          EXPECT_TRUE(std::isfinite(l) && l >= 0.0f);
        }
      }
      EXPECT_NEAR(testing::referenceHorizontalIlluminanceLux(sky) / sky.diffuseHorizontalLux(), 1.0, 0.005)
          << zenith << " " << direct << " " << diffuse;
    }
  }
}

TEST(PerezSky, RejectsInvalidInput) {
  EXPECT_THROW(makePerezSky(irradiance(30.0, -1.0, 100.0)), InputError);
  EXPECT_THROW(makePerezSky(irradiance(30.0, 100.0, std::nan(""))), InputError);
  EXPECT_THROW(makePerezSky(irradiance(30.0, 1500.0, 100.0)), InputError);  // above the solar constant
  EXPECT_THROW(makePerezSky(irradiance(190.0, 100.0, 100.0)), InputError);
  PerezSkyInput in = irradiance(30.0, 100.0, 100.0);
  in.dayOfYear = 367;
  EXPECT_THROW(makePerezSky(in), InputError);
  in = irradiance(30.0, 140000.0, 100.0);
  in.units = PerezSkyInput::Units::kIlluminanceLux;
  EXPECT_THROW(makePerezSky(in), InputError);
}

}  // namespace
}  // namespace fly::sunsky
