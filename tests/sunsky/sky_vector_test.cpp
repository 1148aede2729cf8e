#include "sunsky/sky_vector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "base/error.h"
#include "sunsky/cie_sky.h"
#include "sunsky/hosek_wilkie.h"
#include "sunsky/perez_sky.h"

namespace fly::sunsky {
namespace {

// A sky of one radiance everywhere above the horizon.
class UniformSky final : public Sky {
 public:
  explicit UniformSky(const Rgb& radiance) : radiance_(radiance) {}
  Rgb radianceCdM2(const dvec3& dirEnu) const override { return dirEnu.z < 0.0 ? Rgb(0.0f) : radiance_; }
  dvec3 sunDirEnu() const override { return glm::normalize(dvec3(0.3, -0.5, 0.6)); }

 private:
  Rgb radiance_;
};

TEST(SkyVector, UniformSkyGivesUniformPatches) {
  const Rgb radiance(1000.0f, 2000.0f, 3000.0f);
  const UniformSky sky(radiance);
  for (int mf : {1, 2, 4}) {
    const SkyPatches patches = makeSkyPatches(mf);
    for (int order : {1, 6}) {
      SkyVectorOptions options;
      options.nodesPerAxis = order;
      options.groundAlbedo = 0.0;
      const SkyVector v = makeSkyVector(sky, SunDisc{}, patches, options);
      ASSERT_EQ(v.radianceCdM2.size(), std::size_t(patches.count()));
      EXPECT_EQ(v.radianceCdM2[kGroundPatch], dvec3(0.0));
      for (int i = 1; i < patches.count(); ++i) {
        EXPECT_NEAR(v.radianceCdM2[i].r, 1000.0, 1e-9) << i;
        EXPECT_NEAR(v.radianceCdM2[i].g, 2000.0, 1e-9) << i;
        EXPECT_NEAR(v.radianceCdM2[i].b, 3000.0, 1e-9) << i;
      }
      // E = π·L for a uniform sky.
      EXPECT_NEAR(horizontalIlluminanceLux(v, patches),
                  kPi * (0.2126 * 1000.0 + 0.7152 * 2000.0 + 0.0722 * 3000.0), 1e-8);
    }
  }
}

// Σ L_i·(projected solid angle)_i against the sky's own hemisphere quadrature (sky.h). Patch means are
// converged (the finer-quadrature test below), so what is left is the discretisation: within a patch L and
// cos θ are correlated (a sky brightening towards the horizon or a low sun), which the product of their means
// misses. The error falls as α², 4× per doubling of MF: Tregenza's 145 patches are within 2.5 % (2.0 % at
// worst: Hosek–Wilkie T 2 and CIE 13 with a low sun), MF 2 within 0.5 %, MF 4 within 0.15 %
// (docs/annual-daylight.md).
void expectHorizontalIlluminanceMatches(const Sky& sky, const std::string& what) {
  const double reference = horizontalIlluminanceLux(sky);
  ASSERT_GT(reference, 0.0) << what;
  const double tolerance[3] = {0.025, 0.005, 0.0015};
  double error[3] = {};
  for (int k = 0; k < 3; ++k) {
    const int mf = 1 << k;
    const SkyPatches patches = makeSkyPatches(mf);
    const SkyVector v = makeSkyVector(sky, SunDisc{}, patches);
    error[k] = horizontalIlluminanceLux(v, patches) / reference - 1.0;
    EXPECT_LT(std::abs(error[k]), tolerance[k]) << what << ", MF " << mf;
  }
  // Second order in α: each doubling of MF divides the error by about 4 (3.6 to 7.2 here, where it is large
  // enough to measure; errors of opposite sign in different parts of the sky make it uneven).
  if (std::abs(error[0]) > 0.002) {
    EXPECT_GT(error[0] / error[1], 3.0) << what;
    EXPECT_GT(error[1] / error[2], 3.0) << what;
  }
}

constexpr double kSunZenithsDeg[] = {5.0, 30.0, 60.0, 85.0};

TEST(SkyVector, HorizontalIlluminanceOfCieSkies) {
  for (double zenith : kSunZenithsDeg) {
    for (int type : {1, 12, 13}) {  // overcast, clear, polluted clear
      const CieSky sky = makeCieSky(type, zenith, 140.0, CieNormalisation::diffuseHorizontalLux(15000.0));
      expectHorizontalIlluminanceMatches(
          sky, "CIE type " + std::to_string(type) + ", Z " + std::to_string(zenith));
    }
  }
}

TEST(SkyVector, HorizontalIlluminanceOfPerezSkies) {
  // Overcast, intermediate and clear (ε ≈ 1, 1.7, 6+ at Z = 40°), W/m².
  const double pairs[3][2] = {{0.0, 150.0}, {150.0, 150.0}, {850.0, 80.0}};
  for (double zenith : kSunZenithsDeg) {
    for (const auto& pair : pairs) {
      PerezSkyInput in;
      in.sunZenithDeg = zenith;
      in.sunAzimuthDeg = 200.0;
      in.directNormal = pair[0];
      in.diffuseHorizontal = pair[1];
      const PerezSky sky = makePerezSky(in);
      expectHorizontalIlluminanceMatches(
          sky, "Perez bin " + std::to_string(sky.condition().bin) + ", Z " + std::to_string(zenith));
    }
  }
}

TEST(SkyVector, HorizontalIlluminanceOfHosekWilkieSkies) {
  for (double zenith : kSunZenithsDeg) {
    for (double turbidity : {2.0, 6.0}) {
      const HosekWilkieSky sky = makeHosekWilkieSky(turbidity, 0.2, zenith, 75.0, 172);
      expectHorizontalIlluminanceMatches(
          sky, "Hosek-Wilkie T " + std::to_string(turbidity) + ", Z " + std::to_string(zenith));
    }
  }
}

// Per patch, the default order agrees with a much finer one (16 × 16 per panel) to 0.1 % on smooth skies.
TEST(SkyVector, PatchMeansConvergeToTheFinerQuadrature) {
  const SkyPatches patches = makeSkyPatches(1);
  SkyVectorOptions fine;
  fine.nodesPerAxis = 16;
  const CieSky overcast = makeCieSky(1, 40.0, 180.0, CieNormalisation::diffuseHorizontalLux(10000.0));
  const CieSky clear = makeCieSky(12, 40.0, 180.0, CieNormalisation::diffuseHorizontalLux(10000.0));
  for (const CieSky* sky : {&overcast, &clear}) {
    const SkyVector coarse = makeSkyVector(*sky, SunDisc{}, patches);
    const SkyVector reference = makeSkyVector(*sky, SunDisc{}, patches, fine);
    for (int i = 1; i < patches.count(); ++i) {
      EXPECT_NEAR(coarse.luminanceCdM2(i) / reference.luminanceCdM2(i), 1.0, 1e-3) << sky->type() << " " << i;
    }
  }
}

TEST(SkyVector, SunInItsPatchAndOnTheGround) {
  const SkyPatches patches = makeSkyPatches(1);
  const CieSky sky = makeCieSky(12, 50.0, 180.0, CieNormalisation::diffuseHorizontalLux(20000.0));
  // The sun's illuminance is single precision (Rgb): compare to 1e-6.
  SunDiscInput in;
  in.zenithDeg = 50.0;
  in.azimuthDeg = 180.0;
  const SunDisc sun = sunDiscWithIlluminance(in, 60000.0);
  const double sunNormalLux = luminance(sun.normalIlluminanceLux);

  SkyVectorOptions separate;
  separate.groundAlbedo = 0.3;
  const SkyVector a = makeSkyVector(sky, sun, patches, separate);
  SkyVectorOptions folded = separate;
  folded.sun = SunInPatches::kContainingPatch;
  const SkyVector b = makeSkyVector(sky, sun, patches, folded);

  // Altitude 40°, south: band 3 (36°–48°, 24 patches of 15°) from patch 85, column 12.
  EXPECT_EQ(a.sunPatch, 85 + 12);
  EXPECT_EQ(b.sunPatch, a.sunPatch);
  for (int i = 0; i < patches.count(); ++i) {
    if (i == a.sunPatch) {
      // The patch gains the sun's normal illuminance over its solid angle.
      EXPECT_NEAR((b.luminanceCdM2(i) - a.luminanceCdM2(i)) * patches[i].solidAngleSr, sunNormalLux,
                  1e-6 * sunNormalLux);
    } else {
      EXPECT_EQ(a.radianceCdM2[i], b.radianceCdM2[i]) << i;
    }
  }
  // The ground: ρ·(E_sky + E_sun·cos Z)/π, the same for both placements.
  const double global = horizontalIlluminanceLux(a, patches) + sunNormalLux * std::cos(degToRad(50.0));
  EXPECT_NEAR(a.luminanceCdM2(kGroundPatch), 0.3 * global / kPi, 1e-6 * global);
  // Folded into a patch, the sun lights the horizontal by the patch's mean cosine instead of its own: the
  // patch (36°–48°) has mean sin-altitude (sin 36° + sin 48°)/2 = 0.6654 against the sun's sin 40° = 0.6428.
  const double foldedGain = horizontalIlluminanceLux(b, patches) - horizontalIlluminanceLux(a, patches);
  EXPECT_NEAR(foldedGain / sunNormalLux, (std::sin(degToRad(36.0)) + std::sin(degToRad(48.0))) / 2.0, 1e-6);
}

TEST(SkyVector, SunBelowTheHorizonLightsNothing) {
  const SkyPatches patches = makeSkyPatches(1);
  const UniformSky sky(Rgb(10.0f));
  SunDisc sun;
  sun.dirEnu = glm::normalize(dvec3(0.0, -1.0, -0.1));
  sun.normalIlluminanceLux = Rgb(50000.0f);
  SkyVectorOptions options;
  options.sun = SunInPatches::kContainingPatch;
  const SkyVector v = makeSkyVector(sky, sun, patches, options);
  EXPECT_EQ(v.sunPatch, kGroundPatch);
  EXPECT_NEAR(v.luminanceCdM2(kGroundPatch), 0.2 * 10.0, 1e-9);  // ρ·πL/π
}

TEST(SkyVector, BadOptionsAreInputErrors) {
  const SkyPatches patches = makeSkyPatches(1);
  const UniformSky sky(Rgb(1.0f));
  SkyVectorOptions options;
  options.groundAlbedo = 1.5;
  EXPECT_THROW(makeSkyVector(sky, SunDisc{}, patches, options), InputError);
  options.groundAlbedo = std::nan("");
  EXPECT_THROW(makeSkyVector(sky, SunDisc{}, patches, options), InputError);
  options.groundAlbedo = 0.2;
  options.nodesPerAxis = 0;
  EXPECT_THROW(makeSkyVector(sky, SunDisc{}, patches, options), InputError);
}

}  // namespace
}  // namespace fly::sunsky
