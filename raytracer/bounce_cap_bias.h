// The light that a cap on the number of bounces (IntegratorSettings::maxBounces) leaves out, estimated so that
// a capped estimate never hides its bias behind a small standard error.
//
// Paths end by Russian roulette, so the default is unbiased; a user's cap ends them early and removes every
// path of more reflections. In a closed room of albedo ρ that is the fraction ρ^(K+1) of the indirect light
// (a white room, ρ = 0.9, loses 39 % at K = 8), which the standard error — the spread of the capped
// estimator around its own mean — cannot show. The estimate: at a pilot set of points, each sample traces the
// same path twice from one copy of the sampler's state, once with the cap and once without; until the cap the
// two paths are the same (same numbers, same Russian roulette), so their difference is exactly the light the
// capped path would have gathered beyond it, an unbiased estimate of the missing irradiance with a small
// variance (common random numbers). Its relative size, Σ missing / Σ uncapped over the pilot points, is what
// fly reports.
#pragma once

#include <cstdint>
#include <span>

#include "base/math.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// Pilot points and samples per point of the estimate: a second or two on a room of albedo 0.9.
inline constexpr uint32_t kBounceCapPilotPoints = 256;
inline constexpr uint32_t kBounceCapPilotSamples = 64;

struct BounceCapBias {
  uint32_t maxBounces = 0;  // the cap estimated
  uint32_t points = 0;      // pilot points used
  uint32_t samplesPerPoint = 0;
  // Σ (E_uncapped − E_capped) / Σ E_uncapped of luminance over the pilot points, and its standard error; 0
  // and 0 when the pilot points receive no light.
  double missingRel = 0.0;
  double missingRelStdError = 0.0;
  // The largest over the pilot points of each point's own E_missing / E_uncapped: a scene's sunlit outside
  // can hide a dark interior's loss in the sum. Each point's ratio comes from kBounceCapPilotSamples samples
  // and has its own error (which can only raise the largest), so this indicates the worst loss rather than
  // bounding it. (A share over the points ranked darkest by the same estimates would be biased low: a path
  // that finds much light beyond the cap raises both numbers of its point.)
  double missingRelMax = 0.0;
  double seconds = 0.0;
};

// Estimates the bias of `capped` (whose maxBounces is the cap) at up to kBounceCapPilotPoints of the given
// points, evenly spread over their order. points, normals (and surfaceMagnitudesM when not empty) have equal
// sizes, as for estimateIrradiance; std::invalid_argument otherwise. threads: 0 = all cores. Deterministic for
// a seed.
BounceCapBias estimateBounceCapBias(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                    const IntegratorSettings& capped, std::span<const vec3> points,
                                    std::span<const vec3> normals, std::span<const float> surfaceMagnitudesM = {},
                                    uint32_t threads = 0, uint64_t seed = 0);

// The same at the centroids of the scene's triangles (front side, geometric normal), for bakes: a pilot over
// the surfaces the bake lights.
BounceCapBias estimateBounceCapBiasOnSurfaces(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                              const IntegratorSettings& capped, uint32_t threads = 0,
                                              uint64_t seed = 0);

}  // namespace fly::raytracer
