// Checkpoints of the progressive driver and the baker: an estimate continued from any saved state ends
// bit-identical to one that never stopped (an uninterrupted bake with the same total samples), and a damaged checkpoint is refused with a message naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/fnv1a.h"
#include "raytracer/baker.h"
#include "raytracer/embree_scene.h"
#include "raytracer/progressive.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::raytracer {
namespace {

// A point's samples: a smooth function of the sampler's first 2D pair and the point index, different per
// channel, so that every sum and every replicate differs.
class SmoothSource final : public SampleSourceOf<SmoothSource> {
  friend SampleSourceOf<SmoothSource>;

 public:
  explicit SmoothSource(size_t points) : points_(points) {}
  size_t pointCount() const override { return points_; }

 private:
  template <class S>
  Rgb sampleAt(size_t point, S& sampler, uint64_t& rays) const {
    sampler.startGroup(0);
    const vec2 u = sampler.next2D();
    ++rays;
    const float k = 1.0f + 0.01f * static_cast<float>(point % 97);
    return Rgb(std::exp(k * u.x) * std::sin(kPiF * u.y), u.x * u.y + 0.1f, k * u.x);
  }

  size_t points_;
};

// Two groups of points that gain unequally from scrambled nets, each with the exact integral 1: group 0
// bright (1000×) and smooth in the first pair (nets gain a lot), group 1 dim and a product over 16
// dimensions in 4 groups (nets gain little). Group 0's samples carry a sun-direct part (the first term), so
// that settled groups are exercised with two quantities a point.
class TwoGroupSource final : public SampleSourceOf<TwoGroupSource> {
  friend SampleSourceOf<TwoGroupSource>;

 public:
  static constexpr size_t kPerGroup = 256;
  size_t pointCount() const override { return 2 * kPerGroup; }
  uint32_t groupCount() const override { return 2; }
  uint32_t groupOf(size_t point) const override { return point < kPerGroup ? 0 : 1; }
  static float exact(size_t point) { return point < kPerGroup ? 1000.0f : 1.0f; }
  bool keepsSunDirect() const override { return true; }

