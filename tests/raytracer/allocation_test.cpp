// Sample allocation by error (EstimateSettings::allocationFraction, raytracer/progressive.h): which points
// skip a pass on constructed estimates; that points far below the p95 skip while those that set it take
// every pass; that the allocated estimate is the same for any thread count and when continued from any
// checkpoint (and a checkpoint of format 4, written before the allocation, still continues to the same
// estimate); and that the means of points that skipped stay unbiased and their reported errors honest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "base/fnv1a.h"
#include "raytracer/progressive.h"

namespace fly::raytracer {
namespace {

IrradianceEstimate estimate(float meanLux, float relativeError, uint32_t samples) {
  IrradianceEstimate e;
  e.meanLux = Rgb(meanLux);
  e.stdErrorLux = Rgb(meanLux * relativeError);
  e.samples = samples;
  return e;
}

// p95 10 %, fraction 0.5: a point is low below 5 %. Groups 0 (points 0–19) and 1 (20–39) make the blocks
// [0, 16), [16, 20), [20, 36) and [36, 40).
TEST(AllocationRuleTest, APointSkipsWhenItsBlockNeighboursAreFarBelowTheP95) {
  std::vector<IrradianceEstimate> points(40, estimate(100.0f, 0.01f, 64));
  std::vector<uint32_t> groups(40, 0);
  for (size_t i = 20; i < 40; ++i) groups[i] = 1;
  points[19] = estimate(100.0f, 0.20f, 64);  // high, in the block [16, 20)
  points[25] = estimate(0.0f, 0.0f, 64);     // no light seen, in [20, 36)
  for (size_t i = 36; i < 40; ++i) points[i] = estimate(100.0f, 0.01f, 32);  // too few samples
  EstimateSettings settings;
  settings.allocationFraction = 0.5f;
  const std::vector<uint8_t> takes = pointsTakingNextPass(points, groups, 0.10f, settings);
  ASSERT_EQ(takes.size(), 40u);
  for (size_t i = 0; i < 16; ++i) EXPECT_EQ(takes[i], 0) << "all low: point " << i << " skips";
  for (size_t i = 16; i < 19; ++i) EXPECT_EQ(takes[i], 1) << "a high neighbour: point " << i << " takes it";
  EXPECT_EQ(takes[19], 0) << "its neighbours are low; its own estimate stays out of its decision";
  for (size_t i = 20; i < 36; ++i) {
    if (i != 25) {
      EXPECT_EQ(takes[i], 1) << "a neighbour of mean 0: point " << i << " takes it";
    }
  }
  EXPECT_EQ(takes[25], 0);
  for (size_t i = 36; i < 40; ++i) EXPECT_EQ(takes[i], 1) << "fewer samples than the minimum: point " << i;

  // Off: every point takes every pass.
  settings.allocationFraction = 0.0f;
  for (uint8_t t : pointsTakingNextPass(points, groups, 0.10f, settings)) EXPECT_EQ(t, 1);
}

// A point that skipped while the rest of its block sampled (the high point of [16, 20) above): its neighbours
// now have 128 samples, it has 64. It takes the next pass, whatever its own error, until it is level with
// the most that any other point of its block has; a point level with or ahead of its block skips as before
// when all its neighbours are low.
TEST(AllocationRuleTest, APointBehindItsBlockCatchesUpBeforeItSkipsAgain) {
  std::vector<IrradianceEstimate> points(16, estimate(100.0f, 0.01f, 128));
  points[3] = estimate(100.0f, 0.01f, 64);   // behind, low
  points[9] = estimate(100.0f, 0.01f, 256);  // ahead, low
  EstimateSettings settings;
  settings.allocationFraction = 0.5f;
  std::vector<uint8_t> takes = pointsTakingNextPass(points, {}, 0.10f, settings);
  for (size_t i = 0; i < 16; ++i) EXPECT_EQ(takes[i], i == 3 ? 1 : 0) << "point " << i;
  // Its own error high: its neighbours take the pass for it (as before), and it takes it to catch up.
  points[3] = estimate(100.0f, 0.20f, 64);
  takes = pointsTakingNextPass(points, {}, 0.10f, settings);
  for (size_t i = 0; i < 16; ++i) EXPECT_EQ(takes[i], 1) << "point " << i;
}

// A pass narrowed to the time left: four blocks of 16 points with errors of 2 %, 6 %, 9 % and 30 % under a p95
// of 10 % and a fraction of 0.7 (threshold 7 %): the first two blocks skip, the last two take the pass.
// When only 16 points fit in the time left, the fraction rises (× 1.1 per step: 0.77, 0.847, 0.932) until
// the 9 % block skips too (at 0.932, threshold 9.32 %) and the block with the highest errors alone takes it;
// when not even one block fits below a fraction of 1, nothing does.
TEST(AllocationRuleTest, APassNarrowedToTheTimeLeftKeepsTheBlocksWithTheHighestErrors) {
  std::vector<IrradianceEstimate> points;
  for (const float error : {0.02f, 0.06f, 0.09f, 0.30f}) {
    for (int i = 0; i < 16; ++i) points.push_back(estimate(100.0f, error, 64));
  }
  EstimateSettings settings;
  settings.allocationFraction = 0.7f;
  auto count = [](const std::vector<uint8_t>& t) {
    size_t n = 0;
    for (uint8_t x : t) n += x;
    return n;
  };
  const std::vector<uint8_t> all = pointsTakingNextPass(points, {}, 0.10f, settings);
  EXPECT_EQ(count(all), 32u);
  for (size_t i = 32; i < 64; ++i) EXPECT_EQ(all[i], 1) << i;
  uint32_t tries = 0;
  const std::vector<uint8_t> fitted =
      pointsFittingTheTimeLeft(points, {}, 0.10f, settings, [&](std::vector<uint8_t>& t) {
        ++tries;
        return count(t) > 0 && count(t) <= 16;
      });
  ASSERT_EQ(fitted.size(), 64u);
  EXPECT_EQ(count(fitted), 16u);
  for (size_t i = 48; i < 64; ++i) EXPECT_EQ(fitted[i], 1) << "the 30 % block: point " << i;
  EXPECT_EQ(tries, 3u);
  EXPECT_TRUE(pointsFittingTheTimeLeft(points, {}, 0.10f, settings, [&](std::vector<uint8_t>& t) {
                return count(t) > 0 && count(t) < 16;
              }).empty());
}

// With a target error above the p95, the threshold is the fraction of the target; a point exactly at the
// threshold is not low; a point alone in its group (no neighbours) takes every pass.
TEST(AllocationRuleTest, TheTargetRaisesTheThresholdAndLonePointsTakeEveryPass) {
  EstimateSettings settings;
  settings.allocationFraction = 0.5f;
  settings.targetRelativeError = 0.2f;  // threshold 10 %, though the p95 is 4 %
  std::vector<IrradianceEstimate> points(4, estimate(5.0f, 0.08f, 128));
  EXPECT_EQ(pointsTakingNextPass(points, {}, 0.04f, settings), std::vector<uint8_t>(4, 0));
  points[2] = estimate(5.0f, 0.1f, 128);  // at the threshold: not low
  EXPECT_EQ(pointsTakingNextPass(points, {}, 0.04f, settings), (std::vector<uint8_t>{1, 1, 0, 1}));
  const std::vector<IrradianceEstimate> lone(1, estimate(5.0f, 0.001f, 128));
  EXPECT_EQ(pointsTakingNextPass(lone, {}, 0.04f, settings), std::vector<uint8_t>(1, 1));
}

// Blocks of 16 points of four kinds, each with the exact mean 1: quiet (2v: relative deviation of a sample
// 0.58), rare bright samples (4 with probability 1/4: 1.7), rarer ones (16 with probability 1/16: 3.9; at 64
// samples their relative error, 0.48, is about half the p95, so that it falls on either side of the
// allocation's threshold by chance) and the rarest (64 with probability 1/64: 7.9, the points that set the
// p95). The rare samples are what makes a point look converged by chance; they stay rare under plain Monte
// Carlo (the tests' sampler: scrambled Sobol' points would stratify them away).
class FourKindsSource final : public SampleSourceOf<FourKindsSource> {
  friend SampleSourceOf<FourKindsSource>;

