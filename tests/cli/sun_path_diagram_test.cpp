#include "cli/sun_path_diagram.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "base/image_io.h"
#include "sunsky/civil_time.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;

class SunPathTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("fly_sun_path_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

SunPathRequest request(double latitudeDeg, double longitudeDeg, const char* localTime, const char* zone,
                       int sizePx = 600) {
  SunPathRequest r;
  r.spa.latitudeDeg = latitudeDeg;
  r.spa.longitudeDeg = longitudeDeg;
  r.spa.utc = sunsky::parseTime(localTime, zone);
  r.timeZone = zone;
  r.sizePx = sizePx;
  return r;
}

bool hasMarkerColour(const ImageU8& image, int x, int y) {
  const uint8_t* px = &image.pixels[3 * (static_cast<size_t>(y) * image.width + x)];
  return px[0] == kSunPathMarkerRgb[0] && px[1] == kSunPathMarkerRgb[1] && px[2] == kSunPathMarkerRgb[2];
}

size_t markerPixels(const ImageU8& image) {
  size_t n = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) n += hasMarkerColour(image, x, y) ? 1 : 0;
  }
  return n;
}

// Equidistant polar projection at 1200 px: the horizon circle's radius is 0.39·1200 = 468 px around
// (600, 0.505·1200 = 606); elevation 45° lies half-way out.
TEST(SunPathLayoutTest, SunPathProjectionZenithCentreHorizonRadiusNorthUpEastRight) {
  const SunPathLayout l = sunPathLayout(1200);
  EXPECT_DOUBLE_EQ(l.radiusPx, 468.0);
  const auto expectNear = [](glm::dvec2 got, glm::dvec2 want) {
    EXPECT_NEAR(got.x, want.x, 1e-9);
    EXPECT_NEAR(got.y, want.y, 1e-9);
  };
  expectNear(l.centrePx, {600.0, 606.0});
  expectNear(l.pixel(123.0, 90.0), {600.0, 606.0});          // zenith, any azimuth
  expectNear(l.pixel(0.0, 0.0), {600.0, 606.0 - 468.0});     // north: up
  expectNear(l.pixel(90.0, 0.0), {600.0 + 468.0, 606.0});    // east: right (seen from above)
  expectNear(l.pixel(180.0, 45.0), {600.0, 606.0 + 234.0});  // south, half-way
  expectNear(l.pixel(270.0, 60.0), {600.0 - 156.0, 606.0});  // west: left, one third out
  expectNear(l.pixel(45.0, 0.0), {600.0 + 468.0 / std::sqrt(2.0), 606.0 - 468.0 / std::sqrt(2.0)});
}

TEST_F(SunPathTest, SunPathHelsinkiMidsummerNoonIsMarkedWhereTheSunIs) {
  const SunPathRequest r = request(60.17, 24.94, "2026-06-21T12:00", "Europe/Helsinki");
  const fs::path png = dir_ / "sunpath.png";
  drawSunPath(r, png);
  const ImageU8 image = readPng(png);
  EXPECT_EQ(image.width, 600);
  EXPECT_EQ(image.height, 600);
  EXPECT_EQ(image.channels, 3);

  const sunsky::SunPosition sun = sunsky::sunPosition(r.spa);
  EXPECT_GT(sun.apparentElevationDeg(), 50.0);
  const glm::dvec2 at = sunPathLayout(r.sizePx).pixel(sun.azimuthDeg, sun.apparentElevationDeg());
  EXPECT_TRUE(hasMarkerColour(image, static_cast<int>(at.x), static_cast<int>(at.y)));
  // The marker is a dot of about 10/1200 of the image in radius, and nothing else has its colour.
  EXPECT_GT(markerPixels(image), 30u);
  EXPECT_LT(markerPixels(image), 100u);
}

TEST_F(SunPathTest, SunPathSouthernHemisphereAndEquatorAreMarked) {
  for (const SunPathRequest& r : {request(-33.87, 151.21, "2026-12-21T15:30", "Australia/Sydney"),
                                  request(0.0, -78.5, "2026-03-20T09:00", "-05:00")}) {
    const fs::path png = dir_ / "sunpath.png";
    drawSunPath(r, png);
    const ImageU8 image = readPng(png);
    const sunsky::SunPosition sun = sunsky::sunPosition(r.spa);
    const glm::dvec2 at = sunPathLayout(r.sizePx).pixel(sun.azimuthDeg, sun.apparentElevationDeg());
    EXPECT_TRUE(hasMarkerColour(image, static_cast<int>(at.x), static_cast<int>(at.y))) << r.timeZone;
  }
}

// Svalbard at the winter solstice: polar night, so the instant is not marked (the caption says so).
TEST_F(SunPathTest, SunPathPolarNightDrawsWithoutMarker) {
  const SunPathRequest r = request(78.22, 15.65, "2026-12-21T12:00", "Arctic/Longyearbyen");
  ASSERT_LT(sunsky::sunPosition(r.spa).apparentElevationDeg(), 0.0);
  const fs::path png = dir_ / "sunpath.png";
  drawSunPath(r, png);
  const ImageU8 image = readPng(png);
  EXPECT_EQ(image.width, 600);
  EXPECT_EQ(markerPixels(image), 0u);
}

TEST_F(SunPathTest, SunPathPolarDayMarksMidnightSun) {
  const SunPathRequest r = request(78.22, 15.65, "2026-06-21T00:30", "Arctic/Longyearbyen");
  const sunsky::SunPosition sun = sunsky::sunPosition(r.spa);
  ASSERT_GT(sun.apparentElevationDeg(), 0.0);
  const fs::path png = dir_ / "sunpath.png";
  drawSunPath(r, png);
  const ImageU8 image = readPng(png);
  const glm::dvec2 at = sunPathLayout(r.sizePx).pixel(sun.azimuthDeg, sun.apparentElevationDeg());
  EXPECT_LT(at.y, sunPathLayout(r.sizePx).centrePx.y);  // the midnight sun is in the north: upper half
  EXPECT_TRUE(hasMarkerColour(image, static_cast<int>(at.x), static_cast<int>(at.y)));
}

TEST_F(SunPathTest, SunPathPolesDrawWithoutError) {
  for (const double latitude : {90.0, -90.0}) {
    for (const char* time : {"2026-06-21T12:00", "2026-12-21T12:00"}) {
      const SunPathRequest r = request(latitude, 0.0, time, "UTC", 400);
      EXPECT_NO_THROW(drawSunPath(r, dir_ / "pole.png")) << latitude << " " << time;
      EXPECT_EQ(readPng(dir_ / "pole.png").width, 400);
    }
  }
}

TEST_F(SunPathTest, SunPathSizeOutOfRangeIsRejectedAndNothingIsWritten) {
  SunPathRequest r = request(60.17, 24.94, "2026-06-21T12:00", "Europe/Helsinki");
  r.sizePx = 100;
  EXPECT_THROW(drawSunPath(r, dir_ / "small.png"), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir_ / "small.png"));
}

}  // namespace
}  // namespace fly::cli
