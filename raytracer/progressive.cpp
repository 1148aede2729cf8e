#include "raytracer/progressive.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>

#include "base/error.h"
#include "base/fnv1a.h"

namespace fly::raytracer {
namespace {

// Every point's running statistics, kept in a ProgressState's sums (sumsPerPoint entries a point). Always
// Welford's running mean and sum of squared deviations over all the point's samples, per channel, in double
// (Welford, "Note on a method for calculating corrected sums of squares and products", Technometrics 4(3),
// 1962); with replicates ≥ 2, each replicate's sum after them.
size_t sumsPerPoint(uint32_t replicates) {
  return replicates == 1 ? 2 : 2 + size_t{replicates};
}

class Accumulators {
 public:
  // groups: per point its group (SampleSource::groupOf), empty when all points are one group.
  Accumulators(ProgressState& state, std::vector<uint32_t> groups, uint32_t groupCount)
      : state_(state), groups_(std::move(groups)), groupCount_(groups_.empty() ? 1 : groupCount) {}

  uint32_t replicates() const { return state_.replicates; }
  uint32_t channels() const { return state_.channels; }

  // Whether the point's group is settled (it takes no more samples), and the samples in its sums.
  bool settled(size_t point) const {
    const uint32_t g = groupOf(point);
    return g < state_.settledSamples.size() && state_.settledSamples[g] > 0;
  }
  uint32_t samplesOf(size_t point) const { return state_.pointSamples[point]; }
  // Whether the point takes the pass in progress, and its samples after it.
  bool takes(size_t point) const { return state_.passTakes[point] != 0; }
  void setSamples(size_t point, uint32_t samples) { state_.pointSamples[point] = samples; }

  // Welford's update of the point's channel with its count-th sample (count ≥ 1).
  void addWelford(size_t point, uint32_t channel, uint32_t count, const Rgb& x) {
    dvec3* sums = at(point, channel);
    const dvec3 delta = dvec3(x) - sums[0];
    sums[0] += delta / static_cast<double>(count);
    sums[1] += delta * (dvec3(x) - sums[0]);
  }
  dvec3& replicateSum(size_t point, uint32_t channel, uint32_t r) { return at(point, channel)[2 + r]; }

  // The variances of a point's mean after `samples` samples: from the spread of its samples (naive: the
  // error of independent samples) and, with replicates ≥ 2, from the spread of its replicates' means (honest
  // for scrambled nets too, with K − 1 degrees of freedom).
  struct Variances {
    dvec3 mean{0.0};
    dvec3 naive{0.0};
    dvec3 replicate{0.0};
  };
  Variances variances(size_t point, uint32_t channel, uint32_t samples) const {
    const dvec3* sums = at(point, channel);
    Variances v;
    v.mean = sums[0];
    if (samples > 1) v.naive = sums[1] / (static_cast<double>(samples) * (samples - 1));
    const uint32_t k = state_.replicates;
    if (k == 1) return v;
    const double perReplicate = static_cast<double>(samples) / k;
    dvec3 mean(0.0);
    for (uint32_t r = 0; r < k; ++r) mean += sums[2 + r] / perReplicate;
    mean /= static_cast<double>(k);
    dvec3 squares(0.0);
    for (uint32_t r = 0; r < k; ++r) {
      const dvec3 d = sums[2 + r] / perReplicate - mean;
      squares += d * d;
    }
    v.replicate = squares / (static_cast<double>(k) * (k - 1));
    return v;
  }