 public:
  static constexpr size_t kPoints = 64 * kAllocationBlockPoints;
  size_t pointCount() const override { return kPoints; }
  static int kindOf(size_t point) { return static_cast<int>(point / kAllocationBlockPoints % 4); }

 private:
  template <class S>
  Rgb sampleAt(size_t point, S& sampler, uint64_t& rays) const {
    sampler.startGroup(0);
    const float u = sampler.next1D();
    const float v = sampler.next1D();
    ++rays;
    switch (kindOf(point)) {
      case 0:
        return Rgb(2.0f * v);
      case 1:
        return Rgb(u < 0.25f ? 4.0f : 0.0f);
      case 2:
        return Rgb(u < 0.0625f ? 16.0f : 0.0f);
      default:
        return Rgb(u < 0.015625f ? 64.0f : 0.0f);
    }
  }
};

EstimateSettings allocated(SamplerKind sampler, uint64_t seed) {
  EstimateSettings settings;
  settings.firstPassSamples = 16;
  settings.maxSamples = 1024;
  settings.sampler = sampler;
  settings.seed = seed;
  settings.threads = 2;
  settings.allocationFraction = 0.5f;
  return settings;
}

bool sameBits(const std::vector<IrradianceEstimate>& a, const std::vector<IrradianceEstimate>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i].meanLux, &b[i].meanLux, sizeof(Rgb)) != 0 ||
        std::memcmp(&a[i].stdErrorLux, &b[i].stdErrorLux, sizeof(Rgb)) != 0 || a[i].samples != b[i].samples) {
      return false;
    }
  }
  return true;
}

