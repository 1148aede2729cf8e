#include "sunsky/sky_patches.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "base/error.h"

namespace fly::sunsky {
namespace {

constexpr int kMultipliers[] = {1, 2, 4};

// Tregenza: 145 sky patches; Reinhart MF 2: 577; MF 4: 2305 (MF²·144 + 1), plus the ground.
TEST(SkyPatches, CountsPerMultiplier) {
  const int expected[] = {145, 577, 2305};
  for (int k = 0; k < 3; ++k) {
    const SkyPatches s = makeSkyPatches(kMultipliers[k]);
    EXPECT_EQ(s.skyCount(), expected[k]);
    EXPECT_EQ(s.count(), expected[k] + 1);
    EXPECT_EQ(s.bandCount(), 7 * kMultipliers[k] + 1);
  }
  EXPECT_EQ(makeSkyPatches(3).skyCount(), 1297);
}

TEST(SkyPatches, TregenzaBandsAsReinhartCal) {
  const SkyPatches s = makeSkyPatches(1);
  EXPECT_DOUBLE_EQ(s.bandWidthDeg(), 12.0);  // 90 / 7.5
  const int perBand[] = {30, 30, 24, 24, 18, 12, 6, 1};
  int first = 1;
  for (int b = 0; b < 8; ++b) {
    EXPECT_EQ(s.bandFirstPatch(b), first) << b;
    EXPECT_EQ(s.bandPatchCount(b), perBand[b]) << b;
    first += perBand[b];
  }
  // Patch 1: the horizon band centred on north at 6° altitude; patch 2 the next one to the east, 12° on.
  EXPECT_NEAR(s[1].centreDirEnu.x, 0.0, 1e-15);
  EXPECT_NEAR(s[1].centreDirEnu.y, std::cos(degToRad(6.0)), 1e-15);
  EXPECT_NEAR(s[1].centreDirEnu.z, std::sin(degToRad(6.0)), 1e-15);
  EXPECT_DOUBLE_EQ(s[1].minAzimuthDeg, -6.0);
  EXPECT_DOUBLE_EQ(s[1].maxAzimuthDeg, 6.0);
  EXPECT_NEAR(s[2].centreDirEnu.x, std::cos(degToRad(6.0)) * std::sin(degToRad(12.0)), 1e-15);
  EXPECT_GT(s[2].centreDirEnu.y, 0.0);
  // Patch 31, the first of band 1, faces north again, at 18°.
  EXPECT_NEAR(s[31].centreDirEnu.x, 0.0, 1e-15);
  EXPECT_NEAR(s[31].centreDirEnu.z, std::sin(degToRad(18.0)), 1e-15);
  // The cap: patch 145, the zenith, radius 6°.
  EXPECT_EQ(s[145].centreDirEnu, dvec3(0.0, 0.0, 1.0));
  EXPECT_DOUBLE_EQ(s[145].minAltitudeDeg, 84.0);
  EXPECT_NEAR(s[145].solidAngleSr, 2.0 * kPi * (1.0 - std::cos(degToRad(6.0))), 1e-15);
  // The ground.
  EXPECT_EQ(s[kGroundPatch].centreDirEnu, dvec3(0.0, 0.0, -1.0));
  EXPECT_DOUBLE_EQ(s[kGroundPatch].solidAngleSr, 2.0 * kPi);
}

TEST(SkyPatches, ReinhartMf2Bands) {
  const SkyPatches s = makeSkyPatches(2);
  EXPECT_DOUBLE_EQ(s.bandWidthDeg(), 90.0 / 14.5);
  const int perBand[] = {60, 60, 60, 60, 48, 48, 48, 48, 36, 36, 24, 24, 12, 12, 1};
  for (int b = 0; b < 15; ++b) EXPECT_EQ(s.bandPatchCount(b), perBand[b]) << b;
}

// Solid angles sum to 2π (the ground another 2π); the cosine-weighted ones to π, both to rounding.
TEST(SkyPatches, SolidAnglesSumToTheHemisphere) {
  for (int mf : kMultipliers) {
    const SkyPatches s = makeSkyPatches(mf);
    double omega = 0.0;
    double projected = 0.0;
    double centreCosine = 0.0;
    for (int i = 1; i < s.count(); ++i) {
      EXPECT_GT(s[i].solidAngleSr, 0.0);
      omega += s[i].solidAngleSr;
      projected += s[i].projectedSolidAngleSr;
      centreCosine += s[i].solidAngleSr * s[i].centreDirEnu.z;
    }
    EXPECT_NEAR(omega, 2.0 * kPi, 1e-12) << mf;
    EXPECT_NEAR(projected, kPi, 1e-12) << mf;
    // The centre's cosine overestimates each band's mean cosine by exactly 1 / cos(α/2) (the cap differs):
    // Σ Ω cos θ_centre lies within [π, π / cos(α/2)].
    const double alpha = degToRad(s.bandWidthDeg());
    EXPECT_GT(centreCosine, kPi);
    EXPECT_LT(centreCosine, kPi / std::cos(0.5 * alpha));
    for (int i = 1; i < s.count() - 1; ++i) {
      EXPECT_NEAR(s[i].solidAngleSr * s[i].centreDirEnu.z * std::cos(0.5 * alpha), s[i].projectedSolidAngleSr,
                  1e-15);
    }
  }
}

// Every patch of a band has the same solid angle: the band's area over its patch count.
TEST(SkyPatches, EqualPatchesWithinABand) {
  const SkyPatches s = makeSkyPatches(4);
  const double alpha = degToRad(s.bandWidthDeg());
  for (int b = 0; b + 1 < s.bandCount(); ++b) {
    const double band = 2.0 * kPi * (std::sin((b + 1) * alpha) - std::sin(b * alpha));
    for (int c = 0; c < s.bandPatchCount(b); ++c) {
      EXPECT_NEAR(s[s.bandFirstPatch(b) + c].solidAngleSr, band / s.bandPatchCount(b), 1e-15);
    }
  }
}

TEST(SkyPatches, LookupOfEachCentreReturnsItsOwnIndex) {
  for (int mf : kMultipliers) {
    const SkyPatches s = makeSkyPatches(mf);
    for (int i = 0; i < s.count(); ++i) EXPECT_EQ(s.patchIndex(s[i].centreDirEnu), i) << mf << " " << i;
  }
}

TEST(SkyPatches, LookupLandsInThePatchWhoseBoundsContainTheDirection) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int mf : kMultipliers) {
    const SkyPatches s = makeSkyPatches(mf);
    for (int k = 0; k < 20000; ++k) {
      dvec3 d(u(rng), u(rng), u(rng));
      if (glm::length(d) < 1e-3) continue;
      d *= 3.7;  // the lookup takes any length
      const int i = s.patchIndex(d);
      const dvec3 n = glm::normalize(d);
      const double altitude = radToDeg(std::asin(n.z));
      const SkyPatch& p = s[i];
      if (n.z < 0.0) {
        EXPECT_EQ(i, kGroundPatch);
        continue;
      }
      EXPECT_GE(altitude, p.minAltitudeDeg - 1e-12);
      EXPECT_LE(altitude, p.maxAltitudeDeg + 1e-12);
      if (p.maxAltitudeDeg < 90.0) {
        double azimuth = radToDeg(std::atan2(n.x, n.y));
        while (azimuth < p.minAzimuthDeg) azimuth += 360.0;
        while (azimuth >= p.maxAzimuthDeg) azimuth -= 360.0;
        EXPECT_GE(azimuth, p.minAzimuthDeg) << i;
        EXPECT_LT(azimuth, p.maxAzimuthDeg) << i;
      }
    }
  }
}

