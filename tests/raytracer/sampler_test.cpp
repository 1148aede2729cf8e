#include "raytracer/sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <vector>

#include "chi2.h"

namespace fly::raytracer {
namespace {

constexpr std::array<uint64_t, 5> kSeeds = {0, 1, 2, 0x9e3779b97f4a7c15ull, 123456789};

// The value of dimension `dim` of sample `index` at point `seed`, read with next1D only.
template <Sampler S>
float dimension(uint64_t seed, uint32_t index, uint32_t dim) {
  S sampler(seed);
  sampler.startSample(index);
  float u = 0.0f;
  for (uint32_t d = 0; d <= dim; ++d) u = sampler.next1D();
  return u;
}

// The t-value of 2^m points in [0, 1)² in base 2: the smallest t such that every elementary interval
// [a/2^i, (a+1)/2^i) × [b/2^j, (b+1)/2^j) with i + j = m − t holds exactly 2^t of them ((t, m, 2)-net).
uint32_t tValue(const std::vector<vec2>& points, uint32_t m) {
  for (uint32_t t = 0;; ++t) {
    const uint32_t k = m - t;
    bool net = true;
    for (uint32_t i = 0; i <= k && net; ++i) {
      std::vector<uint32_t> count(size_t{1} << k, 0);
      for (const vec2& p : points) {
        const auto cx = static_cast<uint32_t>(std::ldexp(p.x, static_cast<int>(i)));
        const auto cy = static_cast<uint32_t>(std::ldexp(p.y, static_cast<int>(k - i)));
        ++count[(cy << i) | cx];
      }
      net = std::all_of(count.begin(), count.end(), [t](uint32_t c) { return c == (1u << t); });
    }
    if (net) return t;
  }
}

TEST(Sampler, SobolPairsAreNetsForEveryPowerOfTwo) {
  // Dimensions (0, 1) of Sobol' are a (0, 2)-sequence: every 2^m samples are a (0, m, 2)-net. Dimensions (2,
  // 3) are not; with Joe & Kuo's direction numbers their nets have these t-values for m = 0 … 10. The index
  // shuffle (a digital shift of an aligned block) and Owen scrambling preserve t, so every point seed and
  // group must give exactly these.
  constexpr std::array<uint32_t, 11> kPair23T = {0, 0, 1, 2, 0, 1, 1, 1, 1, 1, 1};
  for (uint64_t seed : kSeeds) {
    for (uint32_t group : {0u, 1u, 7u}) {
      for (uint32_t m = 0; m <= 10; ++m) {
        std::vector<vec2> first;
        std::vector<vec2> second;
        SobolSampler sampler(seed);
        for (uint32_t i = 0; i < (1u << m); ++i) {
          sampler.startSample(i);
          sampler.startGroup(group);
          first.push_back(sampler.next2D());   // dimensions (0, 1) of the group
          second.push_back(sampler.next2D());  // dimensions (2, 3)
        }
        EXPECT_EQ(tValue(first, m), 0u) << "dims (0,1), seed " << seed << ", group " << group << ", m " << m;
        EXPECT_EQ(tValue(second, m), kPair23T[m])
            << "dims (2,3), seed " << seed << ", group " << group << ", m " << m;
      }
    }
  }
}

// One sample at each of many points is a set of independent uniform points: Owen scrambling makes every point
// of the sequence uniform on [0, 1)^4, and the point seeds make them independent.
void expectUniformAcrossPoints(uint32_t group, bool secondPair) {
  test::Chi2Grid grid(32, 32);
  for (uint64_t seed = 0; seed < (1u << 18); ++seed) {
    SobolSampler sampler(seed);
    sampler.startSample(static_cast<uint32_t>(seed % 7));
    sampler.startGroup(group);
    vec2 u = sampler.next2D();
    if (secondPair) u = sampler.next2D();
    grid.add(u.x, u.y);
  }
  const test::Chi2Result r = grid.test([](double, double) { return 1.0; });
  std::cout << "[ chi2     ] Sobol group " << group << (secondPair ? " dims (2,3): " : " dims (0,1): ")
            << r.describe() << "\n";
  EXPECT_TRUE(r.passed()) << r.describe();
}

TEST(Sampler, SobolIsUniformAcrossPointsChi2) {
  expectUniformAcrossPoints(0, false);
  expectUniformAcrossPoints(0, true);
  expectUniformAcrossPoints(5, false);
}

TEST(Sampler, RandomIsUniformChi2) {
  test::Chi2Grid grid(32, 32);
  RandomSampler sampler(7);
  for (uint32_t i = 0; i < (1u << 18); ++i) {
    sampler.startSample(i);
    const vec2 u = sampler.next2D();
    grid.add(u.x, u.y);
  }
  const test::Chi2Result r = grid.test([](double, double) { return 1.0; });
  std::cout << "[ chi2     ] Random dims (0,1): " << r.describe() << "\n";
  EXPECT_TRUE(r.passed()) << r.describe();
}

TEST(Sampler, Pcg32MatchesTheReferenceImplementation) {
  // pcg32-demo of the PCG reference (O'Neill 2014), seeded with initstate 42 and stream 54.
  Pcg32 rng(42, 54);
  for (uint32_t expected : {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u, 0x83d2f293u, 0xbfa4784bu, 0xcbed606eu}) {
    EXPECT_EQ(rng.next(), expected);
  }
}

// RMSE over 128 point seeds of the N-sample estimate of ∫∫ e^x sin(πy) dx dy = (e − 1)·2/π on one dimension
// pair.
template <Sampler S>
double rmse(uint32_t n, bool secondPair) {
  const double exact = (std::exp(1.0) - 1.0) * 2.0 / kPi;
  double sumSquares = 0.0;
  constexpr int kPoints = 128;
  for (int seed = 0; seed < kPoints; ++seed) {
    S sampler(static_cast<uint64_t>(seed));
    double sum = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
      sampler.startSample(i);
      vec2 u = sampler.next2D();
      if (secondPair) u = sampler.next2D();
      sum += std::exp(static_cast<double>(u.x)) * std::sin(kPi * static_cast<double>(u.y));
    }
    const double error = sum / n - exact;
    sumSquares += error * error;
  }
  return std::sqrt(sumSquares / kPoints);
}

TEST(Sampler, SobolErrorFallsFasterThanRandom) {
  for (bool secondPair : {false, true}) {
    double previousSobol = 0.0;
    double previousRandom = 0.0;
    for (uint32_t n : {16u, 64u, 256u}) {
      const double sobol = rmse<SobolSampler>(n, secondPair);
      const double random = rmse<RandomSampler>(n, secondPair);
      std::cout << "[ rmse     ] dims " << (secondPair ? "(2,3)" : "(0,1)") << " N = " << n << ": Sobol "
                << sobol << ", random " << random << ", ratio " << random / sobol << "\n";
      EXPECT_LT(4.0 * sobol, random) << n;
      if (previousSobol > 0.0) {
        // Random error falls like N^−1/2 (×1/2 per 4× samples); Owen-scrambled nets on a smooth integrand
        // like N^−3/2 (Owen 1997): ask for at least N^−1 (×1/4).
        EXPECT_LT(sobol, previousSobol / 4.0) << n;
        EXPECT_GT(random, previousRandom / 4.0) << n;
      }
      previousSobol = sobol;
      previousRandom = random;
    }
  }
}

// Pearson's correlation coefficient of two sequences.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const auto n = static_cast<double>(a.size());
  double ma = 0.0;
  double mb = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    ma += a[i] / n;
    mb += b[i] / n;
  }
  double sab = 0.0;
  double saa = 0.0;
  double sbb = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