// The quiet blocks skip passes; the points that set the p95 take every pass and end bit-identical to an
// estimate without the allocation (their samples depend only on their seed and index), so the p95 is theirs
// for fewer samples in all.
TEST(AllocationTest, QuietPointsSkipAndThePointsThatSetTheP95TakeEveryPass) {
  const FourKindsSource source;
  const EstimateSettings settings = allocated(SamplerKind::kRandom, 7);
  EstimateSettings everyPass = settings;
  everyPass.allocationFraction = 0.0f;
  const EstimateResult a = estimateProgressively(source, settings);
  const EstimateResult full = estimateProgressively(source, everyPass);
  ASSERT_EQ(a.samplesPerPoint, 1024u);
  uint64_t taken = 0;
  size_t quietSkipped = 0;
  for (size_t i = 0; i < source.pointCount(); ++i) {
    const IrradianceEstimate& e = a.points[i];
    taken += e.samples;
    if (FourKindsSource::kindOf(i) == 0) quietSkipped += e.samples < 1024 ? 1 : 0;
    if (FourKindsSource::kindOf(i) == 3) {
      ASSERT_EQ(e.samples, 1024u) << "point " << i;
      ASSERT_TRUE(std::memcmp(&e.meanLux, &full.points[i].meanLux, sizeof(Rgb)) == 0) << "point " << i;
    }
  }
  const double share = double(taken) / (1024.0 * double(source.pointCount()));
  std::cout << "[ allocate ] samples taken: " << share << " of every point every pass; p95 " << a.relativeErrorP95
            << " against " << full.relativeErrorP95 << "; quiet points that skipped: " << quietSkipped << "\n";
  EXPECT_EQ(quietSkipped, FourKindsSource::kPoints / 4);
  EXPECT_LT(share, 0.8);
  EXPECT_LE(a.relativeErrorP95, 1.02f * full.relativeErrorP95);
  EXPECT_LT(a.rays, full.rays);
}

TEST(AllocationTest, TheSameForAnyThreadCount) {
  const FourKindsSource source;
  EstimateSettings settings = allocated(SamplerKind::kRandom, 3);
  settings.threads = 1;
  const EstimateResult one = estimateProgressively(source, settings);
  for (uint32_t threads : {2u, 3u}) {
    settings.threads = threads;
    const EstimateResult r = estimateProgressively(source, settings);
    EXPECT_TRUE(sameBits(r.points, one.points)) << threads << " threads";
    EXPECT_EQ(r.rays, one.rays) << threads << " threads";
  }
}

// Every checkpoint (interval 0: between every two blocks of points and after every pass), serialised, read
// back and continued, gives the uninterrupted estimate bit for bit: the points' samples and the pass's
// points are part of the state.
TEST(AllocationTest, ContinuingFromEveryCheckpointEqualsTheUninterruptedEstimate) {
  const FourKindsSource source;  // 1024 points: 4 blocks of 256 a pass
  const EstimateSettings settings = allocated(SamplerKind::kRandom, 11);
  const EstimateResult whole = estimateProgressively(source, settings);
  std::vector<std::string> saved;
  ProgressState state;
  Checkpointing checkpointing;
  checkpointing.intervalS = 0.0;
  checkpointing.save = [&](const ProgressState& s) { saved.push_back(serializeProgressState(s)); };
  estimateProgressively(source, settings, {}, state, checkpointing);
  size_t midPassWithSkips = 0;
  for (size_t k = 0; k < saved.size(); ++k) {
    ProgressState resumed = deserializeProgressState(saved[k], "state.bin");
    if (resumed.passSamples > 0 && std::count(resumed.passTakes.begin(), resumed.passTakes.end(), 0) > 0)
      ++midPassWithSkips;
    const EstimateResult r = estimateProgressively(source, settings, {}, resumed);
    EXPECT_TRUE(sameBits(r.points, whole.points)) << "continued from checkpoint " << k;
    EXPECT_EQ(r.rays, whole.rays) << "continued from checkpoint " << k;
  }
  EXPECT_GE(midPassWithSkips, 4u);  // checkpoints inside passes that points skip were exercised
}

