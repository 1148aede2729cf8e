#include "daylight/annual_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/math.h"

namespace fly::daylight {
namespace {

// LM-83's default schedule: 8:00–18:00 every day, 3650 hours.
const OccupancySchedule kSchedule = dailyOccupancy();
constexpr double kOccupied = 3650.0;

// A year whose occupied hours take `occupied(i)` for the i-th occupied hour of each day (i = 0..9, 8:00–9:00
// first) and `unoccupied` otherwise.
IlluminanceSeries series(const std::function<double(int)>& occupied, double unoccupied = 0.0) {
  IlluminanceSeries s;
  s.illuminanceLux.resize(kHoursPerYear, unoccupied);
  for (std::size_t k = 0; k < kHoursPerYear; ++k) {
    const int hour = static_cast<int>(k % 24);
    if (hour >= 8 && hour < 18) s.illuminanceLux[k] = occupied(hour - 8);
  }
  return s;
}

IlluminanceSeries constant(double lux, double standardErrorLux = 0.0) {
  IlluminanceSeries s = series([lux](int) { return lux; });
  if (standardErrorLux > 0.0) s.standardErrorLux.assign(kHoursPerYear, standardErrorLux);
  return s;
}

// Φ(1) and Φ(1)·(1 − Φ(1)).
constexpr double kPhi1 = 0.8413447460685429;
constexpr double kBernoulliVarianceAtPhi1 = kPhi1 * (1.0 - kPhi1);

TEST(Occupancy, EightToSixEveryDay) {
  EXPECT_EQ(kSchedule.hourCount(), 8760u);
  EXPECT_EQ(kSchedule.occupiedCount(), 3650u);
  // Hour k covers [k, k + 1) from 1 January 00:00: 7:00–8:00 is out, 8:00–9:00 (EPW record hour 9) in,
  // 17:00–18:00 (record 18) in, 18:00–19:00 out.
  EXPECT_FALSE(kSchedule.occupied[7]);
  EXPECT_TRUE(kSchedule.occupied[8]);
  EXPECT_TRUE(kSchedule.occupied[17]);
  EXPECT_FALSE(kSchedule.occupied[18]);
  EXPECT_TRUE(kSchedule.occupied[8759 - 6]);  // 31 December 17:00–18:00
  EXPECT_EQ(dailyOccupancy(8, 18, kHoursPerLeapYear).occupiedCount(), 3660u);
  EXPECT_EQ(dailyOccupancy(0, 24).occupiedCount(), 8760u);
  EXPECT_EQ(dailyOccupancy(9, 17).occupiedCount(), 365u * 8u);
}

TEST(SensorMetrics, AllZero) {
  const SensorMetrics m = sensorMetrics(constant(0.0), kSchedule);
  EXPECT_EQ(m.daylightAutonomy.value, 0.0);
  EXPECT_EQ(m.continuousDaylightAutonomy.value, 0.0);
  EXPECT_EQ(m.udiBelow.value, 1.0);
  EXPECT_EQ(m.udiUseful.value, 0.0);
  EXPECT_EQ(m.udiAbove.value, 0.0);
  EXPECT_EQ(m.daylightAutonomy.standardError, 0.0);
  EXPECT_EQ(m.continuousDaylightAutonomy.standardErrorBound, 0.0);
}

TEST(SensorMetrics, ThresholdExactlyCounts) {
  // 300 lx is daylit (≥), 100 and 3000 lx are useful (the bins are < 100, [100, 3000], > 3000).
  EXPECT_EQ(sensorMetrics(constant(300.0), kSchedule).daylightAutonomy.value, 1.0);
  EXPECT_EQ(sensorMetrics(constant(300.0), kSchedule).continuousDaylightAutonomy.value, 1.0);
  EXPECT_EQ(sensorMetrics(constant(100.0), kSchedule).udiUseful.value, 1.0);
  EXPECT_EQ(sensorMetrics(constant(3000.0), kSchedule).udiUseful.value, 1.0);
  EXPECT_EQ(sensorMetrics(constant(std::nextafter(300.0, 0.0)), kSchedule).daylightAutonomy.value, 0.0);
}

TEST(SensorMetrics, AllOccupiedHoursAboveAndUnoccupiedHoursIgnored) {
  const SensorMetrics m = sensorMetrics(series([](int) { return 5000.0; }, 0.0), kSchedule);
  EXPECT_EQ(m.daylightAutonomy.value, 1.0);
  EXPECT_EQ(m.continuousDaylightAutonomy.value, 1.0);
  EXPECT_EQ(m.udiAbove.value, 1.0);
  EXPECT_EQ(m.udiBelow.value, 0.0);
}

// Each day's ten occupied hours: 50, 100, 200, 300, 3000, 3001, 600, 0, 150, 450 lx; 10 klx while unoccupied.
//   DA300: 300, 3000, 3001, 600, 450 → 5/10
//   cDA:   (50 + 100 + 200 + 0 + 150)/300 + 5 → (5/3 + 5)/10 = 2/3
//   UDI:   < 100: 50, 0 → 0.2; > 3000: 3001 → 0.1; the other 7 → 0.7
TEST(SensorMetrics, HandComputedDay) {
  const double day[10] = {50, 100, 200, 300, 3000, 3001, 600, 0, 150, 450};
  const SensorMetrics m = sensorMetrics(series([&day](int i) { return day[i]; }, 10000.0), kSchedule);
  EXPECT_DOUBLE_EQ(m.daylightAutonomy.value, 0.5);
  EXPECT_NEAR(m.continuousDaylightAutonomy.value, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(m.udiBelow.value, 0.2, 1e-12);
  EXPECT_NEAR(m.udiUseful.value, 0.7, 1e-12);
  EXPECT_NEAR(m.udiAbove.value, 0.1, 1e-12);
  // Other thresholds: DA500 = 3000, 3001, 600 → 0.3; UDI 200–2000: below 50, 100, 0, 150 → 0.4.
  MetricThresholds t;
  t.daylightAutonomyLux = 500.0;
  t.udiLowerLux = 200.0;
  t.udiUpperLux = 2000.0;
  const SensorMetrics m2 = sensorMetrics(series([&day](int i) { return day[i]; }), kSchedule, t);
  EXPECT_NEAR(m2.daylightAutonomy.value, 0.3, 1e-12);
  EXPECT_NEAR(m2.udiBelow.value, 0.4, 1e-12);
  EXPECT_NEAR(m2.udiAbove.value, 0.2, 1e-12);
}

// An hour at E = T + σ lies above T with probability Φ(1): its indicator has variance Φ(1)(1 − Φ(1)).
TEST(SensorMetrics, StandardErrorOfDaylightAutonomy) {
  const SensorMetrics m = sensorMetrics(constant(330.0, 30.0), kSchedule);
  EXPECT_EQ(m.daylightAutonomy.value, 1.0);
  EXPECT_NEAR(m.daylightAutonomy.standardError, std::sqrt(kOccupied * kBernoulliVarianceAtPhi1) / kOccupied,
              1e-12);
  EXPECT_NEAR(m.daylightAutonomy.standardErrorBound, std::sqrt(kBernoulliVarianceAtPhi1), 1e-12);
  // On the threshold: p = ½, variance ¼.
  const SensorMetrics at = sensorMetrics(constant(300.0, 10.0), kSchedule);
  EXPECT_NEAR(at.daylightAutonomy.standardError, 0.5 / std::sqrt(kOccupied), 1e-12);
  EXPECT_NEAR(at.daylightAutonomy.standardErrorBound, 0.5, 1e-12);
  // Far from every threshold, a small error changes nothing.
  const SensorMetrics far = sensorMetrics(constant(1000.0, 1.0), kSchedule);
  EXPECT_EQ(far.daylightAutonomy.standardError, 0.0);
  EXPECT_EQ(far.udiUseful.standardError, 0.0);
}

// UDI: at E = 100 + σ the hour is below 100 with probability 1 − Φ(1) and otherwise useful.
TEST(SensorMetrics, StandardErrorOfUsefulDaylightIlluminance) {
  const SensorMetrics m = sensorMetrics(constant(110.0, 10.0), kSchedule);
  const double se = std::sqrt(kOccupied * kBernoulliVarianceAtPhi1) / kOccupied;
  EXPECT_NEAR(m.udiBelow.standardError, se, 1e-12);
  EXPECT_NEAR(m.udiUseful.standardError, se, 1e-12);
  EXPECT_NEAR(m.udiAbove.standardError, 0.0, 1e-12);
}

// cDA: well below the threshold min(E, T)/T has the standard deviation σ/T; on it, Var(min(X, T)) =
// (½ − 1/(2π))·σ² (X normal with mean T: E[Z⁺] = σ/√(2π), E[Z⁺²] = σ²/2); well above it, none.
TEST(SensorMetrics, StandardErrorOfContinuousDaylightAutonomy) {
  const Estimate below = sensorMetrics(constant(60.0, 6.0), kSchedule).continuousDaylightAutonomy;
  EXPECT_NEAR(below.value, 0.2, 1e-12);
  EXPECT_NEAR(below.standardError, (6.0 / 300.0) / std::sqrt(kOccupied), 1e-12);
  EXPECT_NEAR(below.standardErrorBound, 6.0 / 300.0, 1e-12);
  const Estimate at = sensorMetrics(constant(300.0, 30.0), kSchedule).continuousDaylightAutonomy;
  const double sdAt = std::sqrt(0.5 - 1.0 / (2.0 * fly::kPi)) * 30.0 / 300.0;
  EXPECT_NEAR(at.standardError, sdAt / std::sqrt(kOccupied), 1e-12);
  EXPECT_NEAR(at.standardErrorBound, sdAt, 1e-12);
  EXPECT_NEAR(sensorMetrics(constant(3000.0, 30.0), kSchedule).continuousDaylightAutonomy.standardError, 0.0,
              1e-9);
}

TEST(HoursAbove, StrictlyMoreThanTheThreshold) {
  EXPECT_EQ(hoursAbove(constant(1000.0), kSchedule, 1000.0).value, 0.0);
  EXPECT_EQ(hoursAbove(constant(1000.1), kSchedule, 1000.0).value, kOccupied);
  // 1100 ± 100 lx against 1000 lx: every hour counts, each with variance Φ(1)(1 − Φ(1)).
  const Estimate e = hoursAbove(constant(1100.0, 100.0), kSchedule, 1000.0);
  EXPECT_EQ(e.value, kOccupied);
  EXPECT_NEAR(e.standardError, std::sqrt(kOccupied * kBernoulliVarianceAtPhi1), 1e-9);
  EXPECT_NEAR(e.standardErrorBound, kOccupied * std::sqrt(kBernoulliVarianceAtPhi1), 1e-9);
}

// Daylit (≥ 300 lx) in the first `daylit` of each day's ten occupied hours, 0 lx otherwise: DA = daylit/10.
IlluminanceSeries daylitHours(int daylit) {
  return series([daylit](int i) { return i < daylit ? 400.0 : 0.0; });
}

TEST(SpatialDaylightAutonomy, ShareOfSensorsWithHalfTheHoursDaylit) {
  // DA = 0.5 passes (≥ 50 %), 0.4 does not: 2 of 4 sensors.
  const std::vector<IlluminanceSeries> grid = {daylitHours(5), daylitHours(4), daylitHours(10),
                                               daylitHours(0)};
  const Estimate sda = spatialDaylightAutonomy(grid, kSchedule);
  EXPECT_DOUBLE_EQ(sda.value, 0.5);
  EXPECT_EQ(sda.standardError, 0.0);
  EXPECT_EQ(sda.standardErrorBound, 0.0);
  // One sensor.
  EXPECT_EQ(spatialDaylightAutonomy(std::vector{daylitHours(5)}, kSchedule).value, 1.0);
  EXPECT_EQ(spatialDaylightAutonomy(std::vector{daylitHours(4)}, kSchedule).value, 0.0);
  // sDA500/30 %: DA500 of 400 lx hours is 0.
  SpatialDaylightAutonomyCriteria c;
  c.illuminanceLux = 500.0;
  c.timeShare = 0.3;
  EXPECT_EQ(spatialDaylightAutonomy(grid, kSchedule, c).value, 0.0);
}

// A sensor whose DA sits on the 50 % line passes with probability ½ once its hours are uncertain.
TEST(SpatialDaylightAutonomy, StandardErrorFromSensorsOnTheLine) {
  IlluminanceSeries onTheLine = daylitHours(5);
  // The daylit hours at 330 ± 30 lx (each above 300 with probability Φ(1)), the others far below.
  for (std::size_t k = 0; k < kHoursPerYear; ++k) {
    if (onTheLine.illuminanceLux[k] > 0.0) onTheLine.illuminanceLux[k] = 330.0;
  }
  onTheLine.standardErrorLux.assign(kHoursPerYear, 30.0);
  const std::vector<IlluminanceSeries> grid = {onTheLine, daylitHours(10)};
  const Estimate sda = spatialDaylightAutonomy(grid, kSchedule);
  EXPECT_DOUBLE_EQ(sda.value, 1.0);
  // DA = 0.5 exactly with σ_DA > 0: p = Φ(0) = ½, variance ¼; the certain sensor adds nothing.
  EXPECT_NEAR(sda.standardError, 0.5 / 2.0, 1e-12);
  EXPECT_NEAR(sda.standardErrorBound, 0.5 / 2.0, 1e-12);
}

// Direct sun above 1000 lx in the first n occupied hours of the year, none otherwise.
IlluminanceSeries sunlitHours(int n, double lux = 2000.0) {
  IlluminanceSeries s;
  s.illuminanceLux.assign(kHoursPerYear, 0.0);
  int counted = 0;
  for (std::size_t k = 0; k < kHoursPerYear && counted < n; ++k) {
    if (kSchedule.occupied[k]) {
      s.illuminanceLux[k] = lux;
      ++counted;
    }
  }
  return s;
}

TEST(AnnualSunlightExposure, MoreThan250HoursAboveMoreThan1000Lux) {
  // 251 hours: exposed; 250: not; 300 hours at exactly 1000 lx: not (more than 1000 lx); none: not.
  const std::vector<IlluminanceSeries> grid = {sunlitHours(251), sunlitHours(250), sunlitHours(300, 1000.0),
                                               sunlitHours(0)};
  const Estimate ase = annualSunlightExposure(grid, kSchedule);
  EXPECT_DOUBLE_EQ(ase.value, 0.25);
  EXPECT_EQ(ase.standardError, 0.0);
  EXPECT_EQ(annualSunlightExposure(std::vector{sunlitHours(251)}, kSchedule).value, 1.0);
  EXPECT_EQ(annualSunlightExposure(std::vector{constant(0.0)}, kSchedule).value, 0.0);
}

TEST(AnnualSunlightExposure, StandardErrorOfASensorNearTheLimit) {
  // 260 hours at 1100 ± 100 lx: the count is 260 with σ = √(260·Φ(1)(1 − Φ(1))) = 5.89; exposed with
  // probability Φ((260 − 250.5)/5.89).
  IlluminanceSeries s = sunlitHours(260, 1100.0);
  s.standardErrorLux.assign(kHoursPerYear, 100.0);
  const double sigmaCount = std::sqrt(260.0 * kBernoulliVarianceAtPhi1);
  const double p = 0.5 * std::erfc(-(260.0 - 250.5) / sigmaCount / std::sqrt(2.0));
  const Estimate ase = annualSunlightExposure(std::vector{s}, kSchedule);
  EXPECT_EQ(ase.value, 1.0);
  EXPECT_NEAR(ase.standardError, std::sqrt(p * (1.0 - p)), 1e-12);
  // The bound takes σ_count = 260·√(Φ(1)(1 − Φ(1))).
  const double sigmaBound = 260.0 * std::sqrt(kBernoulliVarianceAtPhi1);
  const double pBound = 0.5 * std::erfc(-(260.0 - 250.5) / sigmaBound / std::sqrt(2.0));
  EXPECT_NEAR(ase.standardErrorBound, std::sqrt(pBound * (1.0 - pBound)), 1e-9);
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    EXPECT_FALSE(e.hint().empty()) << e.what();
    return e.what();
  }
  return "no error";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(AnnualMetrics, BadInputIsAnInputError) {
  IlluminanceSeries shortSeries = constant(100.0);
  shortSeries.illuminanceLux.pop_back();
  EXPECT_TRUE(contains(errorOf([&] { sensorMetrics(shortSeries, kSchedule); }),
                       "illuminance series has 8759 values; the occupancy schedule has 8760 hours"));
  IlluminanceSeries nan = constant(100.0);
  nan.illuminanceLux[9] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(contains(errorOf([&] { sensorMetrics(nan, kSchedule); }), "illuminance of hour 9 is nan lx"));
  IlluminanceSeries negative = constant(100.0);
  negative.illuminanceLux[3] = -1.0;
  EXPECT_TRUE(contains(errorOf([&] { hoursAbove(negative, kSchedule, 1000.0); }), "hour 3 is -1 lx"));
  IlluminanceSeries badErrors = constant(100.0, 5.0);
  badErrors.standardErrorLux.resize(10);
  EXPECT_TRUE(
      contains(errorOf([&] { sensorMetrics(badErrors, kSchedule); }), "standard error series has 10 values"));
  badErrors = constant(100.0, 5.0);
  badErrors.standardErrorLux[0] = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(contains(errorOf([&] { sensorMetrics(badErrors, kSchedule); }), "standard error of hour 0"));
  const std::vector<IlluminanceSeries> grid = {constant(100.0), shortSeries};
  EXPECT_TRUE(
      contains(errorOf([&] { spatialDaylightAutonomy(grid, kSchedule); }), "sensor 1: illuminance series"));
  EXPECT_TRUE(contains(errorOf([&] { annualSunlightExposure({}, kSchedule); }), "the sensor grid is empty"));
  OccupancySchedule nobody;
  nobody.occupied.assign(kHoursPerYear, false);
  EXPECT_TRUE(contains(errorOf([&] { sensorMetrics(constant(0.0), nobody); }), "no occupied hour"));
  MetricThresholds t;
  t.udiLowerLux = 3000.0;
  EXPECT_TRUE(contains(errorOf([&] { sensorMetrics(constant(0.0), kSchedule, t); }), "not increasing"));
  t = {};
  t.daylightAutonomyLux = 0.0;
  EXPECT_TRUE(
      contains(errorOf([&] { sensorMetrics(constant(0.0), kSchedule, t); }), "not a positive illuminance"));
  SpatialDaylightAutonomyCriteria c;
  c.timeShare = 50.0;
  EXPECT_TRUE(contains(errorOf([&] { spatialDaylightAutonomy(grid, kSchedule, c); }), "outside [0, 1]"));
  EXPECT_TRUE(contains(errorOf([] { dailyOccupancy(18, 8); }), "occupied hours 18 to 8"));
  EXPECT_TRUE(contains(errorOf([] { dailyOccupancy(8, 18, 8000); }), "a year of 8000 hours"));
}

}  // namespace
}  // namespace fly::daylight
