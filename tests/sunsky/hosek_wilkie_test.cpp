#include "sunsky/hosek_wilkie.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "base/cie1931.h"
#include "base/error.h"
#include "sky_reference.h"
#include "sunsky/clear_sky.h"

namespace fly::sunsky {
namespace {

// Day 93 (3 April): the Earth–Sun distance is the mean one to 0.02 %, so the tables' values apply unscaled.
constexpr int kMeanDistanceDay = 93;

// Values of the authors' reference implementation of the model (release 1.4a, the CIE XYZ sky dataset and
// the spectral solar radiance function), sun at azimuth 0 (north), computed independently of fly: luminance
// 683·Y at the zenith, at 30° elevation 90° in azimuth from the sun (east) and at 5° elevation opposite the
// sun (south), cd/m²; diffuse horizontal illuminance by an 800 × 1 600 midpoint rule, lux; the disc's direct
// normal illuminance by integrating the limb-darkened radiance over the disc (200 rings) and 320–720 nm
// (1 nm) against a multi-lobe Gaussian fit of V(λ) (Wyman, Sloan & Shirley, JCGT 2(2) 2013), lux; the
// chromaticity (x, y) at the two directions above the horizon.
struct Reference {
  double turbidity, elevationDeg, albedo;
  double zenithCdM2, east30CdM2, south5CdM2, diffuseLux, directNormalLux;
  double east30X, east30Y, south5X, south5Y;  // CIE 1931 chromaticity
};
constexpr Reference kReference[] = {
    {2, 2, 0.2, 577.704, 1406.62, 4174.81, 4201.29, 9917.72, 0.29449, 0.32931, 0.38364, 0.40053},
    {3, 10, 0.2, 1172.86, 2780.89, 9436.55, 9297.54, 41079.8, 0.26315, 0.28962, 0.31411, 0.34621},
    {3, 45, 0.2, 2810.04, 4719.65, 13085.9, 16779.7, 76550.2, 0.24275, 0.25633, 0.27105, 0.29501},
    {5.2, 20, 0.2, 2074.47, 3961.67, 9975.7, 17106.8, 51071, 0.26642, 0.28522, 0.29509, 0.31963},
    {9.8, 45, 0.2, 9475.15, 8521.86, 8557.58, 54066.6, 44264.6, 0.29260, 0.31023, 0.30412, 0.31768},
    {10, 60, 0.2, 21793.5, 10516.3, 10751.2, 68572.9, 48959.8, 0.28966, 0.30822, 0.31075, 0.33056},
    {3, 45, 0, 2471.32, 4038.62, 11107.2, 14717.3, 76550.2, 0.24147, 0.25432, 0.26973, 0.29337},
    {3, 45, 1, 4030.45, 7594.18, 21705.6, 24286.7, 76550.2, 0.24709, 0.26255, 0.27541, 0.29965},
    {1.7, 30, 0.5, 2293.58, 4654.15, 15888.2, 14634.9, 72787.4, 0.24431, 0.26080, 0.27761, 0.30691},
    {7.5, 80, 0.2, 31208.8, 7368.59, 11229.3, 36327.4, 70556.2, 0.26500, 0.28041, 0.29419, 0.30997},
};

dvec3 atElevation(double azimuthDeg, double elevationDeg) { return sunDirectionEnu(90.0 - elevationDeg, azimuthDeg); }

HosekWilkieSky skyAt(double turbidity, double elevationDeg, double albedo = kDefaultGroundAlbedo) {
  return makeHosekWilkieSky(turbidity, albedo, 90.0 - elevationDeg, 0.0, kMeanDistanceDay);
}

double directNormalLux(double turbidity, double elevationDeg) {
  SunDiscInput in;
  in.zenithDeg = 90.0 - elevationDeg;
  in.turbidity = turbidity;
  in.dayOfYear = kMeanDistanceDay;
  return luminance(hosekWilkieSunDisc(in).normalIlluminanceLux);
}

// CIE 1931 chromaticity of a linear Rec.709 colour (the IEC 61966-2-1 matrix).
dvec2 chromaticityOf(const Rgb& rec709) {
  const double x = 0.4124564 * rec709.r + 0.3575761 * rec709.g + 0.1804375 * rec709.b;
  const double y = 0.2126729 * rec709.r + 0.7151522 * rec709.g + 0.0721750 * rec709.b;
  const double z = 0.0193339 * rec709.r + 0.1191920 * rec709.g + 0.9503041 * rec709.b;
  return dvec2(x, y) / (x + y + z);
}

// McCamy's correlated colour temperature of a chromaticity near the Planckian locus, K (Color Research and
// Application 17(2) 1992).
double correlatedColourTemperatureK(const Rgb& rec709) {
  const dvec2 c = chromaticityOf(rec709);
  const double n = (c.x - 0.3320) / (0.1858 - c.y);
  return 449.0 * n * n * n + 3525.0 * n * n + 6823.3 * n + 5520.33;
}

TEST(HosekWilkieSky, AgreesWithTheAuthorsReferenceImplementation) {
  const double eccentricity = eccentricityCorrection(kMeanDistanceDay);
  for (const Reference& r : kReference) {
    const HosekWilkieSky sky = skyAt(r.turbidity, r.elevationDeg, r.albedo);
    const std::string at = "T " + std::to_string(r.turbidity) + ", elevation " + std::to_string(r.elevationDeg) +
                           ", albedo " + std::to_string(r.albedo);
    EXPECT_NEAR(sky.modelLuminanceCdM2(dvec3(0, 0, 1)) / r.zenithCdM2, 1.0, 1e-5) << at;
    EXPECT_NEAR(sky.modelLuminanceCdM2(atElevation(90.0, 30.0)) / r.east30CdM2, 1.0, 1e-5) << at;
    EXPECT_NEAR(sky.modelLuminanceCdM2(atElevation(180.0, 5.0)) / r.south5CdM2, 1.0, 1e-5) << at;
    // The shown sky adds the Earth–Sun distance and the night sky (1.7e-4 cd/m²).
    EXPECT_NEAR(luminance(sky.radianceCdM2(dvec3(0, 0, 1))) / (eccentricity * r.zenithCdM2), 1.0, 1e-5) << at;
    EXPECT_NEAR(horizontalIlluminanceLux(sky) / (eccentricity * r.diffuseLux), 1.0, 0.002) << at;
    const dvec2 east30 = chromaticityOf(sky.radianceCdM2(atElevation(90.0, 30.0)));
    const dvec2 south5 = chromaticityOf(sky.radianceCdM2(atElevation(180.0, 5.0)));
    EXPECT_NEAR(east30.x, r.east30X, 2e-4) << at;
    EXPECT_NEAR(east30.y, r.east30Y, 2e-4) << at;
    EXPECT_NEAR(south5.x, r.south5X, 2e-4) << at;
    EXPECT_NEAR(south5.y, r.south5Y, 2e-4) << at;
    EXPECT_NEAR(directNormalLux(r.turbidity, r.elevationDeg) / (eccentricity * r.directNormalLux), 1.0, 0.01)
        << at;
  }
}

TEST(HosekWilkieSky, HazeMovesLightFromTheSunToTheSky) {
  // At 45° elevation: the sky's diffuse horizontal illuminance rises with the turbidity, the sun's direct
  // normal illuminance falls.
  double previousSky = 0.0, previousSun = std::numeric_limits<double>::infinity();
  for (double t = 2.0; t <= 10.0; t += 0.5) {
    const double sky = horizontalIlluminanceLux(skyAt(t, 45.0));
    const double sun = directNormalLux(t, 45.0);
    EXPECT_GT(sky, previousSky) << "T " << t;
    EXPECT_LT(sun, previousSun) << "T " << t;
    previousSky = sky;
    previousSun = sun;
  }
  EXPECT_GT(horizontalIlluminanceLux(skyAt(9.8, 45.0)) / horizontalIlluminanceLux(skyAt(2.0, 45.0)), 3.5);
}

TEST(HosekWilkieSky, TheHorizonIsBluishWhiteInAClearSky) {
  // T = 3, 2° above the horizon and 90° in azimuth from the sun: a white bluer than D65 (6 504 K) and
  // not a saturated blue; Preetham's sky shows mauve there.
  for (double sunElevation : {20.0, 45.0}) {
    const HosekWilkieSky sky = skyAt(3.0, sunElevation);
    const Rgb horizon = sky.radianceCdM2(atElevation(90.0, 2.0));
    const double cct = correlatedColourTemperatureK(horizon);
    EXPECT_GT(cct, 6504.0) << "sun at " << sunElevation << "°";
    EXPECT_LT(cct, 10000.0) << "sun at " << sunElevation << "°";
    EXPECT_GT(horizon.b, horizon.r);
  }
}

TEST(HosekWilkieSky, SunReddensTowardsTheHorizon) {
  SunDiscInput in;
  in.turbidity = 3.0;
  in.dayOfYear = kMeanDistanceDay;
  in.zenithDeg = 30.0;
  const Rgb high = hosekWilkieSunDisc(in).normalIlluminanceLux;
  in.zenithDeg = 85.0;
  const Rgb low = hosekWilkieSunDisc(in).normalIlluminanceLux;
  EXPECT_GT(low.r / low.b, 1.5f * (high.r / high.b));
  EXPECT_NEAR(double(luminance(hosekWilkieSunDisc(in).radianceCdM2)) * sunDiscSolidAngleSr() / luminance(low), 1.0,
              1e-5);
}

TEST(HosekWilkieSky, IntegratesToAGivenDiffuseIlluminance) {
  for (double turbidity : {kMinTurbidity, 3.0, kMaxTurbidity}) {
    for (double sunZenith : {0.0, 45.0, 89.0, 90.0, 96.0}) {
      const HosekWilkieSky sky = makeHosekWilkieSky(turbidity, 0.2, sunZenith, 30.0, 172, 12000.0);
      EXPECT_NEAR(testing::referenceHorizontalIlluminanceLux(sky) / 12000.0, 1.0, 0.005)
          << "T " << turbidity << ", sun zenith " << sunZenith;
    }
  }
}

TEST(HosekWilkieSky, TwilightDarkensMonotonicallyToTheNightSky) {
  for (double turbidity : {kMinTurbidity, 3.0, kMaxTurbidity}) {
    double previous = std::numeric_limits<double>::infinity();
    for (double sunZenith = 85.0; sunZenith <= 180.0; sunZenith += 1.0) {
      const HosekWilkieSky sky = makeHosekWilkieSky(turbidity, 0.2, sunZenith, 120.0, 355);
      const double lux = horizontalIlluminanceLux(sky);
      EXPECT_LE(lux, previous * (1.0 + 1e-9)) << "T " << turbidity << ", sun zenith " << sunZenith;
      EXPECT_GE(lux, kPi * kNightSkyLuminanceCdM2 * 0.999);
      previous = lux;
    }
    // 3 lx at the end of civil twilight (6° below the horizon), plus the night sky.
    EXPECT_NEAR(horizontalIlluminanceLux(makeHosekWilkieSky(turbidity, 0.2, 96.0, 0.0, 93)), 3.0, 0.01);
  }
  SunDiscInput in;
  in.zenithDeg = 90.5;
  EXPECT_EQ(luminance(hosekWilkieSunDisc(in).normalIlluminanceLux), 0.0f);
}

TEST(HosekWilkieSky, IsFiniteAndNonNegativeEverywhereInRange) {
  // The fit turns negative near the horizon at high turbidity and low sun; those channels are 0.
  for (double turbidity : {kMinTurbidity, 2.0, 5.5, 9.8, kMaxTurbidity}) {
    for (double albedo : {0.0, 0.2, 1.0}) {
      for (double sunZenith : {0.0, 30.0, 60.0, 80.0, 88.0, 89.99, 90.0, 91.0, 120.0, 180.0}) {
        const HosekWilkieSky sky = makeHosekWilkieSky(turbidity, albedo, sunZenith, 250.0, 1);
        for (double elevation : {0.0, 0.01, 1.0, 5.0, 30.0, 60.0, 89.9, 90.0}) {
          for (double azimuth = 0.0; azimuth < 360.0; azimuth += 15.0) {
            const Rgb c = sky.radianceCdM2(atElevation(azimuth, elevation));
            ASSERT_TRUE(isFinite(c) && c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f)
                << "T " << turbidity << ", albedo " << albedo << ", sun zenith " << sunZenith << ", at "
                << azimuth << "/" << elevation;
          }
        }
        EXPECT_EQ(luminance(sky.radianceCdM2(dvec3(0.0, 0.6, -0.8))), 0.0f);  // below the horizon
        SunDiscInput in;
        in.turbidity = turbidity;
        in.zenithDeg = sunZenith;
        in.dayOfYear = 1;
        const SunDisc disc = hosekWilkieSunDisc(in);
        EXPECT_TRUE(isFinite(disc.normalIlluminanceLux) && isFinite(disc.radianceCdM2));
        EXPECT_GE(luminance(disc.normalIlluminanceLux), 0.0f);
      }
    }
  }
}

TEST(HosekWilkieSky, RejectsInputsOutOfRange) {
  EXPECT_THROW(makeHosekWilkieSky(11.0, 0.2, 30.0, 0.0, 1), InputError);
  EXPECT_THROW(makeHosekWilkieSky(1.0, 0.2, 30.0, 0.0, 1), InputError);
  EXPECT_THROW(makeHosekWilkieSky(3.0, 1.5, 30.0, 0.0, 1), InputError);
  EXPECT_THROW(makeHosekWilkieSky(3.0, std::nan(""), 30.0, 0.0, 1), InputError);
  EXPECT_THROW(makeHosekWilkieSky(3.0, 0.2, 190.0, 0.0, 1), InputError);
  EXPECT_THROW(makeHosekWilkieSky(3.0, 0.2, 30.0, 0.0, 0), InputError);
  EXPECT_THROW(makeHosekWilkieSky(3.0, 0.2, 30.0, 0.0, 1, -5.0), InputError);
  SunDiscInput in;
  in.turbidity = 12.0;
  EXPECT_THROW(hosekWilkieSunDisc(in), InputError);
}

}  // namespace
}  // namespace fly::sunsky
