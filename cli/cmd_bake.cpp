// `fly bake SCENE --out DIR`: bakes the scene's vertex light maps and writes the baked scene directory
// (cli/baked_scene.h), showing the progress and the estimated time left after every pass.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>

#include "base/error.h"
#include "cli/bake_checkpoint.h"
#include "cli/bake_options.h"
#include "cli/bounce_cap_warning.h"
#include "cli/baked_scene.h"
#include "cli/command.h"
#include "cli/image_metadata.h"
#include "cli/scene_daylight.h"
#include "raytracer/baker.h"
#include "raytracer/embree_scene.h"
#include "raytracer/light_resolution.h"
#include "rdb/trace_rdb_build.h"

namespace fly::cli {

namespace {

struct BakeOptions {
  std::string scene;
  std::string out;
  SamplingOptions sampling;
  bool exportGltf = false;
  std::string checkpoint;  // a duration; "" = no checkpoints
  std::string resume;      // DIR of an interrupted bake with a checkpoint; "" = a new bake
  std::string lightPaths = "off";  // on or off: raytracer::LightPathBakeSettings::enabled
  bool noErrorAllocation = false;  // EstimateSettings::allocationFraction = 0
  bool noAutomaticLightTextures = false;  // BakeJob::automaticLightTextures = false
  DaylightOptions daylight;
  double dotsPerInch = 0.0;  // --dpi: convergence.png's print resolution; 0 = none
};

// The job from the command line, or for --resume from the checkpoint (with --threads, --checkpoint and --dpi
// allowed to change: none changes the result).
BakeJob resolveJob(const BakeOptions& o, const CLI::App& sub, std::optional<LoadedCheckpoint>& loaded) {
  if (o.resume.empty()) {
    if (o.scene.empty() || o.out.empty()) {
      throw UsageError("bake: give SCENE and --out DIR (or --resume DIR to continue an interrupted bake)");
    }
    if (o.lightPaths != "on" && o.lightPaths != "off") {
      throw UsageError("--light-paths " + o.lightPaths + ": expected on or off");
    }
    BakeJob job;
    job.scenePath = o.scene;
    job.outDir = o.out;
    job.samplerName = o.sampling.sampler;
    job.exportGltf = o.exportGltf;
    job.automaticLightTextures = !o.noAutomaticLightTextures;
    if (!o.checkpoint.empty()) job.checkpointIntervalS = parseDuration(o.checkpoint, "--checkpoint");
    return job;
  }
  for (const char* name : {"SCENE", "--out", "--target-error", "--time", "--samples", "--sampler",
                           "--max-bounces", "--export-gltf", "--light-paths", "--no-lit-patches",
                           "--no-error-allocation", "--no-automatic-light-textures"}) {
    if (sub.count(name) > 0) {
      throw UsageError(
          std::string("bake --resume DIR continues with the settings saved in the checkpoint; ") + name +
          " cannot change them (only --threads, --checkpoint and --dpi can be given)");
    }
  }
  if (const std::vector<std::string> given = o.daylight.given(); !given.empty()) {
    throw UsageError("bake --resume DIR continues under the daylight saved in the checkpoint; " + given.front() +
                     " cannot change it");
  }
  loaded = loadBakeCheckpoint(o.resume);
  BakeJob job = loaded->job;
  if (sub.count("--threads") > 0) job.settings.estimate.threads = o.sampling.threads;
  if (!o.checkpoint.empty()) job.checkpointIntervalS = parseDuration(o.checkpoint, "--checkpoint");
  return job;
}

// Seconds until the passes stop, from whichever rule stops them first: the sample limit (time grows with the
// samples), the passes' time limit (the driver shortens the last pass to end at it), or the target error (the
// error falls as 1/√samples, so reaching it takes (error / target)² times as long as it took so far). Infinite
// when no rule bounds it.
double secondsLeft(const raytracer::ConvergencePoint& p, const raytracer::EstimateSettings& s) {
  double left = p.seconds * (double(s.maxSamples) / double(p.samples) - 1.0);
  if (std::isfinite(s.timeLimitS)) left = std::min(left, s.timeLimitS - p.seconds);
  if (s.targetRelativeError > 0.0f) {
    const double ratio = double(p.relativeErrorP95) / double(s.targetRelativeError);
    left = std::min(left, p.seconds * std::max(ratio * ratio - 1.0, 0.0));
  }
  return std::max(left, 0.0);
}

std::string formatSeconds(double s) {
  char buf[32];
  if (s < 10.0) {
    std::snprintf(buf, sizeof buf, "%.1f s", s);
  } else if (s < 90.0) {
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  } else if (s < 5400.0) {
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60.0);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600.0);
  }
  return buf;
}

