// Pearson's chi-square goodness-of-fit test for sample warps, in the manner of pbrt-v4's Chi2Test and
// Mitsuba's ChiSquareTest: samples are binned on a grid over [0, 1)² (a chart of the sampled domain), the
// expected count of each cell is the sample count times the density integrated over the cell, cells expected
// to hold fewer than 5 samples are pooled, and the statistic is compared with the chi-square distribution's
// critical value.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <iostream>

#include "base/math.h"
#include "raytracer/sampler.h"

namespace fly::raytracer::test {

// The chi-square tests of correct samplers in this binary (sampler_test 4, warp_test 8, distribution_test 3,
// measured_brdf_test 4, bsdf_test 4), for a Bonferroni-corrected significance: the probability that any of them fails by
// chance is at most 1 %.
inline constexpr int kChi2TestCount = 23;
inline constexpr double kChi2Significance = 0.01 / kChi2TestCount;

// The regularised upper incomplete gamma function Q(a, x) = Γ(a, x) / Γ(a) for a > 0, x ≥ 0: by the series of
// P = 1 − Q for x < a + 1, otherwise by Legendre's continued fraction for Q evaluated with the modified Lentz
// method (Abramowitz & Stegun 6.5.29 and 6.5.31; Press et al., "Numerical Recipes", 3rd ed., §6.2).
inline double regularizedGammaQ(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double logPrefactor = a * std::log(x) - x - std::lgamma(a);
  constexpr double kEpsilon = 1e-15;
  constexpr int kMaxTerms = 100000;
  if (x < a + 1.0) {
    // P(a, x) = e^−x x^a / Γ(a + 1) · Σₙ xⁿ / ((a + 1) … (a + n)).
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < kMaxTerms && std::abs(term) > std::abs(sum) * kEpsilon; ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return 1.0 - sum * std::exp(logPrefactor);
  }
  // Q(a, x) = e^−x x^a / Γ(a) · 1 / (x + 1 − a − 1·(1 − a) / (x + 3 − a − 2·(2 − a) / (x + 5 − a − …))).
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double h = d;
  for (int n = 1; n < kMaxTerms; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEpsilon) break;
  }
  return std::exp(logPrefactor) * h;
}

// P(X ≥ statistic) for X chi-square distributed with dof degrees of freedom.
inline double chi2Survival(double statistic, int dof) {
  return regularizedGammaQ(0.5 * dof, 0.5 * statistic);
}

// The value that X exceeds with probability alpha, by bisection on chi2Survival.
inline double chi2Critical(double alpha, int dof) {
  double lo = 0.0;
  double hi = std::max(1.0, 2.0 * dof);
  while (chi2Survival(hi, dof) > alpha) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2Survival(mid, dof) > alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct Chi2Result {
  double statistic = 0.0;
  int dof = 0;
  double pValue = 0.0;
  double critical = 0.0;
  std::string failure;  // empty when the samples fit

  bool passed() const { return failure.empty(); }
  std::string describe() const {
    std::ostringstream s;
    s << "chi2 = " << statistic << ", dof = " << dof << ", critical = " << critical << ", p = " << pValue;
    if (!failure.empty()) s << ": " << failure;
    return s.str();
  }
};

// Pearson's test of observed against expected counts (Σ expected = Σ observed). A sample in a cell expected
// to hold none fails at once; cells expected below minExpected are pooled into one (if that stays below, into
// the smallest other cell).
inline Chi2Result chi2Test(std::span<const double> observed, std::span<const double> expected, double alpha,
                           double minExpected = 5.0) {
  Chi2Result result;
  std::vector<std::pair<double, double>> cells;  // (expected, observed)
  double pooledExpected = 0.0;
  double pooledObserved = 0.0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] == 0.0 && observed[i] > 0.0) {
      result.failure = std::to_string(static_cast<long long>(observed[i])) + " samples in cell " +
                       std::to_string(i) + ", where the density is 0";
      return result;
    }
    if (expected[i] < minExpected) {
      pooledExpected += expected[i];
      pooledObserved += observed[i];
    } else {
      cells.emplace_back(expected[i], observed[i]);
    }
  }
  if (pooledExpected >= minExpected) {
    cells.emplace_back(pooledExpected, pooledObserved);
  } else if (pooledExpected > 0.0 && !cells.empty()) {
    auto smallest = std::min_element(cells.begin(), cells.end());
    smallest->first += pooledExpected;
    smallest->second += pooledObserved;
  }
  for (const auto& [e, o] : cells) result.statistic += (o - e) * (o - e) / e;
  result.dof = static_cast<int>(cells.size()) - 1;
  if (result.dof < 1) {
    result.failure = "fewer than two cells after pooling";
    return result;
  }
  if (!std::isfinite(result.statistic)) {
    result.failure = "the statistic is not finite (a density of NaN or ∞)";
    return result;
  }
  result.pValue = chi2Survival(result.statistic, result.dof);
  result.critical = chi2Critical(alpha, result.dof);
  if (result.pValue < alpha) result.failure = "rejected at significance " + std::to_string(alpha);
  return result;
}

