// The vertex light-map baker: for every vertex of the TraceRdb, the irradiance (lux, RGB) integrated over its
// neighbourhood, for two-sided meshes on both sides, in progressive passes with a standard error per vertex
// and a convergence history (error against run time) — what `fly bake` runs.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "raytracer/light_paths.h"
#include "raytracer/texel_baker.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// Light paths from the sun (raytracer/light_paths.h) combined with the gathering estimator per vertex side
// (docs/light-paths.md). The sun's reflected light at a vertex side is estimated twice, independently: by the
// gathering samples (Integrator::sampleIrradiance's sunLux less its sunDirectLux) and by the light paths. The
// bake reports E = G − w S_G + w S_L: G the gathering estimate of everything, S_G its estimate of the sun's
// reflected light, S_L the light paths'. For any w fixed before either is drawn, E[S_G] = E[S_L] makes E
// unbiased. w minimises the variance, Var(G − w S_G) + w² Var(S_L), for the planned sample counts:
// w = Cov(G, S_G) / (Var(S_G) + n Var(S_L)) per sample (n gathering samples), clamped to [0, 1], with the
// variances of an independent pilot (its own seeds); w = 0 where the pilot's light paths reached the vertex
// side too rarely to measure their variance. Weights from the samples of the bake itself would
// correlate with them and bias the estimate.
struct LightPathBakeSettings {
  bool enabled = false;
  LightPathSettings paths{1u << 18, 8, 0, 0};  // the light paths of the bake (seed and threads: the bake's)
  uint32_t pilotSamples = 32;                  // per vertex side, gathering
  uint32_t pilotPathsPerBatch = 1u << 15;      // light paths, in 8 batches
  uint32_t plannedSamples = 0;                 // n above; 0: EstimateSettings::maxSamples
};

struct BakeSettings {
  EstimateSettings estimate;      // passes, stopping rules (samples, time, target error), sampler, threads
  IntegratorSettings integrator;  // bounces
  LightPathBakeSettings lightPaths;
};

// One row of convergence.csv: the state after a pass.
struct ConvergencePoint {
  double seconds = 0.0;  // since the bake started
  uint32_t samples = 0;  // per vertex (and side)
  float relativeErrorP95 =
      0.0f;  // 95th percentile over vertex sides and texels of the relative standard error of luminance
  double raysPerSecond = 0.0;  // over the pass
  // With a sun (VertexLightMaps::hasSunDirect): the 95th percentile of the relative standard error of
  // luminance of the sun-direct part, over the vertex sides and texels that receive it; 0 otherwise.
  float sunDirectRelativeErrorP95 = 0.0f;
  // Seconds spent before the passes on training (lit patches, light paths): not in `seconds`, but taken out
  // of EstimateSettings::timeLimitS, which bounds training and passes together.
  double trainingSeconds = 0.0;
};

// Called after every pass (from the calling thread); return false to stop after it.
using BakeProgress = std::function<bool(const ConvergencePoint& latest, uint32_t maxSamples)>;

