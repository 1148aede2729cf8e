// The stopping rules and integrator options that `fly bake` and `fly illuminance` share: --target-error,
// --time, --samples, --sampler, --max-bounces, --threads, each defaulting to the scene's bake settings.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

#include "raytracer/integrator.h"
#include "sdb/bake_settings.h"

namespace fly::cli {

struct SamplingOptions {
  std::string targetError;             // "1%" or 0.01; "" = the scene's bake.targetError
  std::string time;                    // seconds, "90s", "5m", "1.5h"; "" = the scene's bake.time
  std::optional<uint32_t> samples;     // a power of two; none = the scene's bake.samples, else 65536
  std::string sampler = "sobol";       // sobol or random
  uint32_t threads = 0;                // 0 = all cores
  std::optional<uint32_t> maxBounces;  // none = the scene's bake.maxBounces, else unbounded
  uint64_t seed = 0;                   // scrambling / random-number seed (EstimateSettings::seed)
  bool caustics = false;               // IntegratorSettings::caustics
  bool noSkyPortals = false;           // IntegratorSettings::skyPortals = false
  bool noLitPatches = false;           // IntegratorSettings::litPatches = false
};

// Adds the options to `sub`; `per` names what a sample count counts ("sensor", "vertex").
void addSamplingOptions(CLI::App& sub, SamplingOptions& o, const std::string& per);

// "1%" → 0.01, "0.02" → 0.02; UsageError unless in (0, 1).
double parseRelativeError(const std::string& s);

// "90", "90s", "5m", "1.5h" → seconds; UsageError naming `option` unless finite and > 0.
double parseDuration(const std::string& s, const std::string& option = "--time");

// The estimator's settings: the flags, else the scene's bake settings; at most 2^16 samples per point. An
// explicit --samples without --target-error turns the error target off, so that exactly that many are taken.
// UsageError for a malformed flag (sampler, samples not a power of two, target error, time).
raytracer::EstimateSettings estimateSettings(const SamplingOptions& o, const sdb::BakeSettings& bake);

// The integrator's settings: --max-bounces, else the scene's bake.maxBounces, else unbounded
// (kPathLengthGuard). UsageError above kPathLengthGuard.
raytracer::IntegratorSettings integratorSettings(const SamplingOptions& o, const sdb::BakeSettings& bake);

}  // namespace fly::cli