// One progress line per pass: a bar of the time done against the time estimated in all, the samples, the
// error against the target and the time left, as wall-clock time of the command: beforeS (start-up, training)
// before the passes, afterS (writing the results) after them. On a terminal it redraws one line; in a log,
// one line each.
void printProgress(const raytracer::ConvergencePoint& p, const raytracer::EstimateSettings& s, double beforeS,
                   double afterS, bool terminal) {
  constexpr int kBar = 24;
  const double left = secondsLeft(p, s) + afterS;
  const double now = beforeS + p.seconds;
  const double done = now + left > 0.0 ? now / (now + left) : 1.0;
  const int filled = static_cast<int>(std::lround(done * kBar));
  const std::string bar = std::string(size_t(filled), '#') + std::string(size_t(kBar - filled), '.');
  char target[48] = "";
  if (s.targetRelativeError > 0.0f) {
    std::snprintf(target, sizeof target, " (target %.3g %%)", 100.0 * s.targetRelativeError);
  }
  std::fprintf(stderr, "%s[%s] %u/%u samples, error %.3g %%%s, %s, ~%s left%s", terminal ? "\r\033[K" : "",
               bar.c_str(), p.samples, s.maxSamples, 100.0 * p.relativeErrorP95, target,
               formatSeconds(now).c_str(), formatSeconds(left).c_str(), terminal ? "" : "\n");
  std::fflush(stderr);
}