 private:
  template <class S>
  PointSample sampleAt(size_t point, S& sampler, uint64_t& /*rays*/) const {
    sampler.startGroup(0);
    if (point < kPerGroup) {
      const vec2 u = sampler.next2D();
      return {Rgb(1000.0f * (u.x + u.y)), Rgb(1000.0f * u.x)};  // ∫∫ (x + y) = 1
    }
    float f = 1.0f;
    for (int d = 0; d < 16; ++d) f *= 0.5f + sampler.next1D();  // ∫ (1/2 + x) = 1 per dimension
    return Rgb(f);
  }
};

// An estimate of source from 64 samples up to maxSamples (2 replicates), with seed 1000 · seed and the target
// error (0: none).
EstimateResult seededEstimate(const SampleSource& source, uint64_t seed, uint32_t maxSamples, float target) {
  EstimateSettings settings;
  settings.firstPassSamples = 64;
  settings.maxSamples = maxSamples;
  settings.replicates = 2;
  settings.targetRelativeError = target;
  settings.seed = 1000 * seed;
  return estimateProgressively(source, settings);
}

// The moderated error pools the nets' gain per group: each group's reported errors match its measured
// errors, while one gain pooled over both (in lux², led by the bright group) would understate the dim
// group's error several times.
TEST(ModeratedErrorTest, PoolsTheGainPerGroup) {
  const TwoGroupSource source;
  double squared[2] = {0.0, 0.0};
  double reported[2] = {0.0, 0.0};
  for (uint64_t seed = 0; seed < 8; ++seed) {
    const EstimateResult r = seededEstimate(source, seed, 64, 0.0f);
    for (size_t i = 0; i < source.pointCount(); ++i) {
      const double error = r.points[i].meanLux.g - TwoGroupSource::exact(i);
      squared[source.groupOf(i)] += error * error;
      reported[source.groupOf(i)] += double{r.points[i].stdErrorLux.g} * r.points[i].stdErrorLux.g;
    }
  }
  for (int g = 0; g < 2; ++g) {
    const double ratio = std::sqrt(squared[g] / reported[g]);
    std::cout << "[ pooling  ] group " << g << ": RMS error / RMS reported error = " << ratio << "\n";
    EXPECT_GT(ratio, 0.75) << "group " << g;
    EXPECT_LT(ratio, 1.33) << "group " << g;
  }
}

float relativeError(const IrradianceEstimate& e) {
  return luminance(e.stdErrorLux) / luminance(e.meanLux);
}

// With a target error, the bright smooth group, whose every point is far below the target after the first
// pass, is settled there: it takes no more samples, while the dim 16-dimensional group goes on until
// the 95th percentile reaches the target. The settled group's reported errors stay honest: over 8 seeds its
// measured error matches them, although it stopped on them.
TEST(SettledGroupsTest, AGroupFarBelowTheTargetStopsAndStaysHonest) {
  const TwoGroupSource source;
  double squared = 0.0;
  double reported = 0.0;
  constexpr float kTarget = 0.05f;
  for (uint64_t seed = 0; seed < 8; ++seed) {
    const EstimateResult r = seededEstimate(source, seed, 4096, kTarget);
    EXPECT_LE(r.relativeErrorP95, kTarget);
    EXPECT_GT(r.samplesPerPoint, 64u);
    for (size_t i = 0; i < source.pointCount(); ++i) {
      const IrradianceEstimate& e = r.points[i];
      if (source.groupOf(i) == 0) {
        ASSERT_EQ(e.samples, 64u) << "point " << i;
        EXPECT_LE(relativeError(e), kTarget);
        const double error = e.meanLux.g - TwoGroupSource::exact(i);
        squared += error * error;
        reported += double{e.stdErrorLux.g} * e.stdErrorLux.g;
      } else {
        ASSERT_EQ(e.samples, r.samplesPerPoint) << "point " << i;
      }
    }
  }
  const double ratio = std::sqrt(squared / reported);
  std::cout << "[ settled  ] RMS error / RMS reported error of the settled group = " << ratio << "\n";
  EXPECT_GT(ratio, 0.75);
  EXPECT_LT(ratio, 1.33);
}

// Without a target nothing is settled: every point takes every sample.
TEST(SettledGroupsTest, NothingSettlesWithoutATarget) {
  const TwoGroupSource source;
  EstimateSettings settings;
  settings.firstPassSamples = 64;
  settings.maxSamples = 256;
  const EstimateResult r = estimateProgressively(source, settings);
  for (const IrradianceEstimate& e : r.points) ASSERT_EQ(e.samples, 256u);
}

bool sameBits(const std::vector<IrradianceEstimate>& a, const std::vector<IrradianceEstimate>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i].meanLux, &b[i].meanLux, sizeof(Rgb)) != 0 ||
        std::memcmp(&a[i].stdErrorLux, &b[i].stdErrorLux, sizeof(Rgb)) != 0 ||
        std::memcmp(&a[i].sunDirectMeanLux, &b[i].sunDirectMeanLux, sizeof(Rgb)) != 0 ||
        std::memcmp(&a[i].sunDirectStdErrorLux, &b[i].sunDirectStdErrorLux, sizeof(Rgb)) != 0 ||
        a[i].samples != b[i].samples) {
      return false;
    }
  }
  return true;
}

struct Case {
  SamplerKind sampler;
  uint32_t replicates;
};

class ResumeTest : public ::testing::TestWithParam<Case> {};