  // Every point's estimate from all its samples (all replicates together), of every channel.
  //
  // replicates = 1: the standard error is the naive one, honest for plain Monte Carlo only.
  //
  // replicates ≥ 2: a moderated variance (Smyth, "Linear models and empirical Bayes methods for assessing
  // differential expression in microarray experiments", Stat. Appl. Genet. Mol. Biol. 3(1), 2004, eq. 8):
  //   σ̂²_i = (d₀ η² w_i + (K − 1) v_i) / (d₀ + K − 1),
  // v_i the point's replicate variance (unbiased, K − 1 degrees of freedom, noisy for few replicates), w_i
  // its naive variance (many degrees of freedom, but scrambled nets converge faster than it says), and η² = Σ
  // v / Σ w per channel over the points of the point's group (SampleSource::groupOf: one object's vertices,
  // one light texture's texels; over all points when its group has fewer than kMinPointsToPool): how much
  // faster the nets converge than independent samples there, measured by the replicates of those points
  // together. Per group, because the sums are in lux² and so led by the brightest points: pooled over a whole
  // house, the sunlit outside's gain stood for the interior's too (RMS error / RMS reported error 0.47–1.39
  // per object; per group 0.84–1.16 for the objects of at least 64 vertices, docs/benchmarks.md). Each term
  // is an unbiased estimate of Var(mean_i) when a point's η is the common one, so the sum over points of σ̂²
  // is unbiased whatever the η_i (ΣE[η² w_i] = ΣE[v_i]). The prior weight d₀ = max(0,
  // kModeratedDegreesOfFreedom − (K − 1)) tops few replicates up to the steadiness of 8 (7 degrees of
  // freedom), and leaves 8 or more to themselves: pooling assumes that all points gain alike from the nets,
  // which holds only roughly (a point in smooth light gains more than one on a shadow edge), so it is used no
  // more than the replicates need. The sun's direct part (channel 1) has its own η², pooled alike.
  void estimates(std::vector<IrradianceEstimate>& out) const {
    out.assign(state_.pointCount, IrradianceEstimate{});
    for (uint32_t c = 0; c < state_.channels; ++c) estimatesOf(c, out);
  }

 private:
  dvec3* at(size_t point, uint32_t channel) {
    const size_t perPoint = sumsPerPoint(state_.replicates);
    return &state_.sums[(point * state_.channels + channel) * perPoint];
  }
  const dvec3* at(size_t point, uint32_t channel) const {
    const size_t perPoint = sumsPerPoint(state_.replicates);
    return &state_.sums[(point * state_.channels + channel) * perPoint];
  }

  void estimatesOf(uint32_t channel, std::vector<IrradianceEstimate>& out) const {
    const size_t count = state_.pointCount;
    const uint32_t k = state_.replicates;
    // Per group (SampleSource::groupOf), and the last entry over all points.
    const size_t groups = groupCount_;
    std::vector<dvec3> sumNaive(groups + 1, dvec3(0.0));
    std::vector<dvec3> sumReplicate(groups + 1, dvec3(0.0));
    std::vector<size_t> members(groups + 1, 0);
    if (k > 1 && k - 1 < kModeratedDegreesOfFreedom) {
      for (size_t i = 0; i < count; ++i) {
        const Variances v = variances(i, channel, samplesOf(i));
        for (size_t g : {size_t{groupOf(i)}, groups}) {
          sumNaive[g] += v.naive;
          sumReplicate[g] += v.replicate;
          ++members[g];
        }
      }
    }
    std::vector<dvec3> eta2(groups + 1, dvec3(0.0));
    for (size_t g = 0; g <= groups; ++g) {
      const size_t pool = g == groups || members[g] >= kMinPointsToPool ? g : groups;
      for (int c = 0; c < 3; ++c) {
        eta2[g][c] = sumNaive[pool][c] > 0.0 ? sumReplicate[pool][c] / sumNaive[pool][c] : 0.0;
      }
    }
    const double dof = static_cast<double>(k - 1);
    const double priorDof = std::max(0.0, kModeratedDegreesOfFreedom - dof);
    for (size_t i = 0; i < count; ++i) {
      const Variances v = variances(i, channel, samplesOf(i));
      IrradianceEstimate& e = out[i];
      e.samples = samplesOf(i);
      const dvec3 variance =
          k == 1 ? v.naive : (priorDof * eta2[groupOf(i)] * v.naive + dof * v.replicate) / (priorDof + dof);
      (channel == 0 ? e.meanLux : e.sunDirectMeanLux) = Rgb(v.mean);
      (channel == 0 ? e.stdErrorLux : e.sunDirectStdErrorLux) = Rgb(glm::sqrt(variance));
      if (channel == 1 && e.samples > 1) e.sunDirectSpreadLux = Rgb(glm::sqrt(v.naive * double(e.samples)));
    }
  }

 public:
  uint32_t groupOf(size_t point) const { return groups_.empty() ? 0 : groups_[point]; }
  uint32_t groupCount() const { return groupCount_; }
  const std::vector<uint32_t>& groups() const { return groups_; }