std::vector<double> sequence(uint64_t seed, uint32_t dim) {
  std::vector<double> values;
  for (uint32_t i = 0; i < 1024; ++i) values.push_back(dimension<SobolSampler>(seed, i, dim));
  return values;
}

TEST(Sampler, SobolSequencesOfDifferentPointsAndGroupsAreUncorrelated) {
  // For independent sequences of 1024 values, r has a standard deviation of 1/√1024 = 0.031 and E|r| = 0.025.
  double sumAbs = 0.0;
  double maxAbs = 0.0;
  constexpr int kPairs = 64;
  for (uint64_t seed = 0; seed < kPairs; ++seed) {
    const double r = correlation(sequence(seed, 0), sequence(seed + 1, 0));  // neighbouring point seeds
    sumAbs += std::abs(r);
    maxAbs = std::max(maxAbs, std::abs(r));
  }
  std::cout << "[ corr     ] neighbouring seeds, dim 0: mean |r| = " << sumAbs / kPairs
            << ", max |r| = " << maxAbs << "\n";
  EXPECT_LT(sumAbs / kPairs, 0.035);
  EXPECT_LT(maxAbs, 0.13);
  // Across groups and within a group.
  for (uint32_t dim : {1u, 2u, 3u, 4u, 9u}) {
    const double r = correlation(sequence(3, 0), sequence(3, dim));
    std::cout << "[ corr     ] seed 3, dims 0 and " << dim << ": r = " << r << "\n";
    EXPECT_LT(std::abs(r), 0.13) << dim;
  }
}

