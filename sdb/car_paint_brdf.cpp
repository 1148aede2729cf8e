#include "sdb/car_paint_brdf.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fly::sdb {
namespace {

constexpr float kPi = 3.14159265358979323846f;

}  // namespace

namespace {

// The fit's unconstrained parameters x ↦ the model: colours and reflectances through a logistic function
// into (0, 1), widths through one into their ranges.
float logistic(double x) { return float(1.0 / (1.0 + std::exp(-x))); }
double logit(float y) {
  const double c = std::clamp(double(y), 1e-4, 1.0 - 1e-4);
  return std::log(c / (1.0 - c));
}

struct Parametrisation {
  int lobes = 2;
  float coatIor = 1.5f;
  int count() const { return 3 + 4 * lobes + 1; }
  CarPaintBrdf brdf(const std::vector<double>& x) const {
    CarPaintBrdf b;
    b.coatIor = coatIor;
    b.baseAlbedo = Rgb(logistic(x[0]), logistic(x[1]), logistic(x[2]));
    for (int k = 0; k < lobes; ++k) {
      const double* l = &x[size_t(3 + 4 * k)];
      b.lobes[size_t(k)].f0 = Rgb(logistic(l[0]), logistic(l[1]), logistic(l[2]));
      b.lobes[size_t(k)].alpha = 0.01f + 0.99f * logistic(l[3]);
    }
    b.coatAlpha = 0.001f + 0.999f * logistic(x[size_t(3 + 4 * lobes)]);
    return b;
  }
  std::vector<double> parameters(const CarPaintBrdf& b) const {
    std::vector<double> x(static_cast<size_t>(count()), 0.0);
    for (int c = 0; c < 3; ++c) x[size_t(c)] = logit(b.baseAlbedo[c]);
    for (int k = 0; k < lobes; ++k) {
      for (int c = 0; c < 3; ++c) x[size_t(3 + 4 * k + c)] = logit(b.lobes[size_t(k)].f0[c]);
      x[size_t(3 + 4 * k + 3)] = logit((b.lobes[size_t(k)].alpha - 0.01f) / 0.99f);
    }
    x[size_t(3 + 4 * lobes)] = logit((b.coatAlpha - 0.001f) / 0.999f);
    return x;
  }
};

struct FitSample {
  vec3 wi, wo;
  Rgb value;
  float cosWeight;
};

// Solves the symmetric positive definite n × n system a·x = b in place (Cholesky); false when a is singular.
bool solveSpd(std::vector<double> a, std::vector<double>& b, int n) {
  for (int j = 0; j < n; ++j) {
    double d = a[size_t(j * n + j)];
    for (int k = 0; k < j; ++k) d -= a[size_t(j * n + k)] * a[size_t(j * n + k)];
    if (!(d > 0.0)) return false;
    d = std::sqrt(d);
    a[size_t(j * n + j)] = d;
    for (int i = j + 1; i < n; ++i) {
      double s = a[size_t(i * n + j)];
      for (int k = 0; k < j; ++k) s -= a[size_t(i * n + k)] * a[size_t(j * n + k)];
      a[size_t(i * n + j)] = s / d;
    }
  }
  for (int i = 0; i < n; ++i) {
    double s = b[size_t(i)];
    for (int k = 0; k < i; ++k) s -= a[size_t(i * n + k)] * b[size_t(k)];
    b[size_t(i)] = s / a[size_t(i * n + i)];
  }
  for (int i = n - 1; i >= 0; --i) {
    double s = b[size_t(i)];
    for (int k = i + 1; k < n; ++k) s -= a[size_t(k * n + i)] * b[size_t(k)];
    b[size_t(i)] = s / a[size_t(i * n + i)];
  }
  return true;
}

}  // namespace

