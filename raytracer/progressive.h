// The progressive driver of every Monte-Carlo estimate (`fly illuminance`'s sensors, the baker's vertex sides
// and texels): passes that double the samples of every point (of those that still need them: settled groups,
// allocation by error), a mean and a standard error per point after each, and the stopping rules (samples,
// time, target error). Independent of what a sample computes (SampleSource).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "raytracer/sampler.h"

namespace fly::raytracer {

// One point's estimate: the mean of its samples and the standard error of that mean, per channel; for
// sources that keep the sun's direct light apart (SampleSource::keepsSunDirect), the same of that part.
struct IrradianceEstimate {
  Rgb meanLux{0.0f};
  Rgb stdErrorLux{0.0f};
  uint32_t samples = 0;
  // The part of meanLux that arrived straight from the sun's disc at the point, estimated from the same
  // samples (so meanLux − sunDirectMeanLux is the estimate of the rest), and its standard error; 0 for
  // sources that do not keep it apart.
  Rgb sunDirectMeanLux{0.0f};
  Rgb sunDirectStdErrorLux{0.0f};
  // The standard deviation of the sun-direct samples themselves (not of their mean): how much the sun's direct
  // light varies over the point's footprint (a vertex's one-ring, a texel), where it is not uniform (a shadow
  // edge or sun patch crosses it): what a value read at one spot of the footprint may differ from its mean.
  Rgb sunDirectSpreadLux{0.0f};
};

// One sample of a point: its irradiance (lux) and the part of it that came straight from the sun's disc
// (raytracer/integrator.h, sampleIrradiance's sunDirectLux), 0 where the source does not keep it apart. A
// plain Rgb converts to a sample without a sun-direct part.
struct PointSample {
  Rgb lux{0.0f};
  Rgb sunDirectLux{0.0f};
  PointSample(const Rgb& irradianceLux = Rgb(0.0f), const Rgb& sunDirect = Rgb(0.0f))  // NOLINT: implicit
      : lux(irradianceLux), sunDirectLux(sunDirect) {}
};

enum class SamplerKind { kSobol, kRandom };

// EstimateSettings::replicates = 0 takes 2 replicates for at least this many points, else 8: pooling the
// nets' gain needs many points, and with few (a handful of sensors) each point's error must stand on its own
// replicates.
inline constexpr size_t kMinPointsToPool = 64;

// With a target error, a group of points (SampleSource::groupOf) of which 99 % of the points (all, for groups
// of fewer than 100) have a relative standard error of luminance at most the target after a pass is settled:
// it takes no more samples, so that later passes spend their time where the error is (a bake's sunlit ground
// is settled long before the rooms it lights). Its points count towards the 95th percentile of the stopping
// rule as they are. Decided per group, from all its points, not per point: stopping points one by one on
// their own noisy error estimates would stop those whose error happens to be underestimated (on shadow edges
// such per-point stopping reported errors 2.4× too small).
inline constexpr double kSettledPercentile = 0.99;

// Sample allocation by error (EstimateSettings::allocationFraction > 0): after a pass, a point skips the next
// pass when it has at least kAllocationMinSamples samples and every other point of its block
// (kAllocationBlockPoints consecutive points of one group: neighbouring vertices of an object, neighbouring
// texels of a row) has at least as many, a mean above 0 and a relative standard error of luminance below
// allocationFraction × max(p95, target) (p95: the 95th percentile over all points after that pass). A
// skipped point takes a later pass again once the p95 has fallen far enough; it then catches up to that
// pass's total (its samples stay a prefix of its sequence, a power of two × firstPassSamples). The time goes
// to the points whose error sets the p95 (a bake's shaded interior), not to those far below it (the sunlit
// outside): the error ends more even for the same time.
// The decision for a point looks at its neighbours' estimates, never at its own: a point's samples depend
// only on (seed, point, replicate, sample index) and are independent of other points' samples, so the
// number of samples it takes is independent of their values, and its mean stays an unbiased average with an
// honest standard error (up to the p95's dependence on the point, one rank among all points). Stopping a
// point on its own estimate would stop it preferentially where its samples happen to hold more of its rare
// bright ones (a sun patch found by chance): a higher mean with a lower relative error, kept — a bias of up
// to half its standard error per decision (36 standard errors over the points of a test,
// tests/raytracer/allocation_test.cpp), and errors reported too small (settled groups, kSettledPercentile,
// say why they are decided per group). The
// minimum samples keep blocks whose rare bright samples have not yet shown up from looking converged; a
// neighbour whose mean is 0 (no light seen yet) keeps the block sampling, its relative error undefined. The
// decision is made between passes from the estimates, so it is the same for any thread count, and a
// checkpoint keeps every point's samples and the points of the pass in progress.
inline constexpr uint32_t kAllocationMinSamples = 64;
inline constexpr size_t kAllocationBlockPoints = 16;

// With fewer than 8 replicates, a point's variance is moderated with the variance pooled over all points up
// to this many degrees of freedom, those of 8 replicates (EstimateSettings::replicates).
inline constexpr double kModeratedDegreesOfFreedom = 7.0;

struct EstimateSettings {
  uint32_t firstPassSamples =
      16;                      // per point, a power of two ≥ replicates; every later pass doubles the total
  uint32_t maxSamples = 1024;  // per point; no pass starts that would exceed it
  double timeLimitS =
      std::numeric_limits<double>::infinity();  // no pass starts that is predicted to end later
  // Stop when the 95th percentile over points of (standard error / mean) of luminance is at most this; 0 =
  // off.
  float targetRelativeError = 0.0f;
  uint32_t threads = 0;  // 0 = std::thread::hardware_concurrency()
  SamplerKind sampler = SamplerKind::kSobol;
  // How the standard error is estimated, a power of two. 1: from the per-sample variance (Welford), honest
  // for plain Monte Carlo only — scrambled Sobol' points converge faster than their variance says, and it
  // overstates their error 2.5–5× (the ReportedStandardErrorIsHonest test). K ≥ 2: the samples are split into
  // K independently randomised sequences (randomised quasi-Monte Carlo replicates: L'Ecuyer & Lemieux,
  // "Recent advances in randomized quasi-Monte Carlo methods", 2002), whose spread measures the error
  // honestly for either sampler, at the cost of K shorter nets; the variance of a point's mean is moderated
  // with the naive one scaled by the nets' gain measured over all points (progressive.cpp,
  // Accumulators::estimates) up to kModeratedDegreesOfFreedom. 0 (the default): automatic,
  // automaticReplicates() — 2 when there are enough points to pool over (at 64 samples QMC's error is then
  // 17 % lower than with 8 replicates: docs/benchmarks.md), else 8.
  uint32_t replicates = 0;
  uint64_t seed = 0;  // point i's samplers are seeded from seed + i
  // Sample allocation by error (kAllocationMinSamples, docs/sample-allocation.md): a point whose block
  // neighbours all have a relative error below this fraction of max(p95, targetRelativeError) skips the next
  // pass; 0 = off (every point takes every pass), else in (0, 1]. `fly bake` uses kBakeAllocationFraction.
  float allocationFraction = 0.0f;
};

// What the stopping rule and the settled groups count as dark: a point whose irradiance is below this share
// of the 95th percentile of all points' irradiance (hidden ones left out) has its standard error taken
// relative to that level instead of its own (a relative and an absolute tolerance, as numerical integrators
// combine them). 10⁻⁴ is 13 stops: in a picture exposed for the bright surfaces it is black, and its relative
// error, however large, is invisible; a lamp's unlit underside at 10⁻⁵ lx beside 30 lx surfaces would
// otherwise hold a bake back for ever. Reported errors are unchanged.
inline constexpr float kDarkShare = 1e-4f;

// The allocation fraction of `fly bake` (EstimateSettings::allocationFraction), measured on the house
// (docs/benchmarks.md, "Sample allocation by error").
inline constexpr float kBakeAllocationFraction = 0.7f;

// A last pass fitted to the time left: with the allocation on, when the next pass is predicted to end after
// EstimateSettings::timeLimitS, the fraction is raised by factors of kFitFractionStep, up to
// kMaxFitFraction, until the points that still take the pass (those in blocks with a high error, by the same
// neighbours' rule) are predicted to finish in time. Without such a fraction (and without the allocation),
// the pass is shortened instead: half the samples of a doubling, a quarter … (whole per replicate), the
// largest predicted to fit, over the points that the allocation lets take it; the estimate ends when not
// even a replicate's share fits. Passes double the samples, so a bake given a time limit would otherwise
// stop up to half its time early, with its slowest points where they were. The fraction stays at most 1: blocks whose errors lie just
// below the p95 keep taking the pass, so that the p95 itself still falls (with fractions up to 16 only the
// worst blocks took it, and on the house the p95 stalled: docs/benchmarks.md).
inline constexpr float kFitFractionStep = 1.1f;
inline constexpr float kMaxFitFraction = 1.0f;

// The allocation's rule (EstimateSettings::allocationFraction, kAllocationMinSamples): per point, whether it
// takes the next pass (1) or skips it (0), given every point's estimate after the last pass, its group
// (SampleSource::groupOf; empty: one group) and the p95 of their relative errors. Settled groups are the
// caller's to leave out. All points take it when settings.allocationFraction is 0.
std::vector<uint8_t> pointsTakingNextPass(const std::vector<IrradianceEstimate>& estimates,
                                          const std::vector<uint32_t>& groups, float relativeErrorP95,
                                          const EstimateSettings& settings);

// The points of a pass narrowed to the time left (kFitFractionStep): pointsTakingNextPass with the fraction
// raised step by step from settings.allocationFraction until fits(takes) holds (fits may also drop points,
// those of settled groups); empty when none up to kMaxFitFraction does.
std::vector<uint8_t> pointsFittingTheTimeLeft(const std::vector<IrradianceEstimate>& estimates,
                                              const std::vector<uint32_t>& groups, float relativeErrorP95,
                                              const EstimateSettings& settings,
                                              const std::function<bool(std::vector<uint8_t>&)>& fits);

// The replicates an estimate of pointCount points takes with these settings (settings.replicates unless 0),
// at most settings.firstPassSamples.
uint32_t replicatesFor(const EstimateSettings& settings, size_t pointCount);

struct EstimateResult {
  std::vector<IrradianceEstimate> points;
  uint32_t replicates = 0;  // as replicatesFor()
  uint32_t samplesPerPoint = 0;
  float relativeErrorP95 = 0.0f;  // of luminance, after the last pass (dark points against darkFloorLux)
  float darkFloorLux = 0.0f;      // kDarkShare of the 95th percentile of the points' irradiance
  uint64_t rays = 0;
  double seconds = 0.0;
};

// The points the progressive driver estimates: estimateIrradiance's sensors, the baker's vertex sides. Sample
// index s of point i is sample(i, sampler) after sampler.startSample(s); `rays` grows by the rays traced.
// Both overloads must compute the same function of the sampler's numbers.
class SampleSource {
 public:
  virtual ~SampleSource() = default;
  virtual size_t pointCount() const = 0;
  // Points that light alike (one object's vertices, one light texture's texels) form a group: the moderated
  // error (progressive.cpp) pools the replicates' gain over a group's points when it has at least
  // kMinPointsToPool, else over all points. Groups are numbered 0 … groupCount() − 1.
  virtual uint32_t groupCount() const { return 1; }
  virtual uint32_t groupOf(size_t /*point*/) const { return 0; }
  // Whether the samples carry the sun's direct part (PointSample::sunDirectLux): the driver then keeps its
  // statistics too (IrradianceEstimate::sunDirectMeanLux). The stopping rules and settled groups look at
  // the irradiance alone.
  virtual bool keepsSunDirect() const { return false; }
  // Points that no view reaches (raytracer/enclosure.h): they take the first pass only and stay out of the
  // 95th percentile and of the settled groups' rule, so that light nobody sees holds no estimate back. Their
  // estimates keep their (large) honest errors.
  virtual bool isHidden(size_t /*point*/) const { return false; }
  virtual PointSample sample(size_t point, SobolSampler& sampler, uint64_t& rays) const = 0;
  virtual PointSample sample(size_t point, RandomSampler& sampler, uint64_t& rays) const = 0;
};

// A SampleSource whose two overloads are one template: Derived provides
// `template <class S> PointSample sampleAt(size_t point, S& sampler, uint64_t& rays) const` (or returning
// Rgb; public, or with this class as a friend), so both samplers compute the same function by construction.
template <class Derived>
class SampleSourceOf : public SampleSource {
 public:
  PointSample sample(size_t point, SobolSampler& sampler, uint64_t& rays) const final {
    return static_cast<const Derived&>(*this).sampleAt(point, sampler, rays);
  }
  PointSample sample(size_t point, RandomSampler& sampler, uint64_t& rays) const final {
    return static_cast<const Derived&>(*this).sampleAt(point, sampler, rays);
  }
};

// Called after every pass (from the calling thread) with the estimates so far (seconds: since the start) and
// the pass's rays and seconds; return false to stop after it.
using PassCallback = std::function<bool(const EstimateResult& soFar, uint64_t passRays, double passSeconds)>;

// Progressive passes over all of source's points in parallel, as described for estimateIrradiance below.
// std::invalid_argument for replicates or firstPassSamples that are not powers of two, or fewer first-pass
// samples than replicates.
EstimateResult estimateProgressively(const SampleSource& source, const EstimateSettings& settings,
                                     const PassCallback& afterPass = {});

// Everything the driver needs to continue an estimate where it stopped (a checkpoint): every point's running
// sums and samples, bit for bit, and where in its passes it was. A pass may stop between blocks of points:
// the points of [0, passPointsDone) that take it (passTakes) then have samplesPerPoint + passSamples samples,
// the others what they had. Because a point's samples depend only on (seed, point, replicate, sample index),
// its sums are added in sample order and which points take a pass is decided from the state alone, an
// estimate continued from a state ends bit-identical to one that never stopped.
struct ProgressState {
  uint64_t pointCount = 0;
  uint32_t replicates = 0;
  // Quantities per point: 1 (the irradiance), or 2 (also its sun-direct part: SampleSource::keepsSunDirect).
  uint32_t channels = 1;
  uint32_t samplesPerPoint = 0;  // after the last complete pass, of the points that took it (the most any has)
  uint32_t passSamples = 0;      // samples per point of the pass in progress; 0 = none
  uint64_t passPointsDone = 0;   // points of the pass in progress that are done
  uint32_t passes = 0;           // complete passes
  uint64_t rays = 0;             // all rays so far
  uint64_t passRays = 0;         // rays of the pass in progress so far
  double seconds = 0.0;          // run time so far, summed over every process that worked on it
  double passSeconds = 0.0;      // run time of the pass in progress so far
  double lastPassS = 0.0;        // duration of the last complete pass (predicts the next one's)
  uint32_t lastPassSamples = 0;  // samples per point of the last complete pass
  // Per point (point-major) and per channel (channel-major within the point): Welford's mean and sum of
  // squared deviations over all its samples, then with replicates ≥ 2 each replicate's sum of its samples
  // (channels × (2 + replicates) entries a point).
  std::vector<dvec3> sums;
  // Per group (SampleSource::groupOf): the samples per point at which it was settled
  // (kSettledFractionOfTarget), 0 while it is not; empty when none is.
  std::vector<uint32_t> settledSamples;
  // Samples the last complete pass took, over all points (predicts the next one's time).
  uint64_t lastPassPointSamples = 0;
  // Per point: the samples in its sums. Empty in states of format versions before 5, whose points all had
  // samplesPerPoint (with the pass in progress, up to passPointsDone) or their settled group's samples.
  std::vector<uint32_t> pointSamples;
  // Per point: 1 when it takes the pass in progress, 0 when it skips it (settled group, allocation by
  // error); empty when no pass is in progress, and in states before format version 5 (whose passes every
  // point not settled took).
  std::vector<uint8_t> passTakes;

