#include "cli/bake_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "base/error.h"

namespace fly::cli {

void addSamplingOptions(CLI::App& sub, SamplingOptions& o, const std::string& per) {
  sub.add_option(
      "--target-error", o.targetError,
      "stop when the 95th percentile of the relative standard error reaches this, e.g. 1% (default: "
      "the scene's bake.targetError, 1%)");
  sub.add_option("--time", o.time,
                 "stop after this run time, e.g. 60s or 5m (default: the scene's bake.time)");
  sub.add_option(
      "--samples", o.samples,
      "samples per " + per + ", a power of two (default: the scene's bake.samples, else up to 65536)");
  sub.add_option("--sampler", o.sampler,
                 "sobol (Owen-scrambled, quasi-Monte Carlo) or random (plain Monte Carlo)")
      ->capture_default_str();
  sub.add_option("--max-bounces", o.maxBounces,
                 "cap on the interreflections of a path (default: the scene's bake.maxBounces, else none: "
                 "paths end by Russian roulette, the unbiased answer); a cap removes light, which fly "
                 "estimates and reports");
  sub.add_option("--threads", o.threads, "worker threads (default 0: all cores)")->capture_default_str();
  sub.add_option("--seed", o.seed,
                 "seed of the sample scrambling; runs with different seeds are independent estimates, "
                 "whose differences check the reported errors")
      ->capture_default_str();
  sub.add_flag("--caustics", o.caustics,
               "also the sun seen in mirrors and window panes (caustics); off by default: paths find the "
               "sun's image so rarely that it makes fireflies and errors that cannot be estimated");
  sub.add_flag("--no-sky-portals", o.noSkyPortals,
               "sample the sky from its table alone; by default a scene with clear glass also sends half of "
               "the sky's light samples through the glass, which lowers the error of interiors lit through "
               "windows");
  sub.add_flag("--no-lit-patches", o.noLitPatches,
               "path sampling alone; by default, in a scene with a sun, points in enclosed regions also "
               "sample the surfaces that the sun and sky light directly (next-event estimation to lit "
               "patches, docs/lit-patches.md), which lowers the error of sunlit interiors");
}

double parseRelativeError(const std::string& s) {
  std::string v = s;
  double scale = 1.0;
  if (!v.empty() && v.back() == '%') {
    v.pop_back();
    scale = 0.01;
  }
  double x = 0.0;
  const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
  if (ec != std::errc() || ptr != v.data() + v.size() || !(x * scale > 0.0 && x * scale < 1.0)) {
    throw UsageError("--target-error " + s + ": expected a relative error in (0, 1) such as 0.01 or 1%");
  }
  return x * scale;
}

double parseDuration(const std::string& s, const std::string& option) {
  std::string v = s;
  double unit = 1.0;
  if (!v.empty() && (v.back() == 's' || v.back() == 'm' || v.back() == 'h')) {
    unit = v.back() == 'h' ? 3600.0 : v.back() == 'm' ? 60.0 : 1.0;
    v.pop_back();
  }
  double x = 0.0;
  const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
  if (ec != std::errc() || ptr != v.data() + v.size() || !(x > 0.0) || !std::isfinite(x)) {
    throw UsageError(option + " " + s + ": expected a duration such as 60, 90s, 5m or 1.5h");
  }
  return x * unit;
}

raytracer::EstimateSettings estimateSettings(const SamplingOptions& o, const sdb::BakeSettings& bake) {
  if (o.sampler != "sobol" && o.sampler != "random") throw UsageError("--sampler: expected sobol or random");
  if (o.samples && (*o.samples == 0 || (*o.samples & (*o.samples - 1)) != 0)) {
    throw UsageError("--samples " + std::to_string(*o.samples) + ": expected a power of two (e.g. 256)");
  }
  raytracer::EstimateSettings settings;
  settings.maxSamples = o.samples ? *o.samples : bake.samples > 0 ? bake.samples : 65536u;
  settings.firstPassSamples = std::min(settings.maxSamples, 16u);
  settings.replicates = std::min(settings.firstPassSamples, settings.replicates);
  settings.targetRelativeError = float(!o.targetError.empty() ? parseRelativeError(o.targetError)
                                       : o.samples            ? 0.0
                                                              : bake.targetErrorRel);
  const double timeLimit = !o.time.empty() ? parseDuration(o.time) : bake.timeLimitS;
  if (timeLimit > 0.0) settings.timeLimitS = timeLimit;
  settings.threads = o.threads;
  settings.seed = o.seed;
  settings.sampler = o.sampler == "random" ? raytracer::SamplerKind::kRandom : raytracer::SamplerKind::kSobol;
  return settings;
}

raytracer::IntegratorSettings integratorSettings(const SamplingOptions& o, const sdb::BakeSettings& bake) {
  raytracer::IntegratorSettings settings;
  settings.maxBounces = o.maxBounces ? *o.maxBounces : bake.maxBounces.value_or(raytracer::kPathLengthGuard);
  if (settings.maxBounces > raytracer::kPathLengthGuard) {
    throw UsageError("--max-bounces " + std::to_string(settings.maxBounces) + ": at most " +
                     std::to_string(raytracer::kPathLengthGuard) + "; leave it out for unbounded paths");
  }
  settings.caustics = o.caustics;
  settings.skyPortals = !o.noSkyPortals;
  settings.litPatches = !o.noLitPatches;
  return settings;
}

}  // namespace fly::cli