// Every checkpoint of an estimate (interval 0: one between every two blocks of points and after every pass),
// serialised, read back and continued, gives the uninterrupted estimate bit for bit, with 1 and 2 threads.
TEST_P(ResumeTest, ContinuingFromEveryCheckpointEqualsTheUninterruptedEstimate) {
  const SmoothSource source(1000);  // 4 blocks of 256 points per pass
  EstimateSettings settings;
  settings.firstPassSamples = 16;
  settings.maxSamples = 128;
  settings.sampler = GetParam().sampler;
  settings.replicates = GetParam().replicates;
  settings.threads = 2;
  const EstimateResult whole = estimateProgressively(source, settings);
  ASSERT_EQ(whole.samplesPerPoint, 128u);

  std::vector<std::string> saved;
  ProgressState state;
  Checkpointing checkpointing;
  checkpointing.intervalS = 0.0;
  checkpointing.save = [&](const ProgressState& s) { saved.push_back(serializeProgressState(s)); };
  const EstimateResult checkpointed = estimateProgressively(source, settings, {}, state, checkpointing);
  EXPECT_TRUE(sameBits(checkpointed.points, whole.points));
  // Passes of 16, 16, 32, 64 samples: 3 block boundaries each, and one after each pass (the last twice).
  ASSERT_GE(saved.size(), 16u);

  uint32_t midPass = 0;
  for (size_t k = 0; k < saved.size(); ++k) {
    ProgressState resumed = deserializeProgressState(saved[k], "state.bin");
    if (resumed.passSamples > 0) ++midPass;
    settings.threads = 1 + static_cast<uint32_t>(k % 2);
    const EstimateResult r = estimateProgressively(source, settings, {}, resumed);
    EXPECT_TRUE(sameBits(r.points, whole.points)) << "continued from checkpoint " << k;
    EXPECT_EQ(r.rays, whole.rays) << "continued from checkpoint " << k;
  }
  EXPECT_GE(midPass, 12u);  // the checkpoints inside passes were exercised
}

INSTANTIATE_TEST_SUITE_P(Samplers, ResumeTest,
                         ::testing::Values(Case{SamplerKind::kSobol, 8}, Case{SamplerKind::kSobol, 1},
                                           Case{SamplerKind::kRandom, 4}),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           return std::string(param.param.sampler == SamplerKind::kSobol ? "Sobol"
                                                                                         : "Random") +
                                  std::to_string(param.param.replicates) + "Replicates";
                         });

// An estimate with settled groups, continued from every checkpoint, equals the uninterrupted one: the settled
// groups are part of the state.
TEST(SettledGroupsTest, ContinuingFromEveryCheckpointEqualsTheUninterruptedEstimate) {
  const TwoGroupSource source;
  EstimateSettings settings;
  settings.firstPassSamples = 16;
  settings.maxSamples = 512;
  settings.targetRelativeError = 0.05f;
  settings.threads = 2;
  const EstimateResult whole = estimateProgressively(source, settings);
  ASSERT_EQ(whole.points.front().samples, 16u);  // group 0 settled after the first pass
  ASSERT_GT(whole.points.back().samples, 16u);
  EXPECT_NEAR(whole.points.front().sunDirectMeanLux.g, 500.0f,
              5.0f * whole.points.front().sunDirectStdErrorLux.g);
  std::vector<std::string> saved;
  ProgressState state;
  Checkpointing checkpointing;
  checkpointing.intervalS = 0.0;
  checkpointing.save = [&](const ProgressState& s) { saved.push_back(serializeProgressState(s)); };
  estimateProgressively(source, settings, {}, state, checkpointing);
  ASSERT_GE(saved.size(), 4u);
  for (size_t k = 0; k < saved.size(); ++k) {
    ProgressState resumed = deserializeProgressState(saved[k], "state.bin");
    const EstimateResult r = estimateProgressively(source, settings, {}, resumed);
    EXPECT_TRUE(sameBits(r.points, whole.points)) << "continued from checkpoint " << k;
    EXPECT_EQ(r.rays, whole.rays) << "continued from checkpoint " << k;
  }
}

