#include "raytracer/progressive.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

namespace fly::raytracer {
namespace {

// Welford's running mean and sum of squared deviations, per channel, in double (Welford, "Note on a method
// for calculating corrected sums of squares and products", Technometrics 4(3), 1962).
struct Welford {
  dvec3 mean{0.0};
  dvec3 m2{0.0};
  uint32_t count = 0;

  void add(const Rgb& x) {
    ++count;
    const dvec3 delta = dvec3(x) - mean;
    mean += delta / static_cast<double>(count);
    m2 += delta * (dvec3(x) - mean);
  }
};

// Every point's running statistics.
class Accumulators {
 public:
  Accumulators(size_t pointCount, uint32_t replicates)
      : replicates_(replicates), welford_(pointCount), replicateSums_(pointCount * replicates, dvec3(0.0)) {}

  uint32_t replicates() const { return replicates_; }
  Welford& welford(size_t point) { return welford_[point]; }
  dvec3& replicateSum(size_t point, uint32_t r) { return replicateSums_[point * replicates_ + r]; }

  // samples: per point, all replicates together.
  IrradianceEstimate estimate(size_t point, uint32_t samples) const {
    IrradianceEstimate e;
    e.samples = samples;
    if (replicates_ == 1) {
      const Welford& w = welford_[point];
      e.meanLux = Rgb(w.mean);
      if (w.count > 1) e.stdErrorLux = Rgb(glm::sqrt(w.m2 / (static_cast<double>(w.count) * (w.count - 1))));
      return e;
    }
    // The replicates' means are independent and identically distributed; the standard error of their mean is
    // their sample standard deviation over √K.
    const double perReplicate = static_cast<double>(samples) / replicates_;
    dvec3 mean(0.0);
    for (uint32_t r = 0; r < replicates_; ++r) mean += replicateSums_[point * replicates_ + r] / perReplicate;
    mean /= static_cast<double>(replicates_);
    dvec3 squares(0.0);
    for (uint32_t r = 0; r < replicates_; ++r) {
      const dvec3 d = replicateSums_[point * replicates_ + r] / perReplicate - mean;
      squares += d * d;
    }
    e.meanLux = Rgb(mean);
    e.stdErrorLux = Rgb(glm::sqrt(squares / (static_cast<double>(replicates_) * (replicates_ - 1))));
    return e;
  }

 private:
  uint32_t replicates_;
  std::vector<Welford> welford_;      // replicates_ == 1
  std::vector<dvec3> replicateSums_;  // replicates_ ≥ 2: point-major
};

float relativeErrorP95(const std::vector<IrradianceEstimate>& estimates) {
  std::vector<float> rel;
  rel.reserve(estimates.size());
  for (const IrradianceEstimate& e : estimates) {
    const float mean = luminance(e.meanLux);
    const float err = luminance(e.stdErrorLux);
    rel.push_back(mean > 0.0f ? err / mean : (err > 0.0f ? std::numeric_limits<float>::infinity() : 0.0f));
  }
  if (rel.empty()) return 0.0f;
  const size_t k =
      std::min(rel.size() - 1, static_cast<size_t>(std::ceil(0.95 * static_cast<double>(rel.size()))) - 1);
  std::nth_element(rel.begin(), rel.begin() + static_cast<std::ptrdiff_t>(k), rel.end());
  return rel[k];
}

// Samples firstSample … firstSample + sampleCount − 1 of every point (split evenly over the replicates).
template <class S>
void runPass(const SampleSource& source, const EstimateSettings& settings, uint32_t firstSample,
             uint32_t sampleCount, Accumulators& acc, uint64_t& rays) {
  const size_t pointCount = source.pointCount();
  std::atomic<size_t> next{0};
  std::atomic<uint64_t> totalRays{0};
  const uint32_t k = acc.replicates();
  auto work = [&] {
    constexpr size_t kChunk = 16;
    uint64_t threadRays = 0;
    for (size_t begin = next.fetch_add(kChunk); begin < pointCount; begin = next.fetch_add(kChunk)) {
      for (size_t i = begin; i < std::min(begin + kChunk, pointCount); ++i) {
        if (k == 1) {
          S sampler(settings.seed + i);
          for (uint32_t s = firstSample; s < firstSample + sampleCount; ++s) {
            sampler.startSample(s);
            acc.welford(i).add(source.sample(i, sampler, threadRays));
          }
          continue;
        }
        for (uint32_t r = 0; r < k; ++r) {
          // An independent randomisation per replicate.
          S sampler(detail::mix64(settings.seed + i) + r);
          dvec3& sum = acc.replicateSum(i, r);
          for (uint32_t s = firstSample / k; s < (firstSample + sampleCount) / k; ++s) {
            sampler.startSample(s);
            sum += dvec3(source.sample(i, sampler, threadRays));
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

bool isPowerOfTwo(uint32_t x) {
  return x != 0 && (x & (x - 1)) == 0;
}

}  // namespace

EstimateResult estimateProgressively(const SampleSource& source, const EstimateSettings& settings,
                                     const PassCallback& afterPass) {
  if (!isPowerOfTwo(settings.replicates) || !isPowerOfTwo(settings.firstPassSamples) ||
      settings.firstPassSamples < settings.replicates) {
    throw std::invalid_argument("estimateProgressively: replicates (" + std::to_string(settings.replicates) +
                                ") and firstPassSamples (" + std::to_string(settings.firstPassSamples) +
                                ") must be powers of two, firstPassSamples >= replicates");
  }
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const size_t pointCount = source.pointCount();
  EstimateResult result;
  Accumulators acc(pointCount, settings.replicates);
  uint32_t total = 0;
  double lastPassS = 0.0;
  for (uint32_t passSamples = settings.firstPassSamples; total + passSamples <= settings.maxSamples;
       passSamples = total) {
    // Passes double the total; each costs about as much per sample as the last.
    if (total > 0 && elapsed() + lastPassS * passSamples / static_cast<double>(total) > settings.timeLimitS)
      break;
    const double passStart = elapsed();
    const uint64_t raysBefore = result.rays;
    if (settings.sampler == SamplerKind::kSobol) {
      runPass<SobolSampler>(source, settings, total, passSamples, acc, result.rays);
    } else {
      runPass<RandomSampler>(source, settings, total, passSamples, acc, result.rays);
    }
    total += passSamples;
    lastPassS = elapsed() - passStart;
    result.points.clear();
    for (size_t i = 0; i < pointCount; ++i) result.points.push_back(acc.estimate(i, total));
    result.relativeErrorP95 = relativeErrorP95(result.points);
    result.samplesPerPoint = total;
    result.seconds = elapsed();
    if (afterPass && !afterPass(result, result.rays - raysBefore, lastPassS)) break;
    if (settings.targetRelativeError > 0.0f && result.relativeErrorP95 <= settings.targetRelativeError) break;
  }
  if (total == 0) result.points.assign(pointCount, IrradianceEstimate{});
  result.seconds = elapsed();
  return result;
}


}  // namespace fly::raytracer
