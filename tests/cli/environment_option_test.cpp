// --environment's parts (cli/environment_option.h, cli/studio_environment.h): the studio's documented
// luminances, an environment put in place of the sky with its hemispheres' illuminance, and bad options.
#include "cli/environment_option.h"

#include <gtest/gtest.h>

#include <cmath>

#include "base/error.h"
#include "base/math.h"
#include "cli/studio_environment.h"

namespace fly::cli {
namespace {

// The pixel of `sky` holding direction (azimuth φ = atan2(z, x), elevation), in degrees.
float at(const rdb::RasterSky& sky, double azimuthDeg, double elevationDeg) {
  const double theta = (90.0 - elevationDeg) / 180.0, phi = azimuthDeg / 360.0;
  const uint32_t x = uint32_t(phi * sky.width) % sky.width, y = std::min(sky.height - 1, uint32_t(theta * sky.height));
  return sky.radianceCdM2[size_t(y) * sky.width + x].g;
}

TEST(StudioEnvironment, DomeFloorAndSoftboxes) {
  const rdb::RasterSky s = studioEnvironment();
  ASSERT_EQ(s.width, 512u);
  ASSERT_EQ(s.height, 256u);
  EXPECT_FALSE(s.hasSun);
  EXPECT_FLOAT_EQ(at(s, 45.0, 30.0), 4000.0f);   // the key's centre
  EXPECT_FLOAT_EQ(at(s, 300.0, 15.0), 1200.0f);  // the fill's
  EXPECT_FLOAT_EQ(at(s, 180.0, 75.0), 2500.0f);  // the top strip's
  EXPECT_FLOAT_EQ(at(s, 90.0, 10.0), 30.0f);     // the dome between them
  EXPECT_FLOAT_EQ(at(s, 0.0, -45.0), 10.0f);     // the floor
  EXPECT_FLOAT_EQ(at(s, 45.0, 55.0), 30.0f);     // above the key (30° ± 20°)
  EXPECT_THROW(studioEnvironment(2, 2), std::invalid_argument);
}

// A uniform environment of L gives each hemisphere E = π L on a horizontal surface facing it.
TEST(EnvironmentOption, ReplacesTheSkyAndSun) {
  rdb::RasterRdb r;
  r.variants.sun = true;
  rdb::RasterSky e;
  e.width = 64;
  e.height = 32;
  e.radianceCdM2.assign(64 * 32, Rgb(2000.0f, 1000.0f, 500.0f));
  applyEnvironment(r, e);
  ASSERT_TRUE(r.sky);
  EXPECT_TRUE(r.variants.sky);
  EXPECT_FALSE(r.variants.sun);
  EXPECT_FALSE(r.sky->hasSun);
  for (const Rgb& lux : {r.daylightAmbient.upLux, r.daylightAmbient.downLux}) {
    EXPECT_NEAR(lux.r / (kPi * 2000.0), 1.0, 2e-3);
    EXPECT_NEAR(lux.b / (kPi * 500.0), 1.0, 2e-3);
  }
}

TEST(EnvironmentOption, BadOptions) {
  EXPECT_FALSE(loadEnvironment({}));
  EXPECT_THROW(loadEnvironment({.source = "studio", .scale = 0.0}), UsageError);
  EXPECT_THROW(loadEnvironment({.source = "studio", .scale = NAN}), UsageError);
  EXPECT_THROW(loadEnvironment({.source = "", .scale = 2.0}), UsageError);
  EXPECT_THROW(loadEnvironment({.source = "studio", .scale = 2.0}), UsageError);
  EXPECT_THROW(loadEnvironment({.source = "/no/such/panorama.exr"}), InputError);
}

}  // namespace
}  // namespace fly::cli