// The bytes of a one-channel state without point samples or a pass in progress in an older format version:
// 4 (neither the points' samples nor the pass's flags, two empty lists of 8 bytes each before the FNV-1a
// checksum, and the last pass counted in points where format 5 counts samples), 3 (also no channel count: the
// 4 bytes after the point count and replicates) or 2 (also neither the settled-group count and list, 8 bytes
// for an empty one, nor the last pass's point count, 8 bytes).
std::string olderFormat(const ProgressState& s, char version) {
  std::string bytes = serializeProgressState(s);
  if (version != '4') bytes.erase(8 + 8 + 4, 4);
  bytes.resize(bytes.size() - (version == '2' ? 40 : 24));
  bytes[7] = version;
  const uint64_t h = fnv1a(bytes);
  bytes.append(reinterpret_cast<const char*>(&h), sizeof h);
  return bytes;
}

// States of format versions 2 (before settled groups), 3 (before the sun's direct part) and 4 (before every
// point's samples) still read, 2 and 3 as one channel; the last pass's points become its samples.
TEST(ProgressStateTest, ReadsVersion2To4States) {
  ProgressState s;
  s.pointCount = 2;
  s.replicates = 1;
  s.samplesPerPoint = 16;
  s.passes = 1;
  s.lastPassSamples = 16;
  s.sums.assign(4, dvec3(1.0, 2.0, 3.0));
  s.lastPassPointSamples = 2;  // written where formats 3 and 4 keep the last pass's point count
  const ProgressState v2 = deserializeProgressState(olderFormat(s, '2'), "old.bin");
  EXPECT_EQ(v2.samplesPerPoint, 16u);
  EXPECT_EQ(v2.sums.size(), 4u);
  EXPECT_EQ(v2.channels, 1u);
  EXPECT_TRUE(v2.settledSamples.empty());
  EXPECT_EQ(v2.lastPassPointSamples, 0u);
  EXPECT_TRUE(v2.pointSamples.empty());
  for (const char version : {'3', '4'}) {
    const ProgressState old = deserializeProgressState(olderFormat(s, version), "old.bin");
    EXPECT_EQ(old.channels, 1u);
    EXPECT_EQ(old.sums.size(), 4u);
    EXPECT_EQ(old.lastPassPointSamples, 32u) << version;
    EXPECT_TRUE(old.pointSamples.empty());
    EXPECT_TRUE(old.passTakes.empty());
  }
}

// A source that keeps a second quantity (the sun's direct part): its own smooth function of the same sample.
class SunSource final : public SampleSourceOf<SunSource> {
  friend SampleSourceOf<SunSource>;

 public:
  size_t pointCount() const override { return 100; }
  bool keepsSunDirect() const override { return true; }

 private:
  template <class S>
  PointSample sampleAt(size_t point, S& sampler, uint64_t& /*rays*/) const {
    sampler.startGroup(0);
    const vec2 u = sampler.next2D();
    const float sun = 2.0f * float(point) * u.x * u.x * 1.5f;  // ∫ = point
    return {Rgb(sun + u.y), Rgb(sun)};                         // ∫ = point + 1/2
  }
};

// The sun-direct channel: its mean and honest standard error from the same samples, kept in the state (format
// 4, round trip), and a one-channel state (an older checkpoint) refused by a source that keeps it.
TEST(ProgressStateTest, TheSunDirectChannelIsEstimatedKeptAndChecked) {
  EstimateSettings settings;
  settings.maxSamples = 1024;
  settings.replicates = 8;
  ProgressState state;
  const EstimateResult r = estimateProgressively(SunSource(), settings, {}, state);
  EXPECT_EQ(state.channels, 2u);
  for (size_t i = 1; i < r.points.size(); ++i) {
    const IrradianceEstimate& e = r.points[i];
    EXPECT_NEAR(e.sunDirectMeanLux.g, float(i), 5.0f * e.sunDirectStdErrorLux.g + 1e-4f) << i;
    EXPECT_NEAR(e.meanLux.g, float(i) + 0.5f, 5.0f * e.stdErrorLux.g + 1e-4f) << i;
    EXPECT_GT(e.sunDirectStdErrorLux.g, 0.0f);
    EXPECT_LT(e.sunDirectStdErrorLux.g, 0.01f * float(i));
  }
  const std::string bytes = serializeProgressState(state);
  const ProgressState back = deserializeProgressState(bytes, "state.bin");
  EXPECT_EQ(back.channels, 2u);
  EXPECT_EQ(serializeProgressState(back), bytes);

  ProgressState oneChannel;
  estimateProgressively(SmoothSource(100), settings, {}, oneChannel);
  EXPECT_THROW(estimateProgressively(SunSource(), settings, {}, oneChannel), std::invalid_argument);
}