CarPaintFit fitCarPaint(const MeasuredBrdf& table, int lobes, float coatIor) {
  const Parametrisation param{std::clamp(lobes, 1, CarPaintBrdf::kMaxLobes), coatIor};
  // The samples: every θh (the highlight is resolved in θh), every 4th θd and every 10th φd, measured and
  // with both directions within 80° of the normal (beyond, grazing measurements are the least reliable).
  const std::vector<uint8_t>& valid = MeasuredBrdf::validSamples();
  const float cos80 = std::cos(80.0f * kPi / 180.0f);
  std::vector<FitSample> samples;
  for (int i = 0; i < MeasuredBrdf::kThetaHalfRes; ++i) {
    for (int j = 0; j < MeasuredBrdf::kThetaDiffRes; j += 4) {
      for (int k = 0; k < MeasuredBrdf::kPhiDiffRes; k += 10) {
        if (!valid[MeasuredBrdf::sampleIndex(i, j, k)]) continue;
        FitSample s;
        directionsOf(MeasuredBrdf::sampleAngles(i, j, k), s.wi, s.wo);
        if (s.wi.z < cos80 || s.wo.z < cos80) continue;
        s.value = table.sample(i, j, k);
        s.cosWeight = s.wi.z * s.wo.z;
        samples.push_back(s);
      }
    }
  }
  // ε keeps the logarithm finite where the table is 0: 1 % of a white Lambertian surface.
  constexpr float kEpsilon = 0.01f / kPi;
  const size_t residualCount = samples.size() * 3;
  auto residuals = [&](const std::vector<double>& x, std::vector<double>& r) {
    const CarPaintBrdf b = param.brdf(x);
    r.resize(residualCount);
    for (size_t s = 0; s < samples.size(); ++s) {
      const Rgb f = b.evalPerSr(samples[s].wi, samples[s].wo);
      for (int c = 0; c < 3; ++c) {
        r[s * 3 + size_t(c)] = std::log(double(f[c]) + kEpsilon) - std::log(double(samples[s].value[c]) + kEpsilon);
      }
    }
  };
  auto cost = [](const std::vector<double>& r) {
    double c = 0.0;
    for (double v : r) c += v * v;
    return c;
  };

  // Start: ρd from the table's mean away from the highlight (θh ≥ 45°), where lobes and coat add little;
  // two lobes of different widths; a smooth coat.
  Rgb farMean(0.0f);
  int farCount = 0;
  for (const FitSample& s : samples) {
    if (glm::normalize(s.wi + s.wo).z < std::cos(kPi / 4.0f)) {
      farMean += s.value;
      ++farCount;
    }
  }
  CarPaintBrdf start;
  start.coatIor = coatIor;
  start.baseAlbedo = glm::clamp(farMean / float(std::max(farCount, 1)) * kPi * coatIor * coatIor, Rgb(0.01f), Rgb(0.95f));
  const float startAlpha[CarPaintBrdf::kMaxLobes] = {0.15f, 0.4f, 0.05f};
  for (int k = 0; k < param.lobes; ++k) start.lobes[size_t(k)] = {Rgb(0.2f), startAlpha[k]};
  start.coatAlpha = 0.03f;

  const int n = param.count();
  std::vector<double> x = param.parameters(start);
  std::vector<double> r, rTrial, rStep;
  residuals(x, r);
  double c = cost(r);
  double lambda = 1e-3;
  constexpr int kMaxIterations = 60;
  int iteration = 0;
  bool converged = false;
  std::vector<double> jac(residualCount * size_t(n));
  for (; iteration < kMaxIterations && !converged; ++iteration) {
    for (int p = 0; p < n; ++p) {
      std::vector<double> xs = x;
      constexpr double kStep = 1e-4;
      xs[size_t(p)] += kStep;
      residuals(xs, rStep);
      for (size_t i = 0; i < residualCount; ++i) jac[i * size_t(n) + size_t(p)] = (rStep[i] - r[i]) / kStep;
    }
    std::vector<double> jtj(size_t(n * n), 0.0), jtr(size_t(n), 0.0);
    for (size_t i = 0; i < residualCount; ++i) {
      const double* row = &jac[i * size_t(n)];
      for (int a = 0; a < n; ++a) {
        jtr[size_t(a)] += row[a] * r[i];
        for (int b = 0; b <= a; ++b) jtj[size_t(a * n + b)] += row[a] * row[b];
      }
    }
    for (int a = 0; a < n; ++a) {
      for (int b = a + 1; b < n; ++b) jtj[size_t(a * n + b)] = jtj[size_t(b * n + a)];
    }
    bool improved = false;
    for (int attempt = 0; attempt < 10 && !improved; ++attempt) {
      std::vector<double> damped = jtj;
      for (int a = 0; a < n; ++a) damped[size_t(a * n + a)] *= 1.0 + lambda;
      std::vector<double> delta = jtr;
      if (!solveSpd(damped, delta, n)) {
        lambda *= 10.0;
        continue;
      }
      std::vector<double> xt = x;
      for (int a = 0; a < n; ++a) xt[size_t(a)] -= delta[size_t(a)];
      residuals(xt, rTrial);
      const double ct = cost(rTrial);
      if (ct < c) {
        improved = true;
        const double gain = (c - ct) / c;
        x = std::move(xt);
        r.swap(rTrial);
        c = ct;
        lambda = std::max(lambda / 10.0, 1e-9);
        converged = gain < 1e-7;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }

  CarPaintFit fit;
  fit.brdf = param.brdf(x);
  fit.iterations = iteration;
  double sum = 0.0, sumWeighted = 0.0, weights = 0.0;
  for (const FitSample& s : samples) {
    const Rgb f = fit.brdf.evalPerSr(s.wi, s.wo);
    for (int ch = 0; ch < 3; ++ch) {
      const double e = (double(f[ch]) - s.value[ch]) / (double(s.value[ch]) + kEpsilon);
      sum += e * e;
      sumWeighted += s.cosWeight * e * e;
      weights += s.cosWeight;
    }
  }
  fit.rmsRelativeError = float(std::sqrt(sum / double(residualCount)));
  fit.rmsRelativeErrorCosWeighted = float(std::sqrt(sumWeighted / weights));
  return fit;
}

}  // namespace fly::sdb