TEST(SkyPatches, LookupAtEdges) {
  const SkyPatches s = makeSkyPatches(1);
  // The horizon belongs to the sky (reinhart.cal: altitude 0 is band 0), just below it to the ground.
  EXPECT_EQ(s.patchIndex(dvec3(0.0, 1.0, 0.0)), 1);
  EXPECT_EQ(s.patchIndex(dvec3(0.0, 1.0, -1e-9)), kGroundPatch);
  // North-by-west: the last half-width before north belongs to patch 1.
  EXPECT_EQ(s.patchIndex(dvec3(-0.01, 1.0, 0.1)), 1);
  // Due east at 6°: azimuth 90° is the edge between patches 8 (84°) and 9 (96°)...
  EXPECT_EQ(s.patchIndex(dvec3(1.0, 1e-9, 0.1)), 8);
  EXPECT_EQ(s.patchIndex(dvec3(1.0, -1e-9, 0.1)), 9);
  // South at 30° (band 2, 24 patches of 15°): patch 61 + 12.
  EXPECT_EQ(s.patchIndex(dvec3(0.0, -std::cos(degToRad(30.0)), std::sin(degToRad(30.0)))), 61 + 12);
  EXPECT_EQ(s.patchIndex(dvec3(0.0, 0.0, 1.0)), 145);
}

TEST(SkyPatches, UnknownSubdivisionIsAnInputError) {
  for (int mf : {0, -1, kMaxSkyMultiplier + 1}) {
    try {
      makeSkyPatches(mf);
      ADD_FAILURE() << mf;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("unknown sky subdivision"), std::string::npos) << e.what();
      EXPECT_FALSE(e.hint().empty());
    }
  }
}

}  // namespace
}  // namespace fly::sunsky