struct VertexLightMaps {
  // Per TraceRdb vertex (rdb.positionsM.size() entries): irradiance on the front (the side of the vertex
  // normal) and its standard error, lux per channel.
  std::vector<Rgb> frontLux;
  std::vector<Rgb> frontStdErrorLux;
  // The same for the back (the side of −normal) of vertices of two-sided meshes; 0 for one-sided ones.
  std::vector<Rgb> backLux;
  std::vector<Rgb> backStdErrorLux;
  // With a sun that lights the scene (Integrator::hasSun), the part of frontLux / backLux that arrived
  // straight from the sun's disc (Integrator::sampleIrradiance's sunDirectLux), from the same samples, and
  // its standard error, per vertex as above; all four empty without one. E − E_sunDirect is what sunlight
  // mode keeps baked while it draws the sun's direct term in real time.
  std::vector<Rgb> frontSunDirectLux;
  std::vector<Rgb> frontSunDirectStdErrorLux;
  std::vector<Rgb> backSunDirectLux;
  std::vector<Rgb> backSunDirectStdErrorLux;
  // With them, the spread of the sun's direct light over each vertex's one-ring (IrradianceEstimate::
  // sunDirectSpreadLux): what a value read between the vertices may differ from theirs (cli/baked_scene.h
  // folds it into the errors a bake's reader sees).
  std::vector<Rgb> frontSunDirectSpreadLux;
  std::vector<Rgb> backSunDirectSpreadLux;
  bool hasSunDirect() const { return !frontSunDirectLux.empty(); }
  // Samples per point of the points still sampled at the end (the most any point took); groups settled
  // earlier (kSettledPercentile) took fewer: frontSamples per vertex and LightTexture::samples tell.
  uint32_t samplesPerVertex = 0;
  std::vector<uint32_t> frontSamples;  // per TraceRdb vertex: the samples of its front (0: no one-ring)
  uint32_t replicates = 0;  // of the error estimate (EstimateSettings::replicates; replicatesFor())
  std::vector<ConvergencePoint> history;
  uint64_t rays = 0;
  double seconds = 0.0;
  // Per TraceMesh: its vertex sides inside closed objects (raytracer/enclosure.h), sampled in the first pass
  // only and left out of the error (their values keep their errors).
  std::vector<size_t> hiddenVertexSides;
  // Vertices whose every sample was invalid (no triangle of non-zero area around them), filled from the
  // neighbours along the mesh's edges or, with none, set to 0 and counted here.
  size_t unfilledVertices = 0;
  // One per TraceRdb::lightTextures entry, baked in the same passes (raytracer/texel_baker.h).
  std::vector<LightTexture> lightTextures;
  // With light paths (LightPathBakeSettings::enabled and a sun): the paths traced, pilot included, their rays
  // and seconds (pilots included; `seconds` above is the gathering passes' alone).
  uint64_t lightPaths = 0;
  uint64_t lightPathRays = 0;
  double lightPathSeconds = 0.0;
  // With next-event estimation to lit patches (Integrator::usesLitPatches): its regions, and the seconds
  // its training took (before the passes, not in `seconds`).
  size_t litPatchCells = 0;
  double litPatchSeconds = 0.0;
  // The vertex sides whose estimate combines the light paths' (weight > 0), and their mean weight.
  size_t lightPathCombinedSides = 0;
  double lightPathMeanWeight = 0.0;
};

// A bake's checkpoint: the driver's state and the convergence history so far (raytracer/progressive.h).
struct BakeCheckpoint {
  ProgressState progress;
  std::vector<ConvergencePoint> history;
};

// Checkpointing a bake. `state`: when it holds a started checkpoint, the bake continues from it (and ends
// bit-identical to a bake that never stopped); during and after the bake it holds the current state. `save`
// is called with it at most every intervalS seconds and after the last pass.
struct BakeCheckpointing {
  BakeCheckpoint* state = nullptr;
  double intervalS = std::numeric_limits<double>::infinity();
  std::function<void(const BakeCheckpoint&)> save;
};

// Bakes every vertex of rdb. A vertex's value is the irradiance averaged over its one-ring with the weight of
// its linear "hat" basis function (the area-weighted neighbourhood that interpolated vertex colours
// represent): each sample picks a triangle of the one-ring by area, a point in it by the hat weight, and the
// interpolated shading normal there. The texels of the rdb's light textures are points of the same
// progressive run (after the vertex sides, so that one history and one target error cover both;
// samplesPerVertex is also the samples per texel). Deterministic for any thread count.
VertexLightMaps bakeVertexLightMaps(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                    const BakeSettings& settings, const BakeProgress& progress = {},
                                    const BakeCheckpointing& checkpointing = {});

}  // namespace fly::raytracer
