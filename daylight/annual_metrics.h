// Climate-based annual daylight metrics from hourly illuminance series, each with a standard error propagated
// from the series' per-hour standard errors (docs/annual-daylight.md).
//
// Per sensor (over the occupied hours of an OccupancySchedule):
//   DA   daylight autonomy: the share of hours with E ≥ 300 lx (Reinhart & Walkenhorst 2001; IES LM-83-12)
//   cDA  continuous daylight autonomy: each hour counts min(1, E / 300) (Rogers 2006)
//   UDI  useful daylight illuminance (Nabil & Mardaljevic, "Useful daylight illuminances: a replacement for
//        daylight factors", Energy and Buildings 38 (2006) 905–913), the shares of hours with E < 100 lx,
//        100 ≤ E ≤ 3000 lx and E > 3000 lx (the bins Honeybee uses)
// Over a grid of sensors (IES LM-83-12, "Approved Method: IES Spatial Daylight Autonomy (sDA) and Annual
// Sunlight Exposure (ASE)"):
//   sDA300/50%     the share of sensors with DA300 ≥ 50 %
//   ASE1000,250h   the share of sensors that receive more than 1000 lx of direct sunlight in more than 250
//                  occupied hours. LM-83 takes the DIRECT SUN ONLY, without interreflections and without
//                  shading devices: the function takes that series, not the total one.
//
// Shares are fractions in [0, 1]. Standard errors: each hour's illuminance is taken as normal about the value
// given with its standard error; an hour then lies on the far side of a threshold T with probability
// p = Φ(−|E − T| / σ), each hour's indicator has variance p(1 − p), and a count of hours has the variance
// Σ p(1 − p) when the hours' errors are independent. The value reported is the metric of the series as given;
// the standard error says how much it would move if the series were recomputed with other random numbers.
// Series from daylight coefficients share their errors between hours (the same coefficients weight every
// hour's sky), so `standardErrorBound`, which holds for any correlation (the standard deviation of a sum is
// at most the sum of the standard deviations), is reported too.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace fly::daylight {

inline constexpr std::size_t kHoursPerYear = 8760;
inline constexpr std::size_t kHoursPerLeapYear = 8784;

// Which hours of the year count: hour k (0-based, k = 24·day + h − 1 for EPW record hour h) covers
// [k, k + 1) local standard time from 1 January 00:00.
struct OccupancySchedule {
  std::vector<bool> occupied;  // kHoursPerYear or kHoursPerLeapYear entries

  std::size_t hourCount() const { return occupied.size(); }
  std::size_t occupiedCount() const;
};

// Every day of the year from `startHour` to `endHour` local standard time (integers, 0 ≤ start < end ≤ 24):
// LM-83-12's default is 8:00 to 18:00, 10 hours a day, 3650 hours a year; the EPW records hour 9 to 18.
// InputError for bounds out of range or a year length other than 8760 or 8784.
OccupancySchedule dailyOccupancy(int startHour = 8, int endHour = 18,
                                 std::size_t hoursInYear = kHoursPerYear);

// One sensor's hourly illuminance, lux, one value per hour of the year (as the schedule), and optionally each
// value's standard error (empty = exact).
struct IlluminanceSeries {
  std::vector<double> illuminanceLux;
  std::vector<double> standardErrorLux;
};

// A metric and its uncertainty (see the header comment).
struct Estimate {
  double value = 0.0;
  double standardError = 0.0;       // the hours' (or sensors') errors independent
  double standardErrorBound = 0.0;  // any correlation between them
};

struct MetricThresholds {
  double daylightAutonomyLux = 300.0;  // DA and cDA, > 0
  double udiLowerLux = 100.0;          // UDI bins: < lower, [lower, upper], > upper; 0 < lower < upper
  double udiUpperLux = 3000.0;
};

struct SensorMetrics {
  Estimate daylightAutonomy;            // share of occupied hours with E ≥ daylightAutonomyLux
  Estimate continuousDaylightAutonomy;  // mean over occupied hours of min(1, E / daylightAutonomyLux)
  Estimate udiBelow;                    // share with E < udiLowerLux
  Estimate udiUseful;                   // share with udiLowerLux ≤ E ≤ udiUpperLux
  Estimate udiAbove;                    // share with E > udiUpperLux
};

// The metrics of one sensor. InputError for a series whose length is not the schedule's, whose standard
// errors are neither empty nor as long, for a value that is negative or not finite, for a schedule with no
// occupied hour, or for thresholds out of range.
SensorMetrics sensorMetrics(const IlluminanceSeries& series, const OccupancySchedule& schedule,
                            const MetricThresholds& thresholds = {});

// The number of occupied hours with E > thresholdLux (strictly: LM-83's "more than"), with its standard error
// as above. InputError as sensorMetrics.
Estimate hoursAbove(const IlluminanceSeries& series, const OccupancySchedule& schedule, double thresholdLux);

struct SpatialDaylightAutonomyCriteria {
  double illuminanceLux = 300.0;  // > 0
  double timeShare = 0.5;         // a sensor passes when its DA ≥ this share, [0, 1]
};

// sDA over `sensors` (their total illuminance, with the operable shading LM-83 prescribes already applied by
// whoever computed them): the share of sensors whose DA ≥ timeShare. A sensor's chance of passing is
// Φ((DA − share)/σ_DA) with σ_DA its DA's standard error (its bound for standardErrorBound); the count of
// passing sensors then has the variance Σ p(1 − p). InputError for an empty grid or as sensorMetrics.
Estimate spatialDaylightAutonomy(std::span<const IlluminanceSeries> sensors,
                                 const OccupancySchedule& schedule,
                                 const SpatialDaylightAutonomyCriteria& criteria = {});

struct AnnualSunlightExposureCriteria {
  double illuminanceLux = 1000.0;  // > 0
  double hours = 250.0;            // a sensor is exposed when it gets more than this many hours, ≥ 0
};

// ASE over `directSunOnly` (per sensor, the illuminance from the sun's disc alone, no interreflections, no
// shading devices): the share of sensors with more than `hours` occupied hours above `illuminanceLux`. A
// sensor's chance of exceeding is Φ((count − hours − ½)/σ_count) (the count is a whole number: more than 250
// means at least 251). InputError as spatialDaylightAutonomy.
Estimate annualSunlightExposure(std::span<const IlluminanceSeries> directSunOnly,
                                const OccupancySchedule& schedule,
                                const AnnualSunlightExposureCriteria& criteria = {});

}  // namespace fly::daylight