TEST(ProgressStateTest, RoundTripsAndRefusesDamage) {
  const SmoothSource source(300);
  EstimateSettings settings;
  settings.maxSamples = 32;
  ProgressState state;
  estimateProgressively(source, settings, {}, state);
  const std::string bytes = serializeProgressState(state);
  const ProgressState back = deserializeProgressState(bytes, "state.bin");
  EXPECT_EQ(back.samplesPerPoint, 32u);
  EXPECT_EQ(back.sums.size(), state.sums.size());
  EXPECT_EQ(std::memcmp(back.sums.data(), state.sums.data(), state.sums.size() * sizeof(dvec3)), 0);
  EXPECT_EQ(serializeProgressState(back), bytes);

  auto refused = [](const std::string& damaged) {
    try {
      deserializeProgressState(damaged, "out/bake.checkpoint/state.bin");
    } catch (const InputError& e) {
      return e.location().file == "out/bake.checkpoint/state.bin";
    }
    return false;
  };
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x10);
  EXPECT_TRUE(refused(flipped));
  EXPECT_TRUE(refused(bytes.substr(0, bytes.size() - 1)));
  EXPECT_TRUE(refused(bytes.substr(0, 10)));
  EXPECT_TRUE(refused(""));
  EXPECT_TRUE(refused("FLYPROG1" + bytes.substr(8)));  // the format before Welford sums with replicates
}

// Automatic replicates: 2 where the nets' gain can be pooled over many points, 8 for a handful (each point's
// error then stands on its own replicates), never more than the first pass's samples.
TEST(ProgressStateTest, AutomaticReplicatesFollowThePointCount) {
  EstimateSettings settings;
  settings.maxSamples = 16;
  EXPECT_EQ(settings.replicates, 0u);
  EXPECT_EQ(estimateProgressively(SmoothSource(kMinPointsToPool), settings).replicates, 2u);
  EXPECT_EQ(estimateProgressively(SmoothSource(kMinPointsToPool - 1), settings).replicates, 8u);
  settings.firstPassSamples = 4;
  EXPECT_EQ(replicatesFor(settings, 4), 4u);
  settings.replicates = 16;
  EXPECT_EQ(replicatesFor(settings, 1000), 16u);
}

TEST(ProgressStateTest, AStateOfAnotherEstimateIsRefused) {
  EstimateSettings settings;
  settings.maxSamples = 16;
  ProgressState state;
  estimateProgressively(SmoothSource(100), settings, {}, state);
  EXPECT_THROW(estimateProgressively(SmoothSource(101), settings, {}, state), std::invalid_argument);
  settings.replicates = 4;
  EXPECT_THROW(estimateProgressively(SmoothSource(100), settings, {}, state), std::invalid_argument);
}