// A state in format 4 (before the allocation: no per-point samples, no pass flags, the last pass counted in
// points): the same state's bytes as format 5 writes them, less those.
std::string asFormat4(ProgressState s) {
  s.lastPassPointSamples = s.lastPassSamples > 0 ? s.lastPassPointSamples / s.lastPassSamples : 0;
  s.pointSamples.clear();
  s.passTakes.clear();
  std::string bytes = serializeProgressState(s);
  bytes.resize(bytes.size() - 8 - 16);  // the checksum and two empty lists
  bytes[7] = '4';
  const uint64_t h = fnv1a(bytes);
  bytes.append(reinterpret_cast<const char*>(&h), sizeof h);
  return bytes;
}

// Checkpoints of bakes made before the allocation (format 4, every point every pass) continue to the estimate
// that never stopped, from inside a pass too.
TEST(AllocationTest, AFormat4CheckpointContinuesAsItStarted) {
  const FourKindsSource source;
  EstimateSettings settings = allocated(SamplerKind::kRandom, 5);
  settings.allocationFraction = 0.0f;
  settings.maxSamples = 128;
  const EstimateResult whole = estimateProgressively(source, settings);
  std::vector<ProgressState> saved;
  ProgressState state;
  Checkpointing checkpointing;
  checkpointing.intervalS = 0.0;
  checkpointing.save = [&](const ProgressState& s) { saved.push_back(s); };
  estimateProgressively(source, settings, {}, state, checkpointing);
  size_t midPass = 0;
  for (size_t k = 0; k < saved.size(); ++k) {
    ProgressState resumed = deserializeProgressState(asFormat4(saved[k]), "state.bin");
    ASSERT_TRUE(resumed.pointSamples.empty());
    midPass += resumed.passSamples > 0 ? 1 : 0;
    const EstimateResult r = estimateProgressively(source, settings, {}, resumed);
    EXPECT_TRUE(sameBits(r.points, whole.points)) << "continued from checkpoint " << k;
  }
  EXPECT_GE(midPass, 6u);
}

// Plain Monte Carlo over 64 seeds: every kind's mean error is within 4 standard errors of 0, and its reported
// errors match its actual ones; the quiet and the rare-sample kinds end with fewer samples (they skipped).
// Were a point's decision made on its own estimate, the points of kind 2, whose error falls on either side
// of the threshold, would stop when their samples happened to hold more bright ones (a lower relative error
// with a higher mean): their mean error is then +0.11 (36 standard errors) and the test fails.
TEST(AllocationTest, PointsThatSkipStayUnbiasedAndHonest) {
  const FourKindsSource source;
  for (int kind = 0; kind < 3; ++kind) {
    double sum = 0.0, squares = 0.0, reported = 0.0;
    size_t n = 0, skipped = 0;
    for (uint64_t seed = 0; seed < 64; ++seed) {
      EstimateSettings settings = allocated(SamplerKind::kRandom, 100000 * (seed + 1));
      settings.maxSamples = 256;
      const EstimateResult r = estimateProgressively(source, settings);
      for (size_t i = 0; i < source.pointCount(); ++i) {
        if (FourKindsSource::kindOf(i) != kind) continue;
        const IrradianceEstimate& e = r.points[i];
        const double error = e.meanLux.g - 1.0;
        sum += error;
        squares += error * error;
        reported += double{e.stdErrorLux.g} * e.stdErrorLux.g;
        ++n;
        skipped += e.samples < r.samplesPerPoint ? 1 : 0;
      }
    }
    const double mean = sum / double(n);
    const double standardError = std::sqrt((squares / double(n) - mean * mean) / double(n - 1));
    const double honesty = std::sqrt(squares / reported);
    std::cout << "[ allocate ] kind " << kind << ": " << skipped << " of " << n
              << " points skipped; mean error " << mean << " (" << mean / standardError
              << " standard errors); RMS error / RMS reported error " << honesty << "\n";
    if (kind < 2) {
      EXPECT_GT(skipped, n / 4) << "kind " << kind;
    }
    EXPECT_LT(std::abs(mean), 4.0 * standardError) << "kind " << kind;
    EXPECT_GT(honesty, 0.85) << "kind " << kind;
    EXPECT_LT(honesty, 1.18) << "kind " << kind;
  }
}

}  // namespace
}  // namespace fly::raytracer
