#include "raytracer/distribution.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <vector>

#include "chi2.h"
#include "raytracer/sampler.h"

namespace fly::raytracer {
namespace {

constexpr uint32_t kSampleCount = 1'000'000;

// Bins of zero weight at both ends and inside, and a wide dynamic range.
const std::vector<float> kWeights = {0.0f, 1.0f, 3.0f, 0.0f, 0.0f, 0.5f, 7.0f, 2.0f, 0.02f, 0.0f};

TEST(Distribution, DiscreteChi2) {
  const Distribution1D dist(kWeights);
  std::vector<double> observed(kWeights.size(), 0.0);
  test::forRandomSquarePoints(kSampleCount, 1, [&](vec2 u) {
    const Distribution1D::DiscreteSample s = dist.sampleDiscrete(u.x);
    ASSERT_EQ(s.pmf, dist.pmf(s.index));
    ASSERT_GT(s.pmf, 0.0f);
    ASSERT_TRUE(s.uRemapped >= 0.0f && s.uRemapped < 1.0f);
    observed[s.index] += 1.0;
  });
  double sum = 0.0;
  for (float w : kWeights) sum += w;
  std::vector<double> expected;
  for (float w : kWeights) expected.push_back(kSampleCount * w / sum);
  test::expectFits("discrete 1D", test::chi2Test(observed, expected, test::kChi2Significance));
}

// The guide table only narrows the search: every u must get the bin whose cumulative interval holds it, with
// positive weight, on tables made to stress it — empty bins, one bin holding almost everything next to
// thousands of tiny ones (long runs inside one guide interval), geometric weights, one bin — and at every
// guide interval's edges (k / 4n, four intervals per bin, and the floats beside them).
TEST(Distribution, GuideTableFindsTheBinOfEveryU) {
  std::vector<std::vector<float>> tables = {kWeights, {5.0f}};
  std::vector<float> spike(10000, 1e-3f);
  spike[4321] = 1e6f;
  tables.push_back(spike);
  std::vector<float> geometric;
  for (int i = 0; i < 64; ++i) geometric.push_back(std::ldexp(1.0f, -i));
  tables.push_back(geometric);
  for (const std::vector<float>& weights : tables) {
    const Distribution1D dist(weights);
    std::vector<double> cdf = {0.0};
    for (float w : weights) cdf.push_back(cdf.back() + w);
    for (double& c : cdf) c /= cdf.back();
    std::vector<float> us;
    RandomSampler random(17);
    for (uint32_t i = 0; i < 20000; ++i) {
      random.startSample(i);
      us.push_back(random.next1D());
    }
    const auto n = static_cast<float>(4 * weights.size());
    for (size_t k = 0; k <= 4 * weights.size(); ++k) {
      const float edge = std::min(static_cast<float>(k) / n, 0x1.fffffep-1f);
      us.insert(us.end(), {edge, std::nextafter(edge, 0.0f), std::min(std::nextafter(edge, 1.0f), 0x1.fffffep-1f)});
    }
    for (float u : us) {
      const uint32_t i = dist.sampleDiscrete(u).index;
      ASSERT_LT(i, weights.size());
      ASSERT_GT(weights[i], 0.0f) << "u " << u;
      // Within the float rounding of the stored cumulative table.
      EXPECT_LE(cdf[i], u + 1e-6) << "u " << u << ", bin " << i << " of " << weights.size();
      EXPECT_GT(cdf[i + 1], u - 1e-6) << "u " << u << ", bin " << i << " of " << weights.size();
    }
  }
}

TEST(Distribution, ContinuousChi2) {
  const Distribution1D dist(kWeights);
  test::Chi2Grid grid(static_cast<int>(kWeights.size()) * 4,
                      1);  // four cells per bin: the offset in the bin too
  test::forRandomSquarePoints(kSampleCount, 2, [&](vec2 u) {
    const Distribution1D::Sample s = dist.sampleContinuous(u.x);
    ASSERT_EQ(s.bin, static_cast<uint32_t>(s.x * static_cast<float>(kWeights.size())));
    ASSERT_EQ(s.pdf, dist.pdf(s.x));
    grid.add(s.x, 0.5);
  });
  test::expectFits("continuous 1D", grid.test([&](double x, double) { return dist.pdf(static_cast<float>(x)); }));
}

TEST(Distribution, PdfIntegratesToOneAndMatchesTheFunction) {
  const Distribution1D dist(kWeights);
  double sum = 0.0;
  for (float w : kWeights) sum += w;
  EXPECT_NEAR(dist.integral(), sum / static_cast<double>(kWeights.size()), 1e-12);
  double integral = 0.0;
  double total = 0.0;
  for (uint32_t i = 0; i < dist.size(); ++i) {
    const float x = (static_cast<float>(i) + 0.5f) / static_cast<float>(dist.size());
    integral += static_cast<double>(dist.pdf(x)) / dist.size();
    total += dist.pmf(i);
    EXPECT_NEAR(dist.pdf(x), kWeights[i] / dist.integral(), 1e-6) << i;
  }
  EXPECT_NEAR(integral, 1.0, 1e-6);
  EXPECT_NEAR(total, 1.0, 1e-6);
}

// The values of u at the edges of the bins: 0, each cumulative value and the float just below it, the largest
// float below 1.
std::vector<float> edgeValues(const std::vector<float>& weights) {
  std::vector<float> us = {0.0f, 0x1.fffffep-1f};
  double sum = 0.0;
  for (float w : weights) sum += w;
  double running = 0.0;
  for (float w : weights) {
    running += w;
    const auto c = static_cast<float>(running / sum);
    if (c < 1.0f) us.push_back(c);
    us.push_back(std::nextafter(c, 0.0f));
  }
  return us;
}

TEST(Distribution, SamplesAtBinEdgesStayInTheirBin) {
  // A sample never falls in a bin of zero weight, and its x lies in the bin whose density it reports
  // (rounding of (i + remapped u) / n must not carry it into the next bin, which may have density 0).
  std::vector<float> many;
  RandomSampler random(17);
  for (uint32_t i = 0; i < 997; ++i) {
    random.startSample(i);
    many.push_back(i % 5 == 0 ? 0.0f : random.next1D() * 10.0f);
  }
  for (const std::vector<float>& weights : {kWeights, many}) {
    const Distribution1D dist(weights);
    for (float u : edgeValues(weights)) {
      const Distribution1D::Sample s = dist.sampleContinuous(u);
      EXPECT_GT(weights[s.bin], 0.0f) << u;
      EXPECT_EQ(dist.binOf(s.x), s.bin) << u;
      EXPECT_EQ(dist.pdf(s.x), s.pdf) << u;
      EXPECT_LT(s.x, 1.0f) << u;
      EXPECT_GT(dist.sampleDiscrete(u).pmf, 0.0f) << u;
    }
  }
}

// Distribution2D::sample's cell is the cell that holds its point, row-major, and has the density it reports:
// the integrator reads the sky's radiance from it.
TEST(Distribution, SampleReportsTheCellOfItsPoint) {
  std::vector<float> values(5 * 3);
  for (size_t i = 0; i < values.size(); ++i) values[i] = i % 4 == 1 ? 0.0f : 1.0f + static_cast<float>(i);
  const Distribution2D dist(values, 5, 3);
  for (uint32_t k = 0; k < 64; ++k) {
    for (uint32_t l = 0; l < 64; ++l) {
      const vec2 u((static_cast<float>(k) + 0.5f) / 64.0f, (static_cast<float>(l) + 0.5f) / 64.0f);
      const Distribution2D::Sample s = dist.sample(u);
      const auto col = static_cast<uint32_t>(s.p.x * 5.0f);
      const auto row = static_cast<uint32_t>(s.p.y * 3.0f);
      ASSERT_EQ(s.cell, row * 5 + col) << u.x << " " << u.y;
      EXPECT_GT(values[s.cell], 0.0f);
      EXPECT_EQ(dist.pdf(s.p), s.pdf);
    }
  }
}

TEST(Distribution, AllZeroSamplesUniformly) {
  const std::vector<float> zeros(5, 0.0f);
  const Distribution1D dist(zeros);
  EXPECT_TRUE(dist.allZero());
  EXPECT_EQ(dist.integral(), 0.0);
  const Distribution1D::Sample s = dist.sampleContinuous(0.3f);
  EXPECT_NEAR(s.x, 0.3f, 1e-6f);
  EXPECT_EQ(s.pdf, 1.0f);
  EXPECT_NEAR(dist.sampleDiscrete(0.3f).pmf, 0.2f, 1e-7f);
  EXPECT_FALSE(Distribution1D(kWeights).allZero());

  const Distribution2D flat(std::vector<float>(12, 0.0f), 4, 3);
  EXPECT_TRUE(flat.allZero());
  EXPECT_EQ(flat.sample(vec2(0.7f, 0.2f)).pdf, 1.0f);
  EXPECT_EQ(flat.pdf(vec2(0.1f, 0.9f)), 1.0f);
}

TEST(Distribution, RejectsInvalidWeights) {
  EXPECT_THROW(Distribution1D(std::vector<float>{}), std::invalid_argument);
  EXPECT_THROW(Distribution1D(std::vector<float>{1.0f, -0.5f}), std::invalid_argument);
  EXPECT_THROW(Distribution1D(std::vector<float>{1.0f, NAN}), std::invalid_argument);
  EXPECT_THROW(Distribution1D(std::vector<float>{INFINITY}), std::invalid_argument);
  EXPECT_THROW(Distribution2D(std::vector<float>(6, 1.0f), 4, 2), std::invalid_argument);
  EXPECT_THROW(Distribution2D(std::vector<float>{}, 0, 0), std::invalid_argument);
}

// A latitude–longitude sky of nu × nv cells, v the polar angle: a brighter horizon, a sun in one cell, black
// below the horizon, tabulated as L sin θ.
std::vector<float> skyTable(uint32_t nu, uint32_t nv) {
  std::vector<float> values;
  for (uint32_t j = 0; j < nv; ++j) {
    const double theta = kPi * (j + 0.5) / nv;
    for (uint32_t i = 0; i < nu; ++i) {
      double radiance =
          theta < 0.5 * kPi ? 1.0 + 2.0 * std::sin(theta) * (1.0 + std::cos(2.0 * kPi * i / nu)) : 0.0;
      if (i == nu / 3 && j == nv / 4) radiance += 500.0;
      values.push_back(static_cast<float>(radiance * std::sin(theta)));
    }
  }
  return values;
}

TEST(Distribution, SkyTableChi2) {
  constexpr uint32_t kNu = 32;
  constexpr uint32_t kNv = 16;
  const Distribution2D dist(skyTable(kNu, kNv), kNu, kNv);
  test::Chi2Grid grid(2 * kNu, 2 * kNv);
  test::forRandomSquarePoints(kSampleCount, 3, [&](vec2 u) {
    const Distribution2D::Sample s = dist.sample(u);
    ASSERT_EQ(s.pdf, dist.pdf(s.p));
    ASSERT_GT(s.pdf, 0.0f);
    grid.add(s.p.x, s.p.y);
  });
  test::expectFits("sky table 2D", grid.test([&](double x, double y) {
    return dist.pdf(vec2(static_cast<float>(x), static_cast<float>(y)));
  }));
}

TEST(Distribution, Pdf2DIntegratesToOneAndMatchesTheTable) {
  constexpr uint32_t kNu = 32;
  constexpr uint32_t kNv = 16;
  const std::vector<float> table = skyTable(kNu, kNv);
  const Distribution2D dist(table, kNu, kNv);
  double sum = 0.0;
  for (float v : table) sum += v;
  EXPECT_NEAR(dist.integral() / (sum / (kNu * kNv)), 1.0, 1e-6);
  double integral = 0.0;
  for (uint32_t j = 0; j < kNv; ++j) {
    for (uint32_t i = 0; i < kNu; ++i) {
      const vec2 p((static_cast<float>(i) + 0.5f) / kNu, (static_cast<float>(j) + 0.5f) / kNv);
      const double pdf = dist.pdf(p);
      integral += pdf / (kNu * kNv);
      EXPECT_NEAR(pdf, table[j * kNu + i] / dist.integral(), 1e-5 * pdf) << i << " " << j;
    }
  }
  EXPECT_NEAR(integral, 1.0, 1e-6);
}

}  // namespace
}  // namespace fly::raytracer
