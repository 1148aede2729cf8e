#include "daylight/annual_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "base/error.h"

namespace fly::daylight {

namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;
constexpr double kInvSqrt2Pi = 0.39894228040143267794;

double normalCdf(double x) {
  return 0.5 * std::erfc(-x * kInvSqrt2);
}
double normalPdf(double x) {
  return kInvSqrt2Pi * std::exp(-0.5 * x * x);
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// P(true value ≥ threshold) for a value with normal error σ, plug-in: Φ((value − threshold)/σ); with σ = 0
// the indicator of value ≥ threshold (strict: value > threshold).
double probabilityAbove(double value, double threshold, double sigma, bool strict) {
  if (sigma > 0.0) return normalCdf((value - threshold) / sigma);
  return (strict ? value > threshold : value >= threshold) ? 1.0 : 0.0;
}

// Accumulates Bernoulli indicators: the count as given, Σ p(1 − p) and Σ √(p(1 − p)).
struct IndicatorSum {
  double count = 0.0;
  double variance = 0.0;
  double sdSum = 0.0;

  void add(bool counted, double p) {
    count += counted ? 1.0 : 0.0;
    const double v = std::max(0.0, p * (1.0 - p));
    variance += v;
    sdSum += std::sqrt(v);
  }
  Estimate share(double n) const { return {count / n, std::sqrt(variance) / n, sdSum / n}; }
};

void checkThreshold(const char* what, double value) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw InputError({}, std::string(what) + " " + number(value) + " lx is not a positive illuminance",
                     "give a threshold in lux greater than 0");
  }
}

void checkSeries(const IlluminanceSeries& series, const OccupancySchedule& schedule, const std::string& who) {
  const std::size_t n = schedule.hourCount();
  if (n != kHoursPerYear && n != kHoursPerLeapYear) {
    throw InputError({}, "the occupancy schedule has " + std::to_string(n) + " hours",
                     "give a schedule of 8760 hours (8784 in a year with 29 February)");
  }
  if (series.illuminanceLux.size() != n) {
    throw InputError({},
                     who + "illuminance series has " + std::to_string(series.illuminanceLux.size()) +
                         " values; the occupancy schedule has " + std::to_string(n) + " hours",
                     "give one value per hour of the year, from 1 January 00:00–01:00 local standard time");
  }
  if (!series.standardErrorLux.empty() && series.standardErrorLux.size() != n) {
    throw InputError({},
                     who + "standard error series has " + std::to_string(series.standardErrorLux.size()) +
                         " values; the illuminance series has " + std::to_string(n),
                     "give one standard error per hour, or none for exact values");
  }
  for (std::size_t k = 0; k < n; ++k) {
    const double e = series.illuminanceLux[k];
    if (!std::isfinite(e) || e < 0.0) {
      throw InputError({}, who + "illuminance of hour " + std::to_string(k) + " is " + number(e) + " lx",
                       "illuminances are finite and not negative");
    }
    if (!series.standardErrorLux.empty()) {
      const double s = series.standardErrorLux[k];
      if (!std::isfinite(s) || s < 0.0) {
        throw InputError({}, who + "standard error of hour " + std::to_string(k) + " is " + number(s) + " lx",
                         "standard errors are finite and not negative");
      }
    }
  }
  if (schedule.occupiedCount() == 0) {
    throw InputError({}, "the occupancy schedule has no occupied hour",
                     "occupy at least one hour of the year");
  }
}

double sigmaAt(const IlluminanceSeries& series, std::size_t k) {
  return series.standardErrorLux.empty() ? 0.0 : series.standardErrorLux[k];
}