  bool started() const { return samplesPerPoint > 0 || passPointsDone > 0; }
};

// A state as bytes (little-endian, with a format tag and an FNV-1a checksum at the end), and back. Format 5
// (with every point's samples and the pass in progress's points); format 4 (without them) is read with the
// samples its passes gave; formats 2 and 3, written before the sun's direct part was kept apart, are read as
// one channel. deserializeProgressState throws InputError naming `fileName` when the bytes are truncated,
// corrupt or of another format version.
std::string serializeProgressState(const ProgressState& state);
ProgressState deserializeProgressState(const std::string& bytes, const std::string& fileName);

// Checkpointing for estimateProgressively: `save` is called from the calling thread with the complete state
// at most every intervalS seconds (between blocks of points, so that long passes are cut too) and after the
// last pass. With intervalS = ∞ and no save, passes run unbroken.
struct Checkpointing {
  double intervalS = std::numeric_limits<double>::infinity();
  std::function<void(const ProgressState&)> save;
};

// As above, continuing from `state` when state.started() (std::invalid_argument when its point count,
// replicates or channels do not match), and leaving in it the state at the end. The result's seconds and rays
// include those of earlier runs.
EstimateResult estimateProgressively(const SampleSource& source, const EstimateSettings& settings,
                                     const PassCallback& afterPass, ProgressState& state,
                                     const Checkpointing& checkpointing = {});

}  // namespace fly::raytracer
