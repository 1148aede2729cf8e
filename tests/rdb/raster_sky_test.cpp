#include "rdb/raster_sky.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "rdb/site_lowering.h"
#include "sunsky/civil_time.h"
#include "sunsky/sun_disc.h"
#include "sunsky/sun_position.h"

namespace fly::rdb {
namespace {

using sdb::Scene;

// A site at 20° N on the prime meridian (UTC), or `latitudeDeg`, with true north along −Z.
Scene siteScene(const std::string& localTime, sdb::SkyModel model, bool sun, double latitudeDeg = 20.0,
                int cieType = 12) {
  Scene s;
  sdb::Site site;
  site.latitudeDeg = latitudeDeg;
  site.longitudeDeg = 0.0;
  site.timeZone = "Z";
  s.setSite(site);
  s.setTime({localTime});
  sdb::SkySettings sky;
  sky.model = model;
  sky.cieType = cieType;
  sky.sun = sun;
  s.setSky(sky);
  return s;
}

double elevationDeg(const std::string& localTime, double latitudeDeg = 20.0) {
  sunsky::SpaInput spa;
  spa.utc = sunsky::parseTime(localTime, "Z");
  spa.latitudeDeg = latitudeDeg;
  return sunsky::sunPosition(spa).apparentElevationDeg();
}

// The first whole minute of the morning of 20 March 2026 at 20° N with the sun at least `targetDeg` up.
std::string morningTimeAtElevation(double targetDeg) {
  for (int minute = 4 * 60; minute < 12 * 60; ++minute) {
    char t[32];
    std::snprintf(t, sizeof t, "2026-03-20T%02d:%02d", minute / 60, minute % 60);
    if (elevationDeg(t) >= targetDeg) return t;
  }
  throw std::logic_error("no such time");
}

// ∫ luminance · cos θ dω over the image's upper half, with each pixel's exact ∫ cos θ dω = (μ0² − μ1²)/2 ·
// 2π/W.
double imageHorizontalIlluminanceLux(const RasterSky& r) {
  double e = 0.0;
  for (uint32_t j = 0; j < r.height / 2; ++j) {
    const double mu0 = std::cos(kPi * j / r.height), mu1 = std::cos(kPi * (j + 1) / r.height);
    const double cosWeightedSr = (mu0 * mu0 - mu1 * mu1) / 2.0 * 2.0 * kPi / r.width;
    for (uint32_t i = 0; i < r.width; ++i)
      e += luminance(r.radianceCdM2[size_t(j) * r.width + i]) * cosWeightedSr;
  }
  return e;
}

// The pixel holding world direction d.
const Rgb& pixel(const RasterSky& r, const dvec3& d) {
  double phi = std::atan2(d.z, d.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  const auto i = std::min(r.width - 1, uint32_t(phi / (2.0 * kPi) * r.width));
  const auto j = std::min(r.height - 1, uint32_t(std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi * r.height));
  return r.radianceCdM2[size_t(j) * r.width + i];
}

// The world direction at the sun's azimuth and `elevationDeg` above the horizon.
dvec3 towardsSunAt(const RasterSky& r, double elevationDeg) {
  const dvec3 h = glm::normalize(dvec3(r.sunDirWorld.x, 0.0, r.sunDirWorld.z));
  const double e = degToRad(elevationDeg);
  return {h.x * std::cos(e), std::sin(e), h.z * std::cos(e)};
}

void expectFiniteAndNonNegative(const RasterSky& r) {
  ASSERT_EQ(r.radianceCdM2.size(), size_t(r.width) * r.height);
  for (const Rgb& c : r.radianceCdM2) {
    ASSERT_TRUE(isFinite(c));
    ASSERT_GE(std::min({c.r, c.g, c.b}), 0.0f);
  }
  EXPECT_TRUE(isFinite(r.sunDirWorld));
  EXPECT_NEAR(glm::length(r.sunDirWorld), 1.0f, 1e-6f);
  EXPECT_TRUE(isFinite(r.sunRadianceCdM2));
}

TEST(RasterSky, UpperHemisphereIntegratesToTheSkysHorizontalIlluminance) {
  struct Case {
    double sunElevationDeg;
    sdb::SkyModel model;
    int cieType;
  };
  for (const Case& c : {Case{2.0, sdb::SkyModel::kClear, 12}, Case{60.0, sdb::SkyModel::kClear, 12},
                        Case{30.0, sdb::SkyModel::kCie, 12}, Case{30.0, sdb::SkyModel::kCie, 1}}) {
    const Scene s = siteScene(morningTimeAtElevation(c.sunElevationDeg), c.model, true, 20.0, c.cieType);
    const std::optional<RasterSky> r = buildRasterSky(s);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->width, 256u);
    EXPECT_EQ(r->height, 128u);
    expectFiniteAndNonNegative(*r);
    const double expected = sunsky::horizontalIlluminanceLux(*lowerDaylight(s)->sky);
    EXPECT_NEAR(imageHorizontalIlluminanceLux(*r), expected, 0.01 * expected)
        << "sun at " << c.sunElevationDeg << "°, model " << int(c.model) << ", CIE type " << c.cieType;
  }
}

TEST(RasterSky, SunIsLowerDaylightsSun) {
  const Scene s = siteScene(morningTimeAtElevation(35.0), sdb::SkyModel::kClear, true);
  const std::optional<SceneDaylight> d = lowerDaylight(s);
  const std::optional<RasterSky> r = buildRasterSky(s, 64, 32);
  ASSERT_TRUE(r && d && d->sun);
  EXPECT_TRUE(r->hasSun);
  EXPECT_EQ(r->sunDirWorld, vec3(d->sunDirWorld));
  EXPECT_EQ(r->sunRadianceCdM2, d->sun->radianceCdM2);
  EXPECT_NEAR(r->sunHalfAngleRad, degToRad(0.533 / 2.0), 1e-7);
  EXPECT_NEAR(r->sunDirWorld.y, std::sin(degToRad(elevationDeg(morningTimeAtElevation(35.0)))), 1e-6);
  // In the morning the sun is in the east: world +X with true north along −Z.
  EXPECT_GT(r->sunDirWorld.x, 0.5f);
}

TEST(RasterSky, ImageColumnsFollowWorldAzimuth) {
  // A CIE clear sky (type 12) peaks around the sun: in the row 5° above the sun, the brightest pixel is the
  // one in the sun's direction, so φ = atan2(z, x) and the row order are as documented.
  const std::optional<RasterSky> r =
      buildRasterSky(siteScene(morningTimeAtElevation(30.0), sdb::SkyModel::kCie, false), 128, 64);
  ASSERT_TRUE(r);
  const double sunEl = radToDeg(std::asin(double(r->sunDirWorld.y)));
  const dvec3 above = towardsSunAt(*r, sunEl + 5.0);
  const float atSun = luminance(pixel(*r, above));
  const auto row = uint32_t(std::acos(above.y) / kPi * r->height);
  for (uint32_t i = 0; i < r->width; ++i) {
    EXPECT_LE(luminance(r->radianceCdM2[size_t(row) * r->width + i]), atSun) << "column " << i;
  }
  // The opposite azimuth is much darker.
  const dvec3 opposite(-above.x, above.y, -above.z);
  EXPECT_LT(luminance(pixel(*r, opposite)), 0.5f * atSun);
}

TEST(RasterSky, DawnIsRedderThanNoon) {
  double ratio[2] = {0.0, 0.0};
  const double elevations[2] = {2.0, 60.0};
  for (int k = 0; k < 2; ++k) {
    const std::optional<RasterSky> r =
        buildRasterSky(siteScene(morningTimeAtElevation(elevations[k]), sdb::SkyModel::kClear, true));
    ASSERT_TRUE(r);
    // The horizon 20° of azimuth from the sun, 3° up.
    const dvec3 towards = towardsSunAt(*r, 3.0);
    const double a = degToRad(20.0);
    const dvec3 d(towards.x * std::cos(a) - towards.z * std::sin(a), towards.y,
                  towards.x * std::sin(a) + towards.z * std::cos(a));
    const Rgb c = pixel(*r, d);
    ASSERT_GT(c.b, 0.0f);
    ratio[k] = double(c.r) / double(c.b);
  }
  EXPECT_GT(ratio[0], ratio[1] * 1.2) << "R/B at 2°: " << ratio[0] << ", at 60°: " << ratio[1];
}

TEST(RasterSky, GroundIsLambertianUnderSkyAndSun) {
  const Scene s = siteScene(morningTimeAtElevation(40.0), sdb::SkyModel::kCie, true);
  const std::optional<SceneDaylight> d = lowerDaylight(s);
  const std::optional<RasterSky> r = buildRasterSky(s, 32, 16);
  ASSERT_TRUE(r && d && d->sun);
  const double eLux = sunsky::horizontalIlluminanceLux(*d->sky) +
                      double(luminance(d->sun->normalIlluminanceLux)) * d->sunDirWorld.y;
  const double expected = double(kRasterGroundAlbedo) * eLux / kPi;
  for (uint32_t j = r->height / 2; j < r->height; ++j) {
    for (uint32_t i = 0; i < r->width; ++i) {
      EXPECT_NEAR(luminance(r->radianceCdM2[size_t(j) * r->width + i]), expected, 1e-3 * expected);
    }
  }
  // The CIE sky is neutral, and so the ground is as coloured as the sun alone makes it: R ≥ B.
  EXPECT_GE(r->radianceCdM2.back().r, r->radianceCdM2.back().b);
}

// The scene's ground albedo: the clear sky brightens over a brighter ground (Hosek and Wilkie's model: 16.8 klx
// over albedo 0.2 at T 3 and 45°, 14.7 over 0, 24.3 over 1) and the ground drawn below the horizon reflects
// that albedo of sky and sun.
TEST(RasterSky, TheGroundAlbedoLightsTheClearSkyAndTheGround) {
  double previousSkyLux = 0.0;
  for (const double albedo : {0.0, 0.2, 0.5, 1.0}) {
    Scene s = siteScene(morningTimeAtElevation(40.0), sdb::SkyModel::kClear, true);
    sdb::SkySettings sky = s.sky();
    sky.groundAlbedo = albedo;
    s.setSky(sky);
    const std::optional<SceneDaylight> d = lowerDaylight(s);
    const std::optional<RasterSky> r = buildRasterSky(s, 32, 16);
    ASSERT_TRUE(r && d && d->sun && d->sky);
    const double skyLux = sunsky::horizontalIlluminanceLux(*d->sky);
    EXPECT_GT(skyLux, previousSkyLux) << albedo;
    previousSkyLux = skyLux;
    const double expected = albedo * (skyLux + double(luminance(d->sun->normalIlluminanceLux)) * d->sunDirWorld.y) / kPi;
    EXPECT_NEAR(luminance(r->radianceCdM2.back()), expected, 1e-3 * expected + 1e-9) << albedo;
    EXPECT_FLOAT_EQ(r->groundAlbedo, float(albedo));
  }
}

TEST(RasterSky, SunWithoutSkyGivesABlackSkyAndASunlitGround) {
  const Scene s = siteScene(morningTimeAtElevation(30.0), sdb::SkyModel::kNone, true);
  const std::optional<RasterSky> r = buildRasterSky(s, 16, 8);
  ASSERT_TRUE(r);
  ASSERT_TRUE(r->hasSun);
  for (uint32_t j = 0; j < r->height / 2; ++j) EXPECT_EQ(r->radianceCdM2[size_t(j) * r->width], Rgb(0.0f));
  const std::optional<SceneDaylight> d = lowerDaylight(s);
  const Rgb expected = d->sun->normalIlluminanceLux * float(d->sunDirWorld.y * kRasterGroundAlbedo / kPi);
  const Rgb ground = r->radianceCdM2.back();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(ground[c], expected[c], 1e-4f * expected[c]);
}

TEST(RasterSky, NoSkyAndNoSunGivesNothing) {
  EXPECT_FALSE(buildRasterSky(siteScene("2026-03-20T12:00", sdb::SkyModel::kNone, false)));
  EXPECT_FALSE(buildRasterSky(Scene{}));  // no site at all
}

TEST(RasterSky, SunBelowTheHorizonGivesNoSunAndAFiniteSky) {
  const std::string midnight = "2026-03-20T00:00";
  ASSERT_LT(elevationDeg(midnight), -50.0);
  for (sdb::SkyModel model : {sdb::SkyModel::kClear, sdb::SkyModel::kCie, sdb::SkyModel::kNone}) {
    const std::optional<RasterSky> r = buildRasterSky(siteScene(midnight, model, true), 64, 32);
    ASSERT_TRUE(r);
    EXPECT_FALSE(r->hasSun);
    EXPECT_EQ(r->sunRadianceCdM2, Rgb(0.0f));
    EXPECT_LT(r->sunDirWorld.y, -0.7f);
    expectFiniteAndNonNegative(*r);
  }
}

TEST(RasterSky, PolarNightHasNoNaN) {
  // Longyearbyen (78.2° N) at noon on 21 December: the sun stays ~11.4° below the horizon all day.
  for (sdb::SkyModel model : {sdb::SkyModel::kClear, sdb::SkyModel::kCie}) {
    const Scene s = siteScene("2026-12-21T11:00", model, true, 78.2);
    ASSERT_LT(elevationDeg("2026-12-21T11:00", 78.2), -10.0);
    const std::optional<RasterSky> r = buildRasterSky(s, 64, 32);
    ASSERT_TRUE(r);
    EXPECT_FALSE(r->hasSun);
    expectFiniteAndNonNegative(*r);
    EXPECT_GT(luminance(r->radianceCdM2.front()), 0.0f);  // twilight: the zenith is not black
  }
}

TEST(RasterSky, RejectsBadSizes) {
  const Scene s = siteScene("2026-03-20T12:00", sdb::SkyModel::kClear, true);
  EXPECT_THROW(buildRasterSky(s, 0, 128), std::invalid_argument);
  EXPECT_THROW(buildRasterSky(s, 256, 0), std::invalid_argument);
  EXPECT_THROW(buildRasterSky(s, 100000, 128), std::invalid_argument);
  // An odd height puts the horizon inside a row: that row mixes sky and ground half and half.
  const std::optional<RasterSky> r = buildRasterSky(s, 8, 3);
  ASSERT_TRUE(r);
  expectFiniteAndNonNegative(*r);
}

}  // namespace
}  // namespace fly::rdb