// Var(min(X, T)) for X ~ N(μ, σ²): with Z = X − T, m = μ − T and Z⁺ = max(Z, 0), min(X, T) = X − Z⁺, so
// Var = σ² + Var(Z⁺) − 2·Cov(Z, Z⁺) = σ² − E[Z⁺²] − E[Z⁺]² + 2m·E[Z⁺], where
// E[Z⁺] = m·Φ(m/σ) + σ·φ(m/σ) and E[Z⁺²] = (m² + σ²)·Φ(m/σ) + m·σ·φ(m/σ).
double varianceOfMin(double mu, double sigma, double threshold) {
  if (!(sigma > 0.0)) return 0.0;
  const double m = mu - threshold;
  const double a = m / sigma;
  const double cdf = normalCdf(a);
  const double pdf = normalPdf(a);
  const double zPlus = m * cdf + sigma * pdf;
  const double zPlus2 = (m * m + sigma * sigma) * cdf + m * sigma * pdf;
  return std::max(0.0, sigma * sigma - zPlus2 - zPlus * zPlus + 2.0 * m * zPlus);
}

void checkGrid(std::span<const IlluminanceSeries> sensors, const OccupancySchedule& schedule) {
  if (sensors.empty()) throw InputError({}, "the sensor grid is empty", "give at least one sensor");
  for (std::size_t s = 0; s < sensors.size(); ++s)
    checkSeries(sensors[s], schedule, "sensor " + std::to_string(s) + ": ");
}

}  // namespace

std::size_t OccupancySchedule::occupiedCount() const {
  return static_cast<std::size_t>(std::count(occupied.begin(), occupied.end(), true));
}

OccupancySchedule dailyOccupancy(int startHour, int endHour, std::size_t hoursInYear) {
  if (startHour < 0 || endHour > 24 || startHour >= endHour) {
    throw InputError({}, "occupied hours " + std::to_string(startHour) + " to " + std::to_string(endHour),
                     "give whole hours of local standard time with 0 ≤ start < end ≤ 24, e.g. 8 to 18");
  }
  if (hoursInYear != kHoursPerYear && hoursInYear != kHoursPerLeapYear) {
    throw InputError({}, "a year of " + std::to_string(hoursInYear) + " hours",
                     "give 8760 hours (8784 in a year with 29 February)");
  }
  OccupancySchedule s;
  s.occupied.resize(hoursInYear);
  for (std::size_t k = 0; k < hoursInYear; ++k) {
    const int hourOfDay = static_cast<int>(k % 24);
    s.occupied[k] = hourOfDay >= startHour && hourOfDay < endHour;
  }
  return s;
}

SensorMetrics sensorMetrics(const IlluminanceSeries& series, const OccupancySchedule& schedule,
                            const MetricThresholds& thresholds) {
  checkThreshold("daylight autonomy threshold", thresholds.daylightAutonomyLux);
  checkThreshold("UDI lower bound", thresholds.udiLowerLux);
  checkThreshold("UDI upper bound", thresholds.udiUpperLux);
  if (!(thresholds.udiLowerLux < thresholds.udiUpperLux)) {
    throw InputError({},
                     "UDI bounds " + number(thresholds.udiLowerLux) + " lx and " +
                         number(thresholds.udiUpperLux) + " lx are not increasing",
                     "give a lower bound below the upper one, e.g. 100 and 3000 lx");
  }
  checkSeries(series, schedule, "");
  const double t = thresholds.daylightAutonomyLux;
  IndicatorSum da, below, useful, above;
  double cda = 0.0, cdaVariance = 0.0, cdaSdSum = 0.0;
  double n = 0.0;
  for (std::size_t k = 0; k < schedule.hourCount(); ++k) {
    if (!schedule.occupied[k]) continue;
    n += 1.0;
    const double e = series.illuminanceLux[k];
    const double sigma = sigmaAt(series, k);
    da.add(e >= t, probabilityAbove(e, t, sigma, false));
    const double pBelow = 1.0 - probabilityAbove(e, thresholds.udiLowerLux, sigma, false);
    const double pAbove = probabilityAbove(e, thresholds.udiUpperLux, sigma, true);
    below.add(e < thresholds.udiLowerLux, pBelow);
    above.add(e > thresholds.udiUpperLux, pAbove);
    useful.add(e >= thresholds.udiLowerLux && e <= thresholds.udiUpperLux,
               std::max(0.0, 1.0 - pBelow - pAbove));
    cda += std::min(1.0, e / t);
    const double v = varianceOfMin(e, sigma, t) / (t * t);
    cdaVariance += v;
    cdaSdSum += std::sqrt(v);
  }
  return {da.share(n),
          {cda / n, std::sqrt(cdaVariance) / n, cdaSdSum / n},
          below.share(n),
          useful.share(n),
          above.share(n)};
}