// The baker through a process "killed" after its third checkpoint (save throws), continued from the last
// saved checkpoint: the same light maps and the same convergence history (samples per pass) as a bake that
// ran through.
TEST(BakeCheckpointTest, ABakeStoppedAndContinuedEqualsOneThatRanThrough) {
  for (const bool lightPaths : {false, true}) {
    SCOPED_TRACE(lightPaths ? "light paths" : "gathering");
    rdb::TraceRdbBuilder b;
    const uint32_t grey = b.material(Rgb(0.5f));
    b.ground(5.0f, 24, grey);
    b.grid(vec3(-1, 0, -1), vec3(0, 2, 0), vec3(0, 0, 2), 4, grey, true);  // a two-sided wall
    b.uniformSky(Rgb(1000.0f));
    b.pointLight(vec3(2, 3, 1), Rgb(5000.0f));
    b.sun(vec3(0.4f, 0.7f, -0.5f), Rgb(60000.0f));  // its direct part is kept apart and resumed alike
    const EmbreeScene scene(b.rdb);
    BakeSettings settings;
    settings.estimate.maxSamples = 64;
    settings.estimate.threads = 2;
    // With light paths from the sun too: their pilot and paths are traced again alike on resuming.
    settings.lightPaths.enabled = lightPaths;
    settings.lightPaths.paths.pathsPerBatch = 4096;
    settings.lightPaths.pilotPathsPerBatch = 1024;
    const VertexLightMaps whole = bakeVertexLightMaps(b.rdb, scene, settings);

    struct Killed {};
    BakeCheckpoint state;
    std::vector<std::string> saved;
    std::vector<size_t> historyAtSave;
    BakeCheckpointing checkpointing;
    checkpointing.state = &state;
    checkpointing.intervalS = 0.0;
    checkpointing.save = [&](const BakeCheckpoint& s) {
      saved.push_back(serializeProgressState(s.progress));
      historyAtSave.push_back(s.history.size());
      if (saved.size() == 3) throw Killed{};
    };
    EXPECT_THROW(bakeVertexLightMaps(b.rdb, scene, settings, {}, checkpointing), Killed);
    ASSERT_EQ(saved.size(), 3u);

    BakeCheckpoint resumed;
    resumed.progress = deserializeProgressState(saved.back(), "state.bin");
    resumed.history = std::vector<ConvergencePoint>(
        state.history.begin(), state.history.begin() + static_cast<long>(historyAtSave.back()));
    checkpointing.state = &resumed;
    checkpointing.save = {};
    const VertexLightMaps continued = bakeVertexLightMaps(b.rdb, scene, settings, {}, checkpointing);
    ASSERT_EQ(continued.frontLux.size(), whole.frontLux.size());
    EXPECT_EQ(
        std::memcmp(continued.frontLux.data(), whole.frontLux.data(), whole.frontLux.size() * sizeof(Rgb)),
        0);
    EXPECT_EQ(std::memcmp(continued.backLux.data(), whole.backLux.data(), whole.backLux.size() * sizeof(Rgb)),
              0);
    EXPECT_EQ(std::memcmp(continued.frontStdErrorLux.data(), whole.frontStdErrorLux.data(),
                          whole.frontStdErrorLux.size() * sizeof(Rgb)),
              0);
    ASSERT_TRUE(whole.hasSunDirect());
    for (auto part : {&VertexLightMaps::frontSunDirectLux, &VertexLightMaps::frontSunDirectStdErrorLux,
                      &VertexLightMaps::backSunDirectLux, &VertexLightMaps::backSunDirectStdErrorLux}) {
      ASSERT_EQ((continued.*part).size(), (whole.*part).size());
      EXPECT_EQ(
          std::memcmp((continued.*part).data(), (whole.*part).data(), (whole.*part).size() * sizeof(Rgb)), 0);
    }
    EXPECT_EQ(continued.samplesPerVertex, whole.samplesPerVertex);
    EXPECT_EQ(continued.rays, whole.rays);
    ASSERT_EQ(continued.history.size(), whole.history.size());
    for (size_t i = 0; i < whole.history.size(); ++i) {
      EXPECT_EQ(continued.history[i].samples, whole.history[i].samples);
      EXPECT_EQ(continued.history[i].relativeErrorP95, whole.history[i].relativeErrorP95);
      EXPECT_EQ(continued.history[i].sunDirectRelativeErrorP95, whole.history[i].sunDirectRelativeErrorP95);
    }
  }
}

}  // namespace
}  // namespace fly::raytracer