// Seconds that writing a baked scene takes per vertex and texel (glTF, EXR, manifest), an upper bound.
constexpr double kWriteSecondsPerPoint = 3e-6;
// The share of a time limit kept back from the passes for their predictions' error.
constexpr double kPassTimeMargin = 0.06;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int runBake(const BakeOptions& options, const CLI::App& sub) {
  const auto commandStart = std::chrono::steady_clock::now();
  std::optional<LoadedCheckpoint> loaded;
  BakeJob job = resolveJob(options, sub, loaded);
  BakeOptions o = options;
  o.scene = job.scenePath;
  o.out = job.outDir;
  o.exportGltf = job.exportGltf;
  o.sampling.sampler = job.samplerName;
  // A resumed bake's daylight is the checkpoint's.
  const LitScene lit = loadLitScene(o.scene, loaded ? DaylightOptions{} : o.daylight,
                                    loaded ? job.daylight : nlohmann::json(),
                                    (checkpointDirFor(o.out) / "checkpoint.json").string());
  const sdb::Scene& scene = lit.scene;
  std::fprintf(stderr, "light: %s\n", lit.light.c_str());
  if (!loaded) {
    job.daylight = daylightJson(scene, lit.defaultDaylight);
    job.settings.estimate = estimateSettings(o.sampling, scene.bakeSettings());
    job.settings.integrator = integratorSettings(o.sampling, scene.bakeSettings());
    job.settings.lightPaths.enabled = o.lightPaths == "on";
    job.settings.estimate.allocationFraction = o.noErrorAllocation ? 0.0f : raytracer::kBakeAllocationFraction;
  }
  const raytracer::BakeSettings& settings = job.settings;
  checkBakeOutput(o.out);  // before the bake, so that an hour's work is not refused at the end

  auto t = std::chrono::steady_clock::now();
  rdb::TraceRdb rdb = rdb::buildTraceRdb(scene);
  const double buildRdbS = secondsSince(t);
  t = std::chrono::steady_clock::now();
  const raytracer::EmbreeScene embree(rdb);
  const double buildEmbreeS = secondsSince(t);
  // Light textures where vertices cannot carry the light (before the fingerprint: they are part of the job).
  t = std::chrono::steady_clock::now();
  if (job.automaticLightTextures) {
    raytracer::LightResolutionSettings resolution;
    resolution.texelsPerMetre = float(scene.bakeSettings().texelsPerMetre);
    resolution.threads = settings.estimate.threads;
    raytracer::addNeededLightTextures(rdb, embree, resolution);
  }
  const double lightResolutionS = secondsSince(t);

  // Checkpoints: a resumed bake must see the scene it started with.
  const uint64_t fingerprint = traceRdbFingerprint(rdb);
  raytracer::BakeCheckpoint checkpointState;
  raytracer::BakeCheckpointing checkpointing;
  if (loaded) {
    if (loaded->fingerprint != fingerprint) {
      throw InputError(
          SourceLocation{o.scene},
          "the scene changed since the checkpoint in " + checkpointDirFor(o.out).string() + " was saved",
          "start the bake afresh without --resume (the checkpoint is replaced)");
    }
    checkpointState = std::move(loaded->state);
    checkCheckpointKeepsWhatTheBakeNeeds(checkpointState, rdb, o.out);
    checkpointing.state = &checkpointState;
    std::fprintf(stderr, "bake: resuming from %s (%u samples per point, %s done)\n",
                 checkpointDirFor(o.out).c_str(), checkpointState.progress.samplesPerPoint,
                 formatSeconds(checkpointState.progress.seconds).c_str());
  } else if (std::filesystem::exists(checkpointDirFor(o.out))) {
    std::fprintf(stderr,
                 "warning: %s holds the checkpoint of an earlier bake; starting afresh (use --resume %s "
                 "to continue it instead)\n",
                 checkpointDirFor(o.out).c_str(), o.out.c_str());
    std::filesystem::remove_all(checkpointDirFor(o.out));
  }
  if (job.checkpointIntervalS > 0.0) {
    checkpointing.state = &checkpointState;
    checkpointing.intervalS = job.checkpointIntervalS;
    checkpointing.save = [&](const raytracer::BakeCheckpoint& state) {
      saveBakeCheckpoint(job, fingerprint, state);
    };
  }

  BakeDescription d;
  d.scenePath = o.scene;
  if (settings.integrator.maxBounces < raytracer::kPathLengthGuard) {
    d.bounceCapBias = warnBounceCapBias(raytracer::estimateBounceCapBiasOnSurfaces(
        rdb, embree, settings.integrator, settings.estimate.threads, settings.estimate.seed));
  }

  // --time is the command's wall-clock limit: the passes get what start-up left, less the time that writing
  // the results will take (kWriteSecondsPerPoint per vertex and texel, measured on the house and the living
  // room at about a third of it, plus a second for the images), less kPassTimeMargin of it for the passes'
  // predictions (a pass's cost per sample is predicted from the last, over points that differ from pass to
  // pass: on the living room the passes ran 6 % over once); the baker takes its training out of it too.
  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  size_t points = rdb.positionsM.size();
  for (const rdb::TraceLightTexture& lt : rdb.lightTextures) points += size_t(lt.width) * lt.height;
  const double writeS = 1.0 + kWriteSecondsPerPoint * double(points);
  raytracer::BakeSettings passSettings = settings;
  const double beforeS = secondsSince(commandStart);
  if (std::isfinite(settings.estimate.timeLimitS) && !loaded) {
    passSettings.estimate.timeLimitS =
        std::max(0.0, (settings.estimate.timeLimitS - beforeS - writeS) * (1.0 - kPassTimeMargin));
  }
  const raytracer::VertexLightMaps maps = raytracer::bakeVertexLightMaps(
      rdb, embree, passSettings,
      [&](const raytracer::ConvergencePoint& p, uint32_t) {
        printProgress(p, passSettings.estimate, beforeS + p.trainingSeconds, writeS, terminal);
        return true;
      },
      checkpointing);
  if (terminal) std::fputc('\n', stderr);
  const auto writeStart = std::chrono::steady_clock::now();
  d.daylight = job.daylight;
  d.imageSettings = daylightSettings(scene);
  d.dotsPerInch = o.dotsPerInch;
  const raytracer::EstimateSettings& e = settings.estimate;
  d.settings = {
      {"max_samples", e.maxSamples},
      {"first_pass_samples", e.firstPassSamples},
      {"target_relative_error", e.targetRelativeError},
      {"time_limit_s", std::isfinite(e.timeLimitS) ? nlohmann::json(e.timeLimitS) : nlohmann::json()},
      {"sampler", o.sampling.sampler},
      {"replicates", maps.replicates},
      {"seed", e.seed},
      {"threads", e.threads},
      {"max_bounces", settings.integrator.maxBounces},
      {"caustics", settings.integrator.caustics},
      {"sky_portals", settings.integrator.skyPortals},
      {"lit_patches", settings.integrator.litPatches},
      {"roulette_after_light", settings.integrator.rouletteAfterLight},
      {"roulette_window", settings.integrator.rouletteWindow},
      {"lit_patch_sky", settings.integrator.litPatchSky},
      {"lit_patch_maps", settings.integrator.litPatchMaps},
      {"lit_patch_interior_training", settings.integrator.litPatchInteriorTraining},
      {"portal_continuation", settings.integrator.portalContinuation},
      {"light_paths", settings.lightPaths.enabled},
      {"error_allocation", e.allocationFraction}};
  d.targetRelativeError = e.targetRelativeError;
  for (const rdb::TraceMesh& m : rdb.meshes) {
    d.meshNames.push_back(scene.mesh(sdb::MeshId{m.sdbMeshId}).name);
    d.nodeNames.push_back(scene.node(sdb::NodeId{m.sdbNodeId}).name);
  }
  for (const rdb::TraceMaterial& m : rdb.materials) {
    d.materialNames.push_back(scene.material(sdb::MaterialId{m.sdbMaterialId}).name);
  }
  d.settings["automatic_light_textures"] = job.automaticLightTextures;
  d.timingsS = {{"build_trace_rdb", buildRdbS},
                {"build_embree", buildEmbreeS},
                {"light_resolution", lightResolutionS},
                {"bake", maps.seconds}};
  d.exportGltf = o.exportGltf;
  writeDirectoryAtomic(o.out, [&](const std::filesystem::path& tmp) { writeBakedScene(tmp, rdb, maps, d); });
  const double writeSeconds = secondsSince(writeStart);
  // The bake is complete: its checkpoint (this run's, or a stale one) is no longer needed.
  std::error_code ignored;
  std::filesystem::remove_all(checkpointDirFor(o.out), ignored);

  const float error = maps.history.empty() ? 0.0f : maps.history.back().relativeErrorP95;
  // Objects and light textures settled below the target before the last pass (kSettledPercentile).
  size_t settled = 0;
  for (const rdb::TraceMesh& m : rdb.meshes) {
    const uint32_t samples = objectSamples(maps, m);
    settled += samples > 0 && samples < maps.samplesPerVertex;
  }
  for (const raytracer::LightTexture& tex : maps.lightTextures)
    settled += tex.samples > 0 && tex.samples < maps.samplesPerVertex;
  const std::string settledText = settled == 0
                                      ? ""
                                      : " (fewer for " + std::to_string(settled) +
                                            " objects and light textures whose error was already low)";
  // Under the sun, the error of the part kept apart for sunlight mode (docs/mixed-lighting.md).
  char sunText[96] = "";
  if (maps.hasSunDirect() && !maps.history.empty()) {
    std::snprintf(sunText, sizeof sunText, " (of the sun's direct part %.3g %%)",
                  100.0 * maps.history.back().sunDirectRelativeErrorP95);
  }
  std::fprintf(
      stderr,
      "bake: %zu vertices, %u samples each%s, 95th percentile of relative standard error %.3g %%%s, %.1f s, "
      "%.3g Mrays/s -> %s\n",
      rdb.positionsM.size(), maps.samplesPerVertex, settledText.c_str(), 100.0 * error, sunText, maps.seconds,
      maps.seconds > 0.0 ? double(maps.rays) / maps.seconds * 1e-6 : 0.0, o.out.c_str());
  std::fprintf(stderr, "time: %.1f s in all (start-up %.2f s, training %.1f s, passes %.1f s, writing %.2f s)%s\n",
               secondsSince(commandStart), beforeS, maps.litPatchSeconds + maps.lightPathSeconds, maps.seconds,
               writeSeconds,
               std::isfinite(settings.estimate.timeLimitS) && !loaded
                   ? (" of the " + formatSeconds(settings.estimate.timeLimitS) + " limit").c_str()
                   : "");
  if (maps.litPatchCells > 0) {
    std::fprintf(stderr, "lit patches: sampled from %zu enclosed regions (trained in %.1f s)\n", maps.litPatchCells,
                 maps.litPatchSeconds);
  }
  if (maps.lightPaths > 0) {
    std::fprintf(stderr,
                 "light paths: %llu from the sun (pilot included), %.3g Mrays, %.1f s before the passes; "
                 "combined at %zu vertex sides, mean weight %.2f\n",
                 static_cast<unsigned long long>(maps.lightPaths), double(maps.lightPathRays) * 1e-6,
                 maps.lightPathSeconds, maps.lightPathCombinedSides, maps.lightPathMeanWeight);
  } else if (settings.lightPaths.enabled) {
    const bool fog = std::any_of(rdb.materials.begin(), rdb.materials.end(),
                                 [](const rdb::TraceMaterial& m) { return m.hasReflectionFog(); });
    std::fprintf(stderr, fog ? "light paths: none (the scene has reflection fog, which only the gathering "
                               "estimate models: docs/light-paths.md)\n"
                             : "light paths: none (the scene has no sun that lights it)\n");
  }
  for (const raytracer::LightTexture& tex : maps.lightTextures) {
    const rdb::TraceLightTexture& lt = rdb.lightTextures[size_t(&tex - maps.lightTextures.data())];
    const std::string& name = d.meshNames[tex.mesh].empty() ? d.nodeNames[tex.mesh] : d.meshNames[tex.mesh];
    std::fprintf(stderr,
                 "light texture: object %u \"%s\"%s, %u x %u texels at %.3g texels/m, %zu baked, %zu seam "
                 "edges, %u samples\n",
                 tex.mesh, name.c_str(), lt.automatic ? (" (automatic: " + lt.automaticReason + ")").c_str() : "",
                 tex.width, tex.height, double(lt.texelsPerMetre), tex.bakedTexels, tex.seamEdges, tex.samples);
    if (tex.emptyTexels > 0) {
      std::fprintf(stderr,
                   "warning: light texture of object %u: %zu texels are touched by triangles without area in "
                   "texture space (no valid sample); filled from their neighbours\n",
                   tex.mesh, tex.emptyTexels);
    }
  }
  // A limit shorter than the first pass: every point must take it (16 samples by default), so it ran over.
  if (std::isfinite(settings.estimate.timeLimitS) && !loaded && secondsSince(commandStart) > settings.estimate.timeLimitS &&
      maps.history.size() == 1) {
    std::fprintf(stderr,
                 "warning: the first pass (%u samples per vertex and texel) alone took %.1f s, more than the %s "
                 "limit; a bake cannot stop before it: give more time, or fewer points (a lower "
                 "bake.texelsPerMetre, --no-automatic-light-textures)\n",
                 maps.history.front().samples, maps.history.front().seconds,
                 formatSeconds(settings.estimate.timeLimitS).c_str());
  }
  // Points inside closed objects (raytracer/enclosure.h): reported apart, out of the error.
  size_t hiddenSides = 0, hiddenTexels = 0, hiddenObjects = 0;
  for (size_t i = 0; i < rdb.meshes.size(); ++i) {
    const size_t sides = i < maps.hiddenVertexSides.size() ? maps.hiddenVertexSides[i] : 0;
    const size_t texels = rdb.meshes[i].lightTexture != rdb::TraceMesh::kNoLightTexture
                              ? maps.lightTextures[rdb.meshes[i].lightTexture].hiddenTexelSides
                              : 0;
    hiddenSides += sides;
    hiddenTexels += texels;
    hiddenObjects += sides + texels > 0 ? 1 : 0;
  }
  if (hiddenSides + hiddenTexels > 0) {
    std::fprintf(stderr,
                 "hidden: %zu vertex sides and %zu texel sides in %zu objects lie inside closed objects, where no "
                 "view reaches (sampled in the first pass only, left out of the error; manifest: "
                 "hidden_vertex_sides, hidden_texel_sides)\n",
                 hiddenSides, hiddenTexels, hiddenObjects);
  }
  if (maps.unfilledVertices > 0) {
    std::fprintf(stderr, "warning: %zu vertices had no valid sample and no lit neighbour; their value is 0\n",
                 maps.unfilledVertices);
  }
  return 0;
}

}  // namespace

