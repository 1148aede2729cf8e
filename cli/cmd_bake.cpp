// `fly bake SCENE --out DIR`: bakes the scene's vertex light maps and writes the baked scene directory
// (cli/baked_scene.h), showing the progress and the estimated time left after every pass.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "base/error.h"
#include "cli/bake_options.h"
#include "cli/baked_scene.h"
#include "cli/command.h"
#include "raytracer/baker.h"
#include "raytracer/embree_scene.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/scene_load.h"

namespace fly::cli {

namespace {

struct BakeOptions {
  std::string scene;
  std::string out;
  SamplingOptions sampling;
  bool exportGltf = false;
};

// Seconds until the bake stops, from whichever rule stops it first: the sample limit (time grows with the
// samples), the time limit, or the target error (the error falls as 1/√samples, so reaching it takes
// (error / target)² times as long as it took so far). Infinite when no rule bounds it.
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
// error against the target and the time left. On a terminal it redraws one line; in a log, one line each.
void printProgress(const raytracer::ConvergencePoint& p, const raytracer::EstimateSettings& s,
                   bool terminal) {
  constexpr int kBar = 24;
  const double left = secondsLeft(p, s);
  const double done = p.seconds + left > 0.0 ? p.seconds / (p.seconds + left) : 1.0;
  const int filled = static_cast<int>(std::lround(done * kBar));
  const std::string bar = std::string(size_t(filled), '#') + std::string(size_t(kBar - filled), '.');
  char target[48] = "";
  if (s.targetRelativeError > 0.0f) {
    std::snprintf(target, sizeof target, " (target %.3g %%)", 100.0 * s.targetRelativeError);
  }
  std::fprintf(stderr, "%s[%s] %u/%u samples, error %.3g %%%s, %s, ~%s left%s", terminal ? "\r\033[K" : "",
               bar.c_str(), p.samples, s.maxSamples, 100.0 * p.relativeErrorP95, target,
               formatSeconds(p.seconds).c_str(), formatSeconds(left).c_str(), terminal ? "" : "\n");
  std::fflush(stderr);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int runBake(const BakeOptions& o) {
  const sdb::Scene scene = sdb::loadScene(o.scene);
  raytracer::BakeSettings settings;
  settings.estimate = estimateSettings(o.sampling, scene.bakeSettings());
  settings.integrator = integratorSettings(o.sampling, scene.bakeSettings());
  checkBakeOutput(o.out);  // before the bake, so that an hour's work is not refused at the end

  auto t = std::chrono::steady_clock::now();
  const rdb::TraceRdb rdb = rdb::buildTraceRdb(scene);
  const double buildRdbS = secondsSince(t);
  t = std::chrono::steady_clock::now();
  const raytracer::EmbreeScene embree(rdb);
  const double buildEmbreeS = secondsSince(t);

  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  const raytracer::VertexLightMaps maps = raytracer::bakeVertexLightMaps(
      rdb, embree, settings, [&](const raytracer::ConvergencePoint& p, uint32_t) {
        printProgress(p, settings.estimate, terminal);
        return true;
      });
  if (terminal) std::fputc('\n', stderr);

  BakeDescription d;
  d.scenePath = o.scene;
  const raytracer::EstimateSettings& e = settings.estimate;
  d.settings = {
      {"max_samples", e.maxSamples},
      {"first_pass_samples", e.firstPassSamples},
      {"target_relative_error", e.targetRelativeError},
      {"time_limit_s", std::isfinite(e.timeLimitS) ? nlohmann::json(e.timeLimitS) : nlohmann::json()},
      {"sampler", o.sampling.sampler},
      {"replicates", e.replicates},
      {"seed", e.seed},
      {"threads", e.threads},
      {"max_bounces", settings.integrator.maxBounces}};
  d.targetRelativeError = e.targetRelativeError;
  for (const rdb::TraceMesh& m : rdb.meshes) {
    d.meshNames.push_back(scene.mesh(sdb::MeshId{m.sdbMeshId}).name);
    d.nodeNames.push_back(scene.node(sdb::NodeId{m.sdbNodeId}).name);
  }
  for (const rdb::TraceMaterial& m : rdb.materials) {
    d.materialNames.push_back(scene.material(sdb::MaterialId{m.sdbMaterialId}).name);
  }
  d.timingsS = {{"build_trace_rdb", buildRdbS}, {"build_embree", buildEmbreeS}, {"bake", maps.seconds}};
  d.exportGltf = o.exportGltf;
  writeDirectoryAtomic(o.out, [&](const std::filesystem::path& tmp) { writeBakedScene(tmp, rdb, maps, d); });

  const float error = maps.history.empty() ? 0.0f : maps.history.back().relativeErrorP95;
  std::fprintf(
      stderr,
      "bake: %zu vertices, %u samples each, 95th percentile of relative standard error %.3g %%, %.1f s, "
      "%.3g Mrays/s -> %s\n",
      rdb.positionsM.size(), maps.samplesPerVertex, 100.0 * error, maps.seconds,
      maps.seconds > 0.0 ? double(maps.rays) / maps.seconds * 1e-6 : 0.0, o.out.c_str());
  if (maps.unfilledVertices > 0) {
    std::fprintf(stderr, "warning: %zu vertices had no valid sample and no lit neighbour; their value is 0\n",
                 maps.unfilledVertices);
  }
  return 0;
}

}  // namespace

Command addBakeCommand(CLI::App& app) {
  auto o = std::make_shared<BakeOptions>();
  CLI::App* sub = app.add_subcommand(
      "bake",
      "Bake vertex light maps (irradiance in lux, with standard errors) into a baked scene directory");
  sub->add_option("SCENE", o->scene, "scene file (.json) or glTF model (.gltf, .glb)")->required();
  sub->add_option(
         "--out", o->out,
         "output directory: manifest.json, scene.gltf + scene.bin, convergence.csv, convergence.png; "
         "created atomically; an earlier bake there is replaced, any other existing path refused "
         "(exit 2)")
      ->required();
  addSamplingOptions(*sub, o->sampling, "vertex");
  sub->add_flag("--export-gltf", o->exportGltf,
                "also write export/scene.gltf with tone-mapped vertex colours for any glTF viewer");
  return {sub, [o] { return runBake(*o); }};
}

}  // namespace fly::cli