TEST(Sampler, ValuesDependOnlyOnPointSampleAndDimension) {
  constexpr uint32_t kDims = 11;
  constexpr uint32_t kSamples = 32;
  // Reference: each value by itself.
  std::vector<float> reference;
  for (uint64_t seed : kSeeds) {
    for (uint32_t i = 0; i < kSamples; ++i) {
      for (uint32_t d = 0; d < kDims; ++d) reference.push_back(dimension<SobolSampler>(seed, i, d));
    }
  }
  // Interleaved over points, samples in reverse order, a group jumped to, and 2D reads.
  std::vector<SobolSampler> samplers;
  for (uint64_t seed : kSeeds) samplers.emplace_back(seed);
  for (uint32_t i = kSamples; i-- > 0;) {
    for (size_t p = samplers.size(); p-- > 0;) {
      SobolSampler& s = samplers[p];
      const float* expected = &reference[(p * kSamples + i) * kDims];
      s.startSample(i);
      s.startGroup(2);
      EXPECT_EQ(s.next1D(), expected[8]);
      s.startSample(i);
      const vec2 a = s.next2D();
      EXPECT_EQ(a.x, expected[0]);
      EXPECT_EQ(a.y, expected[1]);
      EXPECT_EQ(s.next1D(), expected[2]);
      const vec2 b = s.next2D();  // skips dimension 3: the aligned pair (4, 5)
      EXPECT_EQ(b.x, expected[4]);
      EXPECT_EQ(b.y, expected[5]);
      for (uint32_t d = 6; d < kDims; ++d) EXPECT_EQ(s.next1D(), expected[d]) << d;
    }
  }
}

// Burley's shuffled, scrambled 4D Sobol' point computed from its definition: the group's seeds hashed from
// the point and group, the index shuffled by a Laine–Karras permutation, the Sobol' product over the eight
// nibbles of the shuffled index, each dimension's scramble, and the whole reversal of its bits; for groups
// that share a slot of the sampler's cache (0, 64; 7, 71), read alternately.
TEST(Sampler, SobolMatchesItsDefinition) {
  for (uint64_t seed : kSeeds) {
    SobolSampler sampler(seed);
    for (uint32_t index : {0u, 1u, 5u, 65535u, 65536u, 1u << 20, 0xffffffffu, 3u}) {
      sampler.startSample(index);
      for (uint32_t group : {0u, 64u, 7u, 71u, 0u, (1u << 19) + 29u, (1u << 20) + 31u}) {
        const uint64_t groupHash = detail::mix64(detail::mix64(seed) + group);
        const uint64_t a = detail::mix64(groupHash + 1);
        const uint64_t b = detail::mix64(groupHash + 2);
        const std::array<uint32_t, 4> scramble = {static_cast<uint32_t>(a), static_cast<uint32_t>(a >> 32),
                                                  static_cast<uint32_t>(b), static_cast<uint32_t>(b >> 32)};
        const uint32_t shuffled =
            detail::laineKarrasPermutation(detail::reverseBits(index), static_cast<uint32_t>(groupHash));
        sampler.startGroup(group);
        for (uint32_t d = 0; d < kGroupDimensions; ++d) {
          uint32_t reversed = 0;
          for (uint32_t k = 0; k < 8; ++k)
            reversed ^= detail::kSobolNibbles[d][k][(shuffled >> (4 * k)) & 15u];
          const float expected =
              detail::toUnitFloat(detail::reverseBits(detail::laineKarrasPermutation(reversed, scramble[d])));
          EXPECT_EQ(sampler.next1D(), expected)
              << "seed " << seed << " group " << group << " index " << index << " dimension " << d;
        }
      }
    }
  }
}

