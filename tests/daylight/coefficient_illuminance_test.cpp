// Hourly illuminance from daylight coefficients (daylight/coefficient_illuminance.h): an unobstructed
// horizontal sensor, whose coefficients are exactly the sky patches' projected solid angles, receives each
// hour the weather file's diffuse horizontal illuminance as the Perez sky gives it plus the sun's beam on the
// horizontal; replicates give the hour's standard error from their spread; bad input is refused.
#include "daylight/coefficient_illuminance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <vector>

#include "base/error.h"
#include "sunsky/epw.h"

namespace fly::daylight {
namespace {

sunsky::SkyMatrix helsinkiMatrix(int multiplier) {
  const sunsky::EpwFile file =
      sunsky::loadEpw(std::filesystem::path(FLY_TEST_DATA_DIR) / "epw" / "helsinki-jun21-22.epw");
  sunsky::SkyMatrixOptions options;
  options.multiplier = multiplier;
  return sunsky::makeSkyMatrix(file, options);
}

// One upward-facing sensor under open sky: E = ∫ L cos θ dω, so its coefficient of each sky patch is the
// patch's projected solid angle (lux per cd/m²), and the ground below it gives nothing.
DaylightCoefficients openSensor(const sunsky::SkyPatches& patches, int replicates = 1,
                                std::vector<float> scales = {1.0f}) {
  DaylightCoefficients c;
  c.patchCount = patches.count();
  c.sensorCount = 1;
  c.replicates = replicates;
  for (int r = 0; r < replicates; ++r) {
    for (int p = 0; p < patches.count(); ++p)
      c.luxPerCdM2.push_back(Rgb(p == 0 ? 0.0f : float(patches[p].projectedSolidAngleSr) * scales[size_t(r)]));
  }
  return c;
}

TEST(CoefficientIlluminance, AnOpenHorizontalSensorGetsTheWeatherFilesGlobalHorizontalIlluminance) {
  const sunsky::SkyMatrix sky = helsinkiMatrix(4);
  const std::size_t hours = sky.hourCount();
  ASSERT_EQ(hours, 48u);
  SunDirectIlluminance sun;
  for (const sunsky::SkyMatrixHour& h : sky.hours)
    sun.lux.push_back(h.sunNormalIlluminanceLux * std::max(0.0, h.sunDirEnu.z));
  const std::vector<IlluminanceSeries> e = coefficientIlluminance(openSensor(sky.patches), sky, &sun);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_TRUE(e[0].standardErrorLux.empty());  // exact coefficients, exact sun
  int daylit = 0;
  double worst = 0.0;
  for (std::size_t h = 0; h < hours; ++h) {
    const double expected = sky.hours[h].diffuseHorizontalLux + sun.lux[h];
    if (expected > 0.0) worst = std::max(worst, std::abs(e[0].illuminanceLux[h] / expected - 1.0));
    // The patch sky's own discretisation error at MF 4 (docs/annual-daylight.md: below 1 %).
    EXPECT_NEAR(e[0].illuminanceLux[h], expected, 0.01 * expected + 1e-9) << "hour " << h;
    daylit += expected > 0.0;
  }
  EXPECT_GT(daylit, 30);  // midsummer in Helsinki: about 19 hours of light a day
  std::printf("open sensor, MF 4: %d daylit hours, worst deviation from the global horizontal %.3f %%\n", daylit,
              100.0 * worst);
}

TEST(CoefficientIlluminance, ReplicatesGiveTheHoursStandardError) {
  const sunsky::SkyMatrix sky = helsinkiMatrix(1);
  constexpr float kDelta = 0.1f;
  const std::vector<IlluminanceSeries> exact = coefficientIlluminance(openSensor(sky.patches), sky);
  const std::vector<IlluminanceSeries> spread =
      coefficientIlluminance(openSensor(sky.patches, 2, {1.0f + kDelta, 1.0f - kDelta}), sky);
  ASSERT_EQ(spread[0].standardErrorLux.size(), sky.hourCount());
  for (std::size_t h = 0; h < sky.hourCount(); ++h) {
    const double e = exact[0].illuminanceLux[h];
    EXPECT_NEAR(spread[0].illuminanceLux[h], e, 1e-5 * e + 1e-9);
    // Two replicates E(1 ± δ): sample variance 2 δ² E², of their mean δ² E².
    EXPECT_NEAR(spread[0].standardErrorLux[h], kDelta * e, 1e-5 * e + 1e-9);
  }
}

TEST(CoefficientIlluminance, BadInputIsRefused) {
  const sunsky::SkyMatrix sky = helsinkiMatrix(1);
  DaylightCoefficients other = openSensor(helsinkiMatrix(2).patches);
  EXPECT_THROW(coefficientIlluminance(other, sky), InputError);  // 578 patches against 146
  DaylightCoefficients c = openSensor(sky.patches);
  c.luxPerCdM2.pop_back();
  EXPECT_THROW(coefficientIlluminance(c, sky), InputError);
  c = openSensor(sky.patches);
  c.luxPerCdM2[3].g = -1.0f;
  EXPECT_THROW(coefficientIlluminance(c, sky), InputError);
  c = openSensor(sky.patches);
  c.luxPerCdM2[3].b = std::nanf("");
  EXPECT_THROW(coefficientIlluminance(c, sky), InputError);
  SunDirectIlluminance sun;
  sun.lux.assign(sky.hourCount() - 1, 0.0);
  EXPECT_THROW(coefficientIlluminance(openSensor(sky.patches), sky, &sun), InputError);
  sun.lux.assign(sky.hourCount(), 0.0);
  sun.lux[5] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(coefficientIlluminance(openSensor(sky.patches), sky, &sun), InputError);
}

}  // namespace
}  // namespace fly::daylight
