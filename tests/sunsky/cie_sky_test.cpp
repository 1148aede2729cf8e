#include "sunsky/cie_sky.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "base/error.h"
#include "sky_reference.h"

namespace fly::sunsky {
namespace {

// A sky element at zenith angle Z and azimuth A (degrees, clockwise from north).
dvec3 element(double zenithDeg, double azimuthDeg) {
  return sunDirectionEnu(zenithDeg, azimuthDeg);
}

TEST(CieSky, EveryTypeIntegratesToTheDiffuseIlluminanceItWasNormalisedTo) {
  for (int type = 1; type <= 15; ++type) {
    for (double sunZenith : {0.0, 35.0, 70.0, 90.0}) {
      const CieSky sky = makeCieSky(type, sunZenith, 135.0, CieNormalisation::diffuseHorizontalLux(20000.0));
      const double lux = testing::referenceHorizontalIlluminanceLux(sky);
      EXPECT_NEAR(lux / 20000.0, 1.0, 0.005) << "type " << type << ", sun zenith " << sunZenith;
    }
  }
}

TEST(CieSky, OvercastZenithIsThreeTimesTheHorizon) {
  // Type 1: L(Z)/Lz = φ(Z)/φ(0) with no azimuthal variation; φ(90°) = 1 and φ(0) = 1 + 4·e^{−0.7} = 2.98634,
  // the standard's approximation of the 3:1 of the CIE overcast sky (Moon & Spencer 1942).
  for (double sunZenith : {10.0, 50.0, 89.0}) {
    const CieSky sky = makeCieSky(1, sunZenith, 200.0, CieNormalisation::zenithLuminanceCdM2(3000.0));
    for (double azimuth : {0.0, 90.0, 200.0}) {
      const double ratio = zenithLuminanceCdM2(sky) / luminance(sky.radianceCdM2(element(90.0, azimuth)));
      EXPECT_NEAR(ratio / 3.0, 1.0, 0.01);
      EXPECT_NEAR(ratio, 2.98634, 1e-4);
    }
  }
}

TEST(CieSky, OvercastDiffuseToZenithRatioMatchesTheClassicalOvercastSky) {
  // The CIE overcast sky L = Lz (1 + 2 cos Z)/3 gives Dv = 7π/9 Lz = 2.4435 Lz; type 1 is its exponential
  // approximation: ∫ φ(Z)/φ(0) cos Z dω = 2.4495 (by numerical integration of the 1-D formula).
  const CieSky sky = makeCieSky(1, 30.0, 0.0, CieNormalisation::zenithLuminanceCdM2(1000.0));
  EXPECT_NEAR(horizontalIlluminanceLux(sky) / 1000.0, 2.4495, 1e-3);
  EXPECT_NEAR(horizontalIlluminanceLux(sky) / 1000.0 / (7.0 * kPi / 9.0), 1.0, 0.005);
}

TEST(CieSky, Type12AgreesWithHandComputation) {
  // Sun at Zs = 30°, azimuth 180°; element at Z = 60°, azimuth 90° (Δα = 90°).
  //   cos χ = cos 30° cos 60° + sin 30° sin 60° cos 90° = 0.4330127 → χ = 64.3411° = 1.1229639 rad
  //   φ(60°) = 1 − e^{−0.32/0.5} = 0.4727076      φ(0) = 1 − e^{−0.32} = 0.2738510
  //   f(χ)  = 1 + 10 (e^{−3·1.1229639} − e^{−3π/2}) + 0.45·0.4330127² = 1.3388198
  //   f(Zs) = 1 + 10 (e^{−3·0.5235988} − e^{−3π/2}) + 0.45·cos² 30° = 3.3264629
  //   L/Lz  = 1.3388198 · 0.4727076 / (3.3264629 · 0.2738510) = 0.6947327
  const CieSky sky = makeCieSky(12, 30.0, 180.0, CieNormalisation::zenithLuminanceCdM2(5000.0));
  EXPECT_NEAR(sky.relativeLuminance(element(60.0, 90.0)), 0.6947327, 1e-6);
  EXPECT_NEAR(luminance(sky.radianceCdM2(element(60.0, 90.0))), 5000.0 * 0.6947327, 5e-3);
  // Towards the sun (χ = 0, Z = 30°): f(0) = 1 + 10 (1 − e^{−3π/2}) + 0.45 = 11.3601671,
  // φ(30°) = 1 − e^{−0.32/cos 30°} = 0.3089231 → L/Lz = 11.3601671 · 0.3089231 / (3.3264629 · 0.2738510)
  // = 3.8524601.
  EXPECT_NEAR(sky.relativeLuminance(element(30.0, 180.0)), 3.8524601, 1e-6);
  EXPECT_NEAR(zenithLuminanceCdM2(sky), 5000.0, 1e-3);
}

TEST(CieSky, Type15AgreesWithHandComputation) {
  // Sun at Zs = 45°, azimuth 90°; element at Z = 80°, azimuth 270° (opposite the sun, Δα = 180°).
  //   cos χ = cos 45° cos 80° − sin 45° sin 80° = −0.5735764 → χ = 125° = 2.1816616 rad
  //   φ(80°) = 1 − e^{−0.15/cos 80°} = 0.5784494   φ(0) = 1 − e^{−0.15} = 0.1392920
  //   f(χ)  = 1 + 24 (e^{−2.8·2.1816616} − e^{−1.4π}) + 0.15·0.5735764² = 0.8075353
  //   f(Zs) = 1 + 24 (e^{−2.8·π/4} − e^{−1.4π}) + 0.15·0.5 = 3.4414524
  //   L/Lz  = 0.8075353 · 0.5784494 / (3.4414524 · 0.1392920) = 0.9744486
  const CieSky sky = makeCieSky(15, 45.0, 90.0, CieNormalisation::zenithLuminanceCdM2(1.0));
  EXPECT_NEAR(sky.relativeLuminance(element(80.0, 270.0)), 0.9744486, 1e-6);
}

TEST(CieSky, Type3AndUniformType5AgreeWithHandComputation) {
  // Type 3 (a = 1.1, b = −0.8, no indicatrix): L/Lz = φ(70°)/φ(0) = (1 + 1.1 e^{−0.8/cos 70°}) / (1 + 1.1
  // e^{−0.8})
  //   = 1.1060618 / 1.4942619 = 0.7402061, at any azimuth.
  const CieSky overcast = makeCieSky(3, 40.0, 0.0, CieNormalisation::zenithLuminanceCdM2(1.0));
  EXPECT_NEAR(overcast.relativeLuminance(element(70.0, 10.0)), 0.7402061, 1e-6);
  EXPECT_NEAR(overcast.relativeLuminance(element(70.0, 250.0)), 0.7402061, 1e-6);
  // Type 5: a = 0 and c = e = 0, so L = Lz everywhere and Dv = π Lz.
  const CieSky uniform = makeCieSky(5, 40.0, 0.0, CieNormalisation::diffuseHorizontalLux(kPi * 1000.0));
  EXPECT_NEAR(luminance(uniform.radianceCdM2(element(63.0, 17.0))), 1000.0f, 1e-3f);
  EXPECT_NEAR(zenithLuminanceCdM2(uniform), 1000.0, 1e-3);
}

TEST(CieSky, IsNeutralAndBlackBelowTheHorizon) {
  const CieSky sky = makeCieSky(12, 40.0, 180.0, CieNormalisation::diffuseHorizontalLux(15000.0));
  const Rgb l = sky.radianceCdM2(element(50.0, 100.0));
  EXPECT_EQ(l.r, l.g);
  EXPECT_EQ(l.g, l.b);
  EXPECT_EQ(sky.radianceCdM2(dvec3(0.0, 0.6, -0.8)), Rgb(0.0f));
  EXPECT_EQ(
      makeCieSky(12, 40.0, 180.0, CieNormalisation::diffuseHorizontalLux(0.0)).radianceCdM2(dvec3(0, 0, 1)),
      Rgb(0.0f));
}

TEST(CieSky, SunAtTheZenithAtTheHorizonAndBelow) {
  for (int type = 1; type <= 15; ++type) {
    for (double sunZenith : {0.0, 90.0, 120.0, 180.0}) {
      const CieSky sky = makeCieSky(type, sunZenith, 0.0, CieNormalisation::diffuseHorizontalLux(10000.0));
      for (double z = 0.0; z <= 90.0; z += 15.0) {
        for (double a = 0.0; a < 360.0; a += 45.0) {
          const float l = luminance(sky.radianceCdM2(element(z, a)));
          EXPECT_TRUE(std::isfinite(l) && l > 0.0f) << type << " " << sunZenith << " " << z << " " << a;
        }
      }
    }
  }
}

TEST(CieSky, RejectsInvalidInput) {
  const auto dv = CieNormalisation::diffuseHorizontalLux(10000.0);
  EXPECT_THROW(makeCieSky(0, 30.0, 0.0, dv), InputError);
  EXPECT_THROW(makeCieSky(16, 30.0, 0.0, dv), InputError);
  EXPECT_THROW(makeCieSky(12, 181.0, 0.0, dv), InputError);
  EXPECT_THROW(makeCieSky(12, 30.0, 0.0, CieNormalisation::zenithLuminanceCdM2(-1.0)), InputError);
  EXPECT_THROW(makeCieSky(12, 30.0, 0.0, CieNormalisation::diffuseHorizontalLux(std::nan(""))), InputError);
  try {
    makeCieSky(12, 30.0, 0.0, CieNormalisation::zenithLuminanceCdM2(-1.0));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.message(), "CIE sky zenith luminance -1 cd/m² is less than 0 cd/m²");
  }
  try {
    cieSkyParameters(16);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.message(), "CIE sky type 16 does not exist");
  }
}

}  // namespace
}  // namespace fly::sunsky