// The byte table's reversal of the 24 bits a coordinate keeps is the whole reversal's.
TEST(Sampler, ReversedToUnitFloatIsTheReversedFraction) {
  Pcg32 rng(7, 11);
  for (uint32_t i = 0; i < 100000; ++i) {
    const uint32_t x = rng.next();
    EXPECT_EQ(detail::reversedToUnitFloat(x), detail::toUnitFloat(detail::reverseBits(x))) << x;
  }
  for (uint32_t bit = 0; bit < 32; ++bit) {
    EXPECT_EQ(detail::reversedToUnitFloat(1u << bit), detail::toUnitFloat(detail::reverseBits(1u << bit)))
        << bit;
  }
  EXPECT_EQ(detail::reversedToUnitFloat(0xffffffffu), 0x1.fffffep-1f);
  EXPECT_EQ(detail::reversedToUnitFloat(0u), 0.0f);
}

TEST(Sampler, RandomValuesDependOnlyOnPointSampleAndDimension) {
  RandomSampler s(99);
  for (uint32_t i : {5u, 0u, 5u}) {
    s.startSample(i);
    s.next1D();
    const vec2 pair = s.next2D();  // dimensions (2, 3)
    EXPECT_EQ(pair.x, dimension<RandomSampler>(99, i, 2));
    EXPECT_EQ(pair.y, dimension<RandomSampler>(99, i, 3));
    EXPECT_EQ(s.next1D(), dimension<RandomSampler>(99, i, 4));
    s.startGroup(3);
    EXPECT_EQ(s.next1D(), dimension<RandomSampler>(99, i, 12));
  }
  EXPECT_NE(dimension<RandomSampler>(99, 0, 0), dimension<RandomSampler>(100, 0, 0));
  EXPECT_NE(dimension<RandomSampler>(99, 0, 0), dimension<RandomSampler>(99, 1, 0));
  EXPECT_NE(dimension<RandomSampler>(99, 0, 0), dimension<RandomSampler>(99, 0, 4));
}

// skip(n) passes over dimensions without computing them: what follows is what n next1D() calls would leave.
// And a sample's group 0, which startSample() no longer hashes up front, is the same whether reached by the
// first next1D() or by startGroup(0).
TEST(Sampler, SkipAndLazyGroupZeroKeepEveryDimension) {
  for (uint32_t i : {0u, 3u, 17u}) {
    for (uint32_t n = 0; n <= 3; ++n) {
      SobolSampler sobol(42);
      sobol.startSample(i);
      sobol.startGroup(5);
      sobol.skip(n);
      EXPECT_EQ(sobol.next1D(), dimension<SobolSampler>(42, i, 20 + n)) << n;
      RandomSampler random(42);
      random.startSample(i);
      random.startGroup(5);
      random.skip(n);
      EXPECT_EQ(random.next1D(), dimension<RandomSampler>(42, i, 20 + n)) << n;
    }
    SobolSampler lazy(7);
    SobolSampler eager(7);
    lazy.startSample(i);
    eager.startSample(i);
    eager.startGroup(0);
    for (uint32_t d = 0; d < 6; ++d) EXPECT_EQ(lazy.next1D(), eager.next1D()) << d;
    lazy.startSample(i);
    eager.startSample(i);
    eager.startGroup(0);
    EXPECT_EQ(lazy.next2D(), eager.next2D());
  }
}

TEST(Sampler, ValuesLieInTheUnitInterval) {
  for (uint64_t seed : kSeeds) {
    SobolSampler sobol(seed);
    RandomSampler random(seed);
    for (uint32_t i = 0; i < 4096; ++i) {
      sobol.startSample(i);
      random.startSample(i);
      for (int d = 0; d < 8; ++d) {
        const float a = sobol.next1D();
        const float b = random.next1D();
        ASSERT_TRUE(a >= 0.0f && a < 1.0f) << a;
        ASSERT_TRUE(b >= 0.0f && b < 1.0f) << b;
      }
    }
  }
}

}  // namespace
}  // namespace fly::raytracer
