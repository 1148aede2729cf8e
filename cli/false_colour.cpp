#include "cli/false_colour.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/math.h"

namespace fly::cli {

namespace {

constexpr double kStart = 0.5;
constexpr double kRotations = -1.5;
constexpr double kHue = 1.0;
constexpr double kLambdaMin = 0.15;
constexpr double kLambdaMax = 0.92;

// The 1-2-5 value at or below (down = true) or at or above v > 0.
double niceLog(double v, bool down) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  static constexpr double kSteps[] = {1.0, 2.0, 5.0, 10.0};
  if (down) {
    double best = decade;
    for (const double s : kSteps) {
      if (s * decade <= v * (1.0 + 1e-9)) best = s * decade;
    }
    return best;
  }
  for (const double s : kSteps) {
    if (s * decade >= v * (1.0 - 1e-9)) return s * decade;
  }
  return 10.0 * decade;
}

// A linear tick step of 1, 2 or 5 × 10^k giving at most 10 steps over `span`.
double linearStep(double span) {
  double step = niceLog(span / 10.0, false);
  return step > 0.0 ? step : 1.0;
}

}  // namespace

Rgb8 falseColour(double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  const double lambda = kLambdaMin + (kLambdaMax - kLambdaMin) * t;
  const double a = kHue * lambda * (1.0 - lambda) / 2.0;
  const double phi = 2.0 * kPi * (kStart / 3.0 + kRotations * lambda);
  const double c = std::cos(phi), s = std::sin(phi);
  auto byte = [](double v) { return int(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); };
  return {byte(lambda + a * (-0.14861 * c + 1.78277 * s)), byte(lambda + a * (-0.29227 * c - 0.90649 * s)),
          byte(lambda + a * (1.97294 * c))};
}

double FalseColourScale::fraction(double value) const {
  if (!std::isfinite(value)) return 0.0;
  double t = 0.0;
  if (logarithmic) {
    t = value > 0.0 ? std::log(value / minValue) / std::log(maxValue / minValue) : 0.0;
  } else {
    t = (value - minValue) / (maxValue - minValue);
  }
  return std::clamp(t, 0.0, 1.0);
}

double FalseColourScale::valueAt(double t) const {
  t = std::clamp(t, 0.0, 1.0);
  return logarithmic ? minValue * std::pow(maxValue / minValue, t) : minValue + t * (maxValue - minValue);
}

std::vector<double> FalseColourScale::ticks() const {
  std::vector<double> out;
  if (logarithmic) {
    for (double decade = std::pow(10.0, std::floor(std::log10(minValue))); decade <= maxValue * 1.000001;
         decade *= 10.0) {
      for (const double s : {1.0, 2.0, 5.0}) {
        const double v = s * decade;
        if (v >= minValue * 0.999999 && v <= maxValue * 1.000001) out.push_back(v);
      }
    }
    return out;
  }
  const double step = linearStep(maxValue - minValue);
  for (double k = std::ceil(minValue / step - 1e-9); k * step <= maxValue * (1.0 + 1e-9) + 1e-12; k += 1.0) {
    out.push_back(k * step);
  }
  return out;
}

FalseColourScale falseColourScale(std::span<const double> values, bool logarithmic,
                                  std::optional<std::pair<double, double>> range) {
  if (range) return {range->first, range->second, logarithmic};
  double lo = std::numeric_limits<double>::infinity();
  double hi = 0.0;
  for (const double v : values) {
    if (!std::isfinite(v) || v <= 0.0) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (hi <= 0.0) return logarithmic ? FalseColourScale{1.0, 10.0, true} : FalseColourScale{0.0, 1.0, false};
  if (logarithmic) {
    const double top = niceLog(hi, false);
    double bottom = niceLog(lo, true);
    if (bottom >= top) bottom = niceLog(top * 0.5, true);
    return {bottom, top, true};
  }
  const double step = linearStep(hi);
  return {0.0, std::ceil(hi / step - 1e-9) * step, false};
}

}  // namespace fly::cli
