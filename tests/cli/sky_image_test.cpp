#include "cli/sky_image.h"

#include <gtest/gtest.h>

#include "sunsky/clear_sky.h"
#include "sunsky/hosek_wilkie.h"
#include "sunsky/sun_disc.h"

namespace fly::cli {
namespace {

class UniformSky final : public sunsky::Sky {
 public:
  explicit UniformSky(double l) : l_(float(l)) {}
  Rgb radianceCdM2(const dvec3& d) const override { return d.z >= 0.0 ? Rgb(l_) : Rgb(0.0f); }
  dvec3 sunDirEnu() const override { return {0.0, 0.0, 1.0}; }

 private:
  float l_;
};

void expectDir(const std::optional<dvec3>& got, const dvec3& want) {
  ASSERT_TRUE(got.has_value());
  EXPECT_NEAR(glm::distance(*got, want), 0.0, 1e-9);
}

TEST(SkyImage, FisheyeLooksUpWithNorthUpAndEastLeft) {
  expectDir(fisheyeDirection(256, 256, 512), {0, 0, 1});  // centre: zenith
  expectDir(fisheyeDirection(256, 0, 512), {0, 1, 0});    // top: north horizon
  expectDir(fisheyeDirection(0, 256, 512), {1, 0, 0});    // left: east horizon
  expectDir(fisheyeDirection(512, 256, 512), {-1, 0, 0});  // right: west
  // Equidistant: halfway to the rim is 45° from the zenith.
  expectDir(fisheyeDirection(256, 384, 512), {0, -std::sqrt(0.5), std::sqrt(0.5)});
  EXPECT_FALSE(fisheyeDirection(0, 0, 512).has_value());  // corner: outside the horizon circle
}

TEST(SkyImage, UniformSkyIntegratesToPiTimesLuminance) {
  // E = π·L for a uniform sky over an unobstructed horizontal surface.
  const ImageRgbF img = renderSkyFisheye(UniformSky(1000.0), std::nullopt, 512);
  EXPECT_NEAR(fisheyeHorizontalIlluminanceLux(img), kPi * 1000.0, kPi * 1000.0 * 0.005);
}

TEST(SkyImage, ImageOfClearSkyAndSunReproducesGlobalHorizontalIlluminance) {
  const double zenithDeg = 40.0;
  const sunsky::ClearSky sky = sunsky::makeClearSky(3.0, zenithDeg, 150.0);
  const sunsky::SunDisc sun = sunsky::clearSkySunDisc({.zenithDeg = zenithDeg, .azimuthDeg = 150.0});
  const double direct = luminance(sun.normalIlluminanceLux) * std::cos(degToRad(zenithDeg));
  const double global = sunsky::horizontalIlluminanceLux(sky) + direct;
  const ImageRgbF img = renderSkyFisheye(sky, sun, 512);
  EXPECT_NEAR(fisheyeHorizontalIlluminanceLux(img), global, global * 0.01);
  // The sun's share alone: the same image without the disc lacks exactly the direct part.
  const ImageRgbF skyOnly = renderSkyFisheye(sky, std::nullopt, 512);
  EXPECT_NEAR(fisheyeHorizontalIlluminanceLux(img) - fisheyeHorizontalIlluminanceLux(skyOnly), direct, direct * 0.01);
}

}  // namespace
}  // namespace fly::cli

#include "cli/daylight.h"

namespace fly::cli {
namespace {

TEST(Daylight, ClearSummerNoonAtMidLatitudeIsEightyToHundredTwentyKilolux) {
  // What `fly sun` reports: 45° N on the June solstice at solar noon, turbidity 3.
  SiteTime st;
  st.spa.latitudeDeg = 45.0;
  st.spa.utc = sunsky::parseTime("2026-06-21T12:00:00Z", "");
  st.timeZone = "Z";
  st.utcOffsetHours = 0.0;
  const sunsky::SunPosition sun = sunsky::sunPosition(st.spa);
  const ClearDaylight d = clearDaylight(st, sun, 3.0);
  const double global = d.directHorizontalLux + d.diffuseHorizontalLux;
  EXPECT_GT(global, 80000.0);
  EXPECT_LT(global, 120000.0);
  // Sky and sun are Hosek and Wilkie's at the site's day.
  const int day = sunsky::dayOfYear(st.spa.utc);
  EXPECT_NEAR(d.diffuseHorizontalLux,
              sunsky::horizontalIlluminanceLux(sunsky::makeHosekWilkieSky(
                  3.0, sunsky::kDefaultGroundAlbedo, sun.apparentZenithDeg, sun.azimuthDeg, day)),
              d.diffuseHorizontalLux * 1e-9);
  sunsky::SunDiscInput in;
  in.zenithDeg = sun.apparentZenithDeg;
  in.turbidity = 3.0;
  in.dayOfYear = day;
  EXPECT_NEAR(d.directNormalLux, luminance(sunsky::hosekWilkieSunDisc(in).normalIlluminanceLux), 1e-6 * global);
  EXPECT_NEAR(d.directHorizontalLux, d.directNormalLux * std::cos(degToRad(sun.apparentZenithDeg)), 1e-6 * global);
}

}  // namespace
}  // namespace fly::cli