Estimate hoursAbove(const IlluminanceSeries& series, const OccupancySchedule& schedule, double thresholdLux) {
  checkThreshold("illuminance threshold", thresholdLux);
  checkSeries(series, schedule, "");
  IndicatorSum sum;
  for (std::size_t k = 0; k < schedule.hourCount(); ++k) {
    if (!schedule.occupied[k]) continue;
    const double e = series.illuminanceLux[k];
    sum.add(e > thresholdLux, probabilityAbove(e, thresholdLux, sigmaAt(series, k), true));
  }
  return sum.share(1.0);
}

Estimate spatialDaylightAutonomy(std::span<const IlluminanceSeries> sensors,
                                 const OccupancySchedule& schedule,
                                 const SpatialDaylightAutonomyCriteria& criteria) {
  checkThreshold("sDA illuminance", criteria.illuminanceLux);
  if (!(criteria.timeShare >= 0.0 && criteria.timeShare <= 1.0)) {
    throw InputError({}, "sDA time share " + number(criteria.timeShare) + " is outside [0, 1]",
                     "give the share of occupied hours as a fraction, e.g. 0.5 for 50 %");
  }
  checkGrid(sensors, schedule);
  MetricThresholds thresholds;
  thresholds.daylightAutonomyLux = criteria.illuminanceLux;
  IndicatorSum independent, bound;
  for (const IlluminanceSeries& s : sensors) {
    const Estimate da = sensorMetrics(s, schedule, thresholds).daylightAutonomy;
    const bool passes = da.value >= criteria.timeShare;
    independent.add(passes, probabilityAbove(da.value, criteria.timeShare, da.standardError, false));
    bound.add(passes, probabilityAbove(da.value, criteria.timeShare, da.standardErrorBound, false));
  }
  const double n = static_cast<double>(sensors.size());
  return {independent.count / n, std::sqrt(independent.variance) / n, bound.sdSum / n};
}

Estimate annualSunlightExposure(std::span<const IlluminanceSeries> directSunOnly,
                                const OccupancySchedule& schedule,
                                const AnnualSunlightExposureCriteria& criteria) {
  checkThreshold("ASE illuminance", criteria.illuminanceLux);
  if (!(criteria.hours >= 0.0) || !std::isfinite(criteria.hours)) {
    throw InputError({}, "ASE hours " + number(criteria.hours) + " is not a number of hours",
                     "give the hours a sensor may exceed the illuminance, e.g. 250");
  }
  checkGrid(directSunOnly, schedule);
  // More than `hours` hours: at least ⌊hours⌋ + 1; the normal approximation of the count is cut half-way.
  const double cut = std::floor(criteria.hours) + 0.5;
  IndicatorSum independent, bound;
  for (const IlluminanceSeries& s : directSunOnly) {
    const Estimate count = hoursAbove(s, schedule, criteria.illuminanceLux);
    const bool exposed = count.value > criteria.hours;
    independent.add(exposed, count.standardError > 0.0 ? normalCdf((count.value - cut) / count.standardError)
                                                       : (exposed ? 1.0 : 0.0));
    bound.add(exposed, count.standardErrorBound > 0.0
                           ? normalCdf((count.value - cut) / count.standardErrorBound)
                           : (exposed ? 1.0 : 0.0));
  }
  const double n = static_cast<double>(directSunOnly.size());
  return {independent.count / n, std::sqrt(independent.variance) / n, bound.sdSum / n};
}

}  // namespace fly::daylight