Command addBakeCommand(CLI::App& app) {
  auto o = std::make_shared<BakeOptions>();
  CLI::App* sub = app.add_subcommand("bake",
                                     "Bake vertex light maps and light textures (irradiance in lux, with "
                                     "standard errors) into a baked scene "
                                     "directory");
  sub->add_option("SCENE", o->scene, "scene file (.json) or glTF model (.gltf, .glb)");
  sub->add_option(
      "--out", o->out,
      "output directory: manifest.json, scene.gltf + scene.bin, lightmaps/*.exr (light textures), "
      "convergence.csv, convergence.png; "
      "created atomically; an earlier bake there is replaced, any other existing path refused "
      "(exit 2)");
  addSamplingOptions(*sub, o->sampling, "vertex");
  sub->add_flag(
      "--export-gltf", o->exportGltf,
      "also write export/scene.gltf with tone-mapped vertex colours and PNG light maps for any glTF "
      "viewer");
  sub->add_option(
      "--checkpoint", o->checkpoint,
      "save progress every SECONDS (e.g. 60, 5m) into DIR.checkpoint/, so that an interrupted bake "
      "can continue with --resume DIR; deleted when the bake completes");
  sub->add_flag("--no-error-allocation", o->noErrorAllocation,
                "every vertex and texel takes every pass; by default, points whose neighbours' error is far "
                "below the 95th percentile skip passes, so that the time goes where the error is "
                "(docs/sample-allocation.md)");
  sub->add_flag("--no-automatic-light-textures", o->noAutomaticLightTextures,
                "light textures only for the meshes that ask for them (lightTexture, bake.lightTextures); by "
                "default a mesh also gets one where its vertices cannot carry the light: sun patches, shadow "
                "edges, lamp pools, triangles of a metre or more");
  sub->add_option("--light-paths", o->lightPaths,
                  "on: light paths from the sun combined with the gathering estimate of every vertex "
                  "(docs/light-paths.md); off (the default): gathering alone");
  o->daylight.add(*sub, &o->sampling.time);
  addDpiOption(*sub, &o->dotsPerInch);
  sub->add_option("--resume", o->resume,
                  "continue the interrupted bake into DIR from DIR.checkpoint/ with its saved settings; the "
                  "result equals an uninterrupted bake with the same samples");
  return {sub, [o, sub] { return runBake(*o, *sub); }};
}

}  // namespace fly::cli