 private:
  ProgressState& state_;
  std::vector<uint32_t> groups_;
  uint32_t groupCount_;
};

// The relative standard error of luminance: ∞ for an error on a zero (or undefined) mean, 0 for neither.
float relativeErrorOf(const IrradianceEstimate& e, float darkFloorLux = 0.0f) {
  const float mean = std::max(luminance(e.meanLux), darkFloorLux);
  const float err = luminance(e.stdErrorLux);
  const float rel = mean > 0.0f ? err / mean : (err > 0.0f ? std::numeric_limits<float>::infinity() : 0.0f);
  return std::isnan(rel) ? std::numeric_limits<float>::infinity() : rel;
}

// The nearest-rank p-quantile of values (reordered; the largest value for p ≥ 1 − 1/n), 0 for none.
float nearestRankQuantile(std::vector<float>& values, double p) {
  if (values.empty()) return 0.0f;
  const size_t k =
      std::min(values.size() - 1, static_cast<size_t>(std::ceil(p * static_cast<double>(values.size()))) - 1);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// The irradiance below which a point's error counts relative to it rather than to its own (kDarkShare of the
// 95th percentile of the points' irradiance, hidden points left out).
float darkFloorLux(const std::vector<IrradianceEstimate>& estimates, const std::vector<uint8_t>& hidden) {
  std::vector<float> lux;
  lux.reserve(estimates.size());
  for (size_t i = 0; i < estimates.size(); ++i) {
    if (hidden.empty() || !hidden[i]) lux.push_back(luminance(estimates[i].meanLux));
  }
  return kDarkShare * nearestRankQuantile(lux, 0.95);
}

// Over the points not hidden (hidden: one flag per point, or empty for none), errors of points darker than
// darkFloorLux relative to it.
float relativeErrorP95(const std::vector<IrradianceEstimate>& estimates, const std::vector<uint8_t>& hidden,
                       float darkFloor) {
  std::vector<float> rel;
  rel.reserve(estimates.size());
  for (size_t i = 0; i < estimates.size(); ++i) {
    if (hidden.empty() || !hidden[i]) rel.push_back(relativeErrorOf(estimates[i], darkFloor));
  }
  return rel.empty() ? 0.0f : nearestRankQuantile(rel, 0.95);
}

// The samples of points [pointBegin, pointEnd) that take the pass, from the samples each has up to
// `total` (split evenly over the replicates).
template <class S>
void runPass(const SampleSource& source, const EstimateSettings& settings, size_t pointBegin, size_t pointEnd,
             uint32_t total, Accumulators& acc, uint64_t& rays) {
  std::atomic<size_t> next{pointBegin};
  std::atomic<uint64_t> totalRays{0};
  const uint32_t k = acc.replicates();
  const bool sunDirect = acc.channels() == 2;
  auto work = [&] {
    constexpr size_t kChunk = 16;
    uint64_t threadRays = 0;
    for (size_t begin = next.fetch_add(kChunk); begin < pointEnd; begin = next.fetch_add(kChunk)) {
      for (size_t i = begin; i < std::min(begin + kChunk, pointEnd); ++i) {
        if (!acc.takes(i)) continue;
        const uint32_t firstSample = acc.samplesOf(i);
        acc.setSamples(i, total);
        if (k == 1) {
          S sampler(settings.seed + i);
          for (uint32_t s = firstSample; s < total; ++s) {
            sampler.startSample(s);
            const PointSample x = source.sample(i, sampler, threadRays);
            acc.addWelford(i, 0, s + 1, x.lux);
            if (sunDirect) acc.addWelford(i, 1, s + 1, x.sunDirectLux);
          }
          continue;
        }
        // The point's samples in a fixed order (replicate by replicate), so that its running statistics are
        // the same whichever thread adds them.
        uint32_t count = firstSample;
        for (uint32_t r = 0; r < k; ++r) {
          // An independent randomisation per replicate.
          S sampler(detail::mix64(settings.seed + i) + r);
          for (uint32_t s = firstSample / k; s < total / k; ++s) {
            sampler.startSample(s);
            const PointSample x = source.sample(i, sampler, threadRays);
            acc.replicateSum(i, 0, r) += dvec3(x.lux);
            acc.addWelford(i, 0, ++count, x.lux);
            if (sunDirect) {
              acc.replicateSum(i, 1, r) += dvec3(x.sunDirectLux);
              acc.addWelford(i, 1, count, x.sunDirectLux);
            }
          }
        }
      }
    }
    totalRays += threadRays;
  };
  const uint32_t threads =
      settings.threads > 0 ? settings.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::jthread> pool;
  for (uint32_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  pool.clear();
  rays += totalRays;
}

// Settles the groups of which kSettledPercentile of the points have a relative error of luminance at most
// the target (ProgressState::settledSamples).
void settleGroups(const EstimateResult& result, const Accumulators& acc, const EstimateSettings& settings,
                  const std::vector<uint8_t>& hidden, ProgressState& state) {
  std::vector<std::vector<float>> errors(acc.groupCount());
  for (size_t i = 0; i < result.points.size(); ++i) {
    if (!acc.settled(i) && (hidden.empty() || !hidden[i]))
      errors[acc.groupOf(i)].push_back(relativeErrorOf(result.points[i], result.darkFloorLux));
  }
  state.settledSamples.resize(acc.groupCount(), 0);
  for (uint32_t g = 0; g < acc.groupCount(); ++g) {
    if (state.settledSamples[g] > 0 || errors[g].empty()) continue;
    if (nearestRankQuantile(errors[g], kSettledPercentile) <= settings.targetRelativeError) {
      state.settledSamples[g] = state.samplesPerPoint;
    }
  }
}

bool isPowerOfTwo(uint32_t x) {
  return x != 0 && (x & (x - 1)) == 0;
}

}  // namespace

std::vector<uint8_t> pointsTakingNextPass(const std::vector<IrradianceEstimate>& estimates,
                                          const std::vector<uint32_t>& groups, float relativeErrorP95,
                                          const EstimateSettings& settings) {
  const size_t count = estimates.size();
  std::vector<uint8_t> takes(count, 1);
  if (!(settings.allocationFraction > 0.0f)) return takes;
  const float threshold =
      settings.allocationFraction * std::max(relativeErrorP95, settings.targetRelativeError);
  auto groupOf = [&](size_t i) { return groups.empty() ? 0u : groups[i]; };
  // Whether a point could let its neighbours skip: enough samples, light seen, an error far below the p95.
  auto low = [&](size_t i) {
    const IrradianceEstimate& e = estimates[i];
    if (e.samples < kAllocationMinSamples || !(luminance(e.meanLux) > 0.0f)) return false;
    return relativeErrorOf(e) < threshold;
  };
  for (size_t begin = 0; begin < count;) {
    size_t end = begin + 1;
    while (end < count && end - begin < kAllocationBlockPoints && groupOf(end) == groupOf(begin)) ++end;
    size_t lowCount = 0;
    for (size_t i = begin; i < end; ++i) lowCount += low(i) ? 1 : 0;
    for (size_t i = begin; i < end; ++i) {
      // Every other point of the block low, whatever the point itself shows (its own estimate stays out of
      // its decision), and the point not behind the others' median sample count: a point that skipped while
      // the rest of its block sampled catches up before it skips again, so that no point stays passes behind
      // its block (a speckle in a light texture).
      uint32_t others[kAllocationBlockPoints];
      size_t otherCount = 0;
      for (size_t j = begin; j < end; ++j) {
        if (j != i) others[otherCount++] = estimates[j].samples;
      }
      uint32_t medianOfOthers = 0;
      if (otherCount > 0) {
        std::nth_element(others, others + (otherCount - 1) / 2, others + otherCount);
        medianOfOthers = others[(otherCount - 1) / 2];
      }
      const size_t lowOthers = lowCount - (low(i) ? 1 : 0);
      const bool skip = end - begin >= 2 && lowOthers == end - begin - 1 &&
                        estimates[i].samples >= kAllocationMinSamples && estimates[i].samples >= medianOfOthers;
      takes[i] = skip ? 0 : 1;
    }
    begin = end;
  }
  return takes;
}

std::vector<uint8_t> pointsFittingTheTimeLeft(const std::vector<IrradianceEstimate>& estimates,
                                              const std::vector<uint32_t>& groups, float relativeErrorP95,
                                              const EstimateSettings& settings,
                                              const std::function<bool(std::vector<uint8_t>&)>& fits) {
  EstimateSettings narrower = settings;
  for (float f = settings.allocationFraction * kFitFractionStep; f <= kMaxFitFraction; f *= kFitFractionStep) {
    narrower.allocationFraction = f;
    std::vector<uint8_t> takes = pointsTakingNextPass(estimates, groups, relativeErrorP95, narrower);
    if (fits(takes)) return takes;
  }
  return {};
}

uint32_t replicatesFor(const EstimateSettings& settings, size_t pointCount) {
  if (settings.replicates != 0) return settings.replicates;
  return std::min(settings.firstPassSamples, pointCount >= kMinPointsToPool ? 2u : 8u);
}

EstimateResult estimateProgressively(const SampleSource& source, const EstimateSettings& settings,
                                     const PassCallback& afterPass) {
  ProgressState state;
  return estimateProgressively(source, settings, afterPass, state);
}

EstimateResult estimateProgressively(const SampleSource& source, const EstimateSettings& settings,
                                     const PassCallback& afterPass, ProgressState& state,
                                     const Checkpointing& checkpointing) {
  if ((settings.replicates != 0 && !isPowerOfTwo(settings.replicates)) ||
      !isPowerOfTwo(settings.firstPassSamples) || settings.firstPassSamples < settings.replicates) {
    throw std::invalid_argument(
        "estimateProgressively: replicates (" + std::to_string(settings.replicates) +
        ") and firstPassSamples (" + std::to_string(settings.firstPassSamples) +
        ") must be powers of two (replicates may be 0), firstPassSamples >= replicates");
  }
  const size_t pointCount = source.pointCount();
  const uint32_t replicates = replicatesFor(settings, pointCount);
  const uint32_t channels = source.keepsSunDirect() ? 2 : 1;
  const size_t perPoint = sumsPerPoint(replicates) * channels;
  if (!state.started()) {
    state = ProgressState{};
    state.pointCount = pointCount;
    state.replicates = replicates;
    state.channels = channels;
    state.sums.assign(pointCount * perPoint, dvec3(0.0));
    state.pointSamples.assign(pointCount, 0);
  } else if (state.pointCount != pointCount || state.replicates != replicates || state.channels != channels ||
             state.sums.size() != pointCount * perPoint || state.passPointsDone > pointCount ||
             state.settledSamples.size() > source.groupCount() ||
             (!state.pointSamples.empty() && state.pointSamples.size() != pointCount) ||
             (!state.passTakes.empty() && state.passTakes.size() != pointCount)) {
    throw std::invalid_argument(
        "estimateProgressively: the state to continue has " + std::to_string(state.pointCount) + " points, " +
        std::to_string(state.replicates) + " replicates and " + std::to_string(state.channels) +
        " channels, the estimate " + std::to_string(pointCount) + ", " + std::to_string(replicates) +
        " and " + std::to_string(channels));
  }

  const auto start = std::chrono::steady_clock::now();
  const double earlierS = state.seconds;
  auto elapsed = [&] {
    return earlierS + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  std::vector<uint32_t> groups;
  if (source.groupCount() > 1) {
    groups.resize(pointCount);
    for (size_t i = 0; i < pointCount; ++i) {
      groups[i] = source.groupOf(i);
      if (groups[i] >= source.groupCount()) {
        throw std::invalid_argument("estimateProgressively: point " + std::to_string(i) + " is in group " +
                                    std::to_string(groups[i]) + " of " + std::to_string(source.groupCount()));
      }
    }
  }
  Accumulators acc(state, std::move(groups), source.groupCount());
  std::vector<uint8_t> hidden(pointCount, 0);
  bool anyHidden = false;
  for (size_t i = 0; i < pointCount; ++i) anyHidden |= (hidden[i] = source.isHidden(i) ? 1 : 0) != 0;
  if (!anyHidden) hidden.clear();
  if (state.pointSamples.empty()) {
    // A state of a format before 5: every point took every pass but its settled group's.
    state.pointSamples.resize(pointCount);
    for (size_t i = 0; i < pointCount; ++i) {
      state.pointSamples[i] = acc.settled(i) ? state.settledSamples[acc.groupOf(i)]
                              : state.passSamples > 0 && i < state.passPointsDone
                                  ? state.samplesPerPoint + state.passSamples
                                  : state.samplesPerPoint;
    }
  }
  if (state.passSamples > 0 && state.passTakes.empty()) {
    state.passTakes.resize(pointCount);
    for (size_t i = 0; i < pointCount; ++i) state.passTakes[i] = acc.settled(i) ? 0 : 1;
  }
  EstimateResult result;
  result.rays = state.rays;
  result.replicates = replicates;
  auto fillResult = [&](uint32_t total) {
    acc.estimates(result.points);
    result.darkFloorLux = darkFloorLux(result.points, hidden);
    result.relativeErrorP95 = relativeErrorP95(result.points, hidden, result.darkFloorLux);
    result.samplesPerPoint = total;
  };
  if (state.samplesPerPoint > 0) fillResult(state.samplesPerPoint);

  // With checkpoints, a pass runs in blocks of points so that a checkpoint can fall inside it.
  const bool checkpoints = checkpointing.save && std::isfinite(checkpointing.intervalS);
  const size_t block =
      checkpoints ? std::max<size_t>(256, (pointCount + 63) / 64) : std::max<size_t>(pointCount, 1);
  double lastCheckpointS = elapsed();
  auto save = [&] {
    state.seconds = elapsed();
    state.rays = result.rays;
    checkpointing.save(state);
    lastCheckpointS = elapsed();
  };

  for (;;) {
    if (state.passSamples == 0) {
      // Start the next pass: the first, or one that doubles the total. Each costs about as much per sample
      // as the last.
      const uint32_t total = state.samplesPerPoint;
      uint32_t passSamples = total == 0 ? settings.firstPassSamples : total;
      if (uint64_t{total} + passSamples > settings.maxSamples) break;
      // The points it will sample (not those of settled groups, nor those the allocation by error lets
      // skip it), and their samples against those of the last pass.
      std::vector<uint8_t> takes =
          total == 0 ? std::vector<uint8_t>(pointCount, 1)
                     : pointsTakingNextPass(result.points, acc.groups(), result.relativeErrorP95, settings);
      auto pointSamplesOf = [&](std::vector<uint8_t>& t) {
        uint64_t sum = 0;
        for (size_t i = 0; i < pointCount; ++i) {
          if (acc.settled(i) || (total > 0 && !hidden.empty() && hidden[i])) t[i] = 0;
          if (t[i]) sum += total + passSamples - state.pointSamples[i];
        }
        return sum;
      };
      uint64_t passPointSamples = pointSamplesOf(takes);
      auto predictedEndS = [&](uint64_t pointSamples) {
        return elapsed() + state.lastPassS * static_cast<double>(pointSamples) /
                               static_cast<double>(state.lastPassPointSamples);
      };
      // A pass that would end too late, narrowed to the points with the highest errors (kFitFractionStep).
      if (total > 0 && state.lastPassPointSamples > 0 && settings.allocationFraction > 0.0f &&
          passPointSamples > 0 && predictedEndS(passPointSamples) > settings.timeLimitS) {
        std::vector<uint8_t> fewer = pointsFittingTheTimeLeft(
            result.points, acc.groups(), result.relativeErrorP95, settings, [&](std::vector<uint8_t>& t) {
              const uint64_t pointSamples = pointSamplesOf(t);
              return pointSamples > 0 && predictedEndS(pointSamples) <= settings.timeLimitS;
            });
        if (!fewer.empty()) {
          takes = std::move(fewer);
          passPointSamples = pointSamplesOf(takes);
        }
      }
      // One that still would, shortened: half the samples, a quarter … (whole per replicate), the largest that
      // fits, over the points that the allocation by error lets take it. The time limit is then spent rather
      // than left when a doubling no longer fits.
      if (total > 0 && state.lastPassPointSamples > 0 && predictedEndS(passPointSamples) > settings.timeLimitS) {
        const uint32_t k = acc.replicates();
        const uint32_t doubling = passSamples;
        for (uint32_t shorter = doubling / 2; shorter >= k && shorter % k == 0; shorter /= 2) {
          passSamples = shorter;
          takes = pointsTakingNextPass(result.points, acc.groups(), result.relativeErrorP95, settings);
          passPointSamples = pointSamplesOf(takes);
          if (passPointSamples > 0 && predictedEndS(passPointSamples) <= settings.timeLimitS) break;
        }
        if (!(passPointSamples > 0) || predictedEndS(passPointSamples) > settings.timeLimitS) break;
      }
      state.lastPassPointSamples = passPointSamples;
      state.passTakes = std::move(takes);
      state.passSamples = passSamples;
      state.passPointsDone = 0;
      state.passRays = 0;
      state.passSeconds = 0.0;
    }
    const uint32_t total = state.samplesPerPoint;
    while (state.passPointsDone < pointCount) {
      const double blockStart = elapsed();
      const size_t end = std::min<size_t>(pointCount, state.passPointsDone + block);
      uint64_t blockRays = 0;
      if (settings.sampler == SamplerKind::kSobol) {
        runPass<SobolSampler>(source, settings, state.passPointsDone, end, total + state.passSamples, acc,
                              blockRays);
      } else {
        runPass<RandomSampler>(source, settings, state.passPointsDone, end, total + state.passSamples, acc,
                               blockRays);
      }
      state.passPointsDone = end;
      state.passRays += blockRays;
      result.rays += blockRays;
      state.passSeconds += elapsed() - blockStart;
      if (checkpoints && end < pointCount && elapsed() - lastCheckpointS >= checkpointing.intervalS) save();
    }
    state.samplesPerPoint = total + state.passSamples;
    state.lastPassS = state.passSeconds;
    state.lastPassSamples = state.passSamples;
    const uint64_t passRays = state.passRays;
    state.passSamples = 0;
    state.passPointsDone = 0;
    state.passRays = 0;
    state.passSeconds = 0.0;
    state.passTakes.clear();
    ++state.passes;
    fillResult(state.samplesPerPoint);
    if (settings.targetRelativeError > 0.0f && acc.groupCount() > 1)
      settleGroups(result, acc, settings, hidden, state);
    result.seconds = elapsed();
    const bool more = !afterPass || afterPass(result, passRays, state.lastPassS);
    if (checkpoints && elapsed() - lastCheckpointS >= checkpointing.intervalS) save();
    if (!more) break;
    if (settings.targetRelativeError > 0.0f && result.relativeErrorP95 <= settings.targetRelativeError) break;
  }
  if (state.samplesPerPoint == 0) result.points.assign(pointCount, IrradianceEstimate{});
  result.seconds = elapsed();
  state.seconds = result.seconds;
  state.rays = result.rays;
  if (checkpointing.save) checkpointing.save(state);
  return result;
}

namespace {

// Version 5 adds every point's samples and the points of the pass in progress (allocation by error), and
// counts the last pass in samples rather than points; version 4 added the channel count (the sun's direct
// part); version 3 the settled groups and the last pass's point count. Versions 2 to 4 are still read, 2 and
// 3 as one channel.
constexpr char kStateTag[8] = {'F', 'L', 'Y', 'P', 'R', 'O', 'G', '5'};
constexpr char kStateTagV4[8] = {'F', 'L', 'Y', 'P', 'R', 'O', 'G', '4'};
constexpr char kStateTagV3[8] = {'F', 'L', 'Y', 'P', 'R', 'O', 'G', '3'};
constexpr char kStateTagV2[8] = {'F', 'L', 'Y', 'P', 'R', 'O', 'G', '2'};

template <class T>
void put(std::string& out, const T& value) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

}  // namespace

std::string serializeProgressState(const ProgressState& s) {
  static_assert(std::endian::native == std::endian::little, "checkpoints are written little-endian");
  std::string out(kStateTag, sizeof kStateTag);
  put(out, s.pointCount);
  put(out, s.replicates);
  put(out, s.channels);
  put(out, s.samplesPerPoint);
  put(out, s.passSamples);
  put(out, s.passPointsDone);
  put(out, s.passes);
  put(out, s.rays);
  put(out, s.passRays);
  put(out, s.seconds);
  put(out, s.passSeconds);
  put(out, s.lastPassS);
  put(out, s.lastPassSamples);
  put(out, static_cast<uint64_t>(s.sums.size()));
  for (const dvec3& v : s.sums) {
    put(out, v.x);
    put(out, v.y);
    put(out, v.z);
  }
  put(out, static_cast<uint64_t>(s.settledSamples.size()));
  for (uint32_t v : s.settledSamples) put(out, v);
  put(out, s.lastPassPointSamples);
  put(out, static_cast<uint64_t>(s.pointSamples.size()));
  for (uint32_t v : s.pointSamples) put(out, v);
  put(out, static_cast<uint64_t>(s.passTakes.size()));
  out.append(reinterpret_cast<const char*>(s.passTakes.data()), s.passTakes.size());
  put(out, fnv1a(out));
  return out;
}

ProgressState deserializeProgressState(const std::string& bytes, const std::string& fileName) {
  auto bad = [&](const std::string& what) {
    return InputError(SourceLocation{fileName}, "not a usable checkpoint: " + what,
                      "the checkpoint is damaged or from another version of fly; start the bake afresh");
  };
  auto tagged = [&](const char(&tag)[8]) {
    return bytes.size() >= sizeof tag && bytes.compare(0, sizeof tag, tag, sizeof tag) == 0;
  };
  const bool version2 = tagged(kStateTagV2);
  const bool version3 = tagged(kStateTagV3);
  const bool version4 = tagged(kStateTagV4);
  if (bytes.size() < sizeof kStateTag + 8 || (!version2 && !version3 && !version4 && !tagged(kStateTag)))
    throw bad("it does not start with the fly progress-state tag");
  uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  if (fnv1a(bytes.data(), bytes.size() - 8) != stored)
    throw bad("its checksum does not match (truncated or corrupt)");
  size_t at = sizeof kStateTag;
  auto get = [&](auto& value) {
    if (at + sizeof value > bytes.size() - 8) throw bad("it ends early");
    std::memcpy(&value, bytes.data() + at, sizeof value);
    at += sizeof value;
  };
  ProgressState s;
  get(s.pointCount);
  get(s.replicates);
  if (!version2 && !version3) get(s.channels);
  get(s.samplesPerPoint);
  get(s.passSamples);
  get(s.passPointsDone);
  get(s.passes);
  get(s.rays);
  get(s.passRays);
  get(s.seconds);
  get(s.passSeconds);
  get(s.lastPassS);
  get(s.lastPassSamples);
  uint64_t count = 0;
  get(count);
  if (s.replicates == 0 || s.replicates > (1u << 20) || (s.channels != 1 && s.channels != 2))
    throw bad("its sizes do not agree");
  const size_t perPoint = sumsPerPoint(s.replicates) * s.channels;
  if (count != s.pointCount * perPoint || count > (bytes.size() - at) / 24)
    throw bad("its sizes do not agree");
  s.sums.resize(count);
  for (dvec3& v : s.sums) {
    get(v.x);
    get(v.y);
    get(v.z);
  }
  if (!version2) {
    uint64_t groups = 0;
    get(groups);
    if (groups > (bytes.size() - at) / 4) throw bad("its sizes do not agree");
    s.settledSamples.resize(groups);
    for (uint32_t& v : s.settledSamples) get(v);
    if (version3 || version4) {
      uint64_t lastPassPoints = 0;
      get(lastPassPoints);
      s.lastPassPointSamples = lastPassPoints * s.lastPassSamples;
    } else {
      get(s.lastPassPointSamples);
      uint64_t points = 0;
      get(points);
      if (points != 0 && points != s.pointCount) throw bad("its sizes do not agree");
      s.pointSamples.resize(points);
      for (uint32_t& v : s.pointSamples) {
        get(v);
        if (uint64_t{v} > uint64_t{s.samplesPerPoint} + s.passSamples) throw bad("a point's samples exceed its passes'");
      }
      get(points);
      if (points != 0 && points != s.pointCount) throw bad("its sizes do not agree");
      s.passTakes.resize(points);
      for (uint8_t& v : s.passTakes) {
        get(v);
        if (v > 1) throw bad("a point's pass flag is not 0 or 1");
      }
    }
  }
  if (at != bytes.size() - 8) throw bad("it has trailing bytes");
  return s;
}

}  // namespace fly::raytracer