// A histogram on nx × ny cells over [0, 1)², the chart in which a test bins its samples. Samples outside the
// chart land in a cell of their own whose expected count is 0.
class Chi2Grid {
 public:
  Chi2Grid(int nx, int ny) : nx_(nx), ny_(ny), counts_(static_cast<size_t>(nx * ny) + 1, 0.0) {}

  void add(double s, double t) {
    const bool inside = s >= 0.0 && s < 1.0 && t >= 0.0 && t < 1.0;
    const size_t cell = inside ? static_cast<size_t>(std::min(static_cast<int>(t * ny_), ny_ - 1) * nx_ +
                                                     std::min(static_cast<int>(s * nx_), nx_ - 1))
                               : counts_.size() - 1;
    counts_[cell] += 1.0;
  }

  // Tests the samples added against `density`, a density over the chart (the domain's density times the
  // Jacobian of the map from chart to domain), integrated over each cell by 5-point Gauss–Legendre quadrature
  // per axis (Abramowitz & Stegun, table 25.4): its nodes lie inside the cell, so a density that jumps at a
  // cell edge (the rim of a hemisphere or cone, a bin of a tabulated distribution) is integrated exactly
  // there.
  Chi2Result test(const std::function<double(double s, double t)>& density) const {
    constexpr std::array<double, 5> kNodes = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                              0.5384693101056831, 0.9061798459386640};
    constexpr std::array<double, 5> kWeights = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                                0.4786286704993665, 0.2369268850561891};
    const double sampleCount = std::accumulate(counts_.begin(), counts_.end(), 0.0);
    std::vector<double> expected(counts_.size(), 0.0);
    const double ds = 1.0 / nx_;
    const double dt = 1.0 / ny_;
    for (int cy = 0; cy < ny_; ++cy) {
      for (int cx = 0; cx < nx_; ++cx) {
        double sum = 0.0;
        for (size_t j = 0; j < kNodes.size(); ++j) {
          const double t = (cy + 0.5 + 0.5 * kNodes[j]) * dt;
          for (size_t i = 0; i < kNodes.size(); ++i) {
            sum += kWeights[i] * kWeights[j] * density((cx + 0.5 + 0.5 * kNodes[i]) * ds, t);
          }
        }
        expected[static_cast<size_t>(cy * nx_ + cx)] = sampleCount * sum * 0.25 * ds * dt;
      }
    }
    return chi2Test(counts_, expected, kChi2Significance);
  }

 private:
  int nx_;
  int ny_;
  std::vector<double> counts_;  // row-major cells, then the outside cell
};

// Charts of the sphere for direction tests. (s, t) = ((z + 1) / 2, φ / 2π) is equal-area: dω = dz dφ = 4π ds
// dt.
inline dvec2 sphereChart(const vec3& d) {
  const double phi = std::atan2(static_cast<double>(d.y), static_cast<double>(d.x));
  return dvec2(0.5 * (static_cast<double>(d.z) + 1.0), (phi < 0.0 ? phi + 2.0 * kPi : phi) / (2.0 * kPi));
}
inline dvec3 sphereChartDirection(double s, double t) {
  const double z = 2.0 * s - 1.0;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return dvec3(r * std::cos(2.0 * kPi * t), r * std::sin(2.0 * kPi * t), z);
}
inline constexpr double kSphereChartJacobian = 4.0 * kPi;

// Calls f with `count` independent uniform points of the unit square (a chi-square test needs independent
// samples, not a net).
template <class F>
void forRandomSquarePoints(uint32_t count, uint64_t seed, F f) {
  RandomSampler sampler(seed);
  for (uint32_t i = 0; i < count; ++i) {
    sampler.startSample(i);
    f(sampler.next2D());
  }
}

// Prints a chi-square result and fails the test unless it passed.
inline void expectFits(const char* name, const Chi2Result& r) {
  std::cout << "[ chi2     ] " << name << ": " << r.describe() << "\n";
  EXPECT_TRUE(r.passed()) << name << ": " << r.describe();
}

}  // namespace fly::raytracer::test
