// fly-bench-light-paths: the vertex baker on the house (scenes/house/house.json under its clear sky and sun)
// with the gathering estimator alone and combined with light paths from the sun (docs/light-paths.md), at
// equal gathering samples, in one run: time (light paths and their pilot included), the 95th percentile over
// vertex sides of the reported relative standard error of luminance, and the efficiency ratio
// (error² × time of gathering) / (error² × time of the combination): how many times sooner the combination
// reaches a given error. The reported errors are checked against a reference bake of another seed: the RMS
// over vertex sides of (value − reference) / √(σ² + σ_ref²) should be near 1 for both.
//
// Usage: fly-bench-light-paths [SCENE] [--samples 64,256,1024] [--reference 1024] [--paths-per-sample 8]
// [--pilot-fraction 0.125] (run from the repository's root for the default scene; --paths-per-sample: light
// paths per vertex side per gathering sample; --pilot-fraction: the pilot's light paths as a fraction of the
// bake's).
//
// fly-bench-light-paths --lit-patches SECONDS [--reference N] [--plot PNG] [--allocation F] [SCENE]: three
// bakes of SECONDS each (passes that would end later do not start), in one run: the gathering estimator as
// it was before next-event estimation to lit patches (IntegratorSettings::litPatches and rouletteAfterLight
// off, rouletteWindow 1: throughput roulette; every point taking every pass), the lit patches (both on, the
// default window; docs/lit-patches.md) with every point taking every pass, and the lit patches with sample allocation by error (EstimateSettings::
// allocationFraction = F, default kBakeAllocationFraction: `fly bake`'s default estimator). Per bake: the
// bake's p95 (its history: vertex sides and light-texture texels) against time per pass, the process's CPU
// time of the bake (getrusage: user + system, the lit patches' training included; steadier than wall time
// on a shared machine), the time at which p95 reaches 2 % extrapolated from the last pass by p95² × time =
// constant (the 1/√time of Monte Carlo; quasi-Monte Carlo and settled groups only make it sooner), in wall
// and CPU seconds, and the ratios against the first bake; the mean over the interior's vertex sides (sensor
// within the house's rooms: scenes/house) of the reported relative error and of the measured one against a
// reference bake of the lit patches (every point every pass) with N samples and another seed (its own error
// subtracted in quadrature); honesty as above; the share of the samples the allocation saved. --plot writes
// the convergence curves in one PNG. --allocation F1,F2,… bakes the lit patches with each fraction;
// --samples N bakes N samples each instead of SECONDS (then SECONDS is ignored: the CPU time is the measure,
// steadier than a time limit on a loaded machine); --no-gathering leaves out the first bake (the ratios are
// then against the lit patches with every point every pass); --breakdown prints after each bake which
// points make its p95 (printBreakdown).
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <map>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cli/convergence_plot.h"
#include "cli/scene_daylight.h"
#include "raytracer/baker.h"
#include "raytracer/embree_scene.h"
#include "rdb/trace_rdb_build.h"

namespace fly {
namespace {

struct Row {
  double seconds = 0.0;
  double p95 = 0.0;
  double honesty = 0.0;
  uint64_t rays = 0;
};

// The nearest-rank 95th percentile of the relative standard error of luminance over vertex sides with a
// positive mean (front sides and the backs of two-sided meshes).
double relativeErrorP95(const raytracer::VertexLightMaps& m) {
  std::vector<double> rel;
  for (const auto& [mean, error] :
       {std::pair{&m.frontLux, &m.frontStdErrorLux}, {&m.backLux, &m.backStdErrorLux}}) {
    for (size_t v = 0; v < mean->size(); ++v) {
      const double l = luminance((*mean)[v]);
      if (l > 0.0) rel.push_back(luminance((*error)[v]) / l);
    }
  }
  if (rel.empty()) return 0.0;
  const size_t k = std::min(rel.size() - 1, static_cast<size_t>(std::ceil(0.95 * double(rel.size()))) - 1);
  std::nth_element(rel.begin(), rel.begin() + static_cast<std::ptrdiff_t>(k), rel.end());
  return rel[k];
}

// RMS over vertex sides of (value − reference) / √(σ² + σ_ref²), in luminance.
double honesty(const raytracer::VertexLightMaps& m, const raytracer::VertexLightMaps& ref) {
  double sum = 0.0;
  size_t n = 0;
  auto add = [&](const std::vector<Rgb>& a, const std::vector<Rgb>& ae, const std::vector<Rgb>& b,
                 const std::vector<Rgb>& be) {
    for (size_t v = 0; v < a.size(); ++v) {
      const double s = std::hypot(double(luminance(ae[v])), double(luminance(be[v])));
      if (!(s > 0.0)) continue;
      const double z = (double(luminance(a[v])) - double(luminance(b[v]))) / s;
      sum += z * z;
      ++n;
    }
  };
  add(m.frontLux, m.frontStdErrorLux, ref.frontLux, ref.frontStdErrorLux);
  add(m.backLux, m.backStdErrorLux, ref.backLux, ref.backStdErrorLux);
  return n > 0 ? std::sqrt(sum / double(n)) : 0.0;
}

std::vector<uint32_t> parseList(const char* s) {
  std::vector<uint32_t> out;
  for (const char* p = s; *p;) {
    out.push_back(static_cast<uint32_t>(std::strtoul(p, nullptr, 10)));
    p = std::strchr(p, ',');
    if (!p) break;
    ++p;
  }
  return out;
}

// The house's rooms (scenes/house/house.gltf: inside the outer walls, floor to ceiling), metres, with a
// margin for the door's inner face: a vertex side is interior when its sensor, 5 cm along its normal, lies
// within.
constexpr float kInteriorMinM[3] = {-3.85f, 0.1f, -2.85f};
constexpr float kInteriorMaxM[3] = {3.85f, 2.8f, 2.95f};

bool interior(const vec3& p, const vec3& n) {
  const vec3 q = p + 0.05f * n;
  for (int k = 0; k < 3; ++k) {
    if (!(q[k] > kInteriorMinM[k] && q[k] < kInteriorMaxM[k])) return false;
  }
  return true;
}

struct InteriorError {
  double reported = 0.0;  // mean of σ / E over interior vertex sides
  double measured = 0.0;  // √(mean of ((E − R)² − σ_R²) / R²), the reference's own error taken out
  size_t sides = 0;
};

InteriorError interiorError(const rdb::TraceRdb& rdb, const raytracer::VertexLightMaps& m,
                            const raytracer::VertexLightMaps& ref) {
  InteriorError out;
  double squares = 0.0;
  for (int back = 0; back < 2; ++back) {
    const auto& e = back ? m.backLux : m.frontLux;
    const auto& se = back ? m.backStdErrorLux : m.frontStdErrorLux;
    const auto& r = back ? ref.backLux : ref.frontLux;
    const auto& rse = back ? ref.backStdErrorLux : ref.frontStdErrorLux;
    for (size_t v = 0; v < e.size(); ++v) {
      const double l = luminance(e[v]), lr = luminance(r[v]);
      if (!(l > 0.0) || !(lr > 0.0) || !interior(rdb.positionsM[v], back ? -rdb.normals[v] : rdb.normals[v]))
        continue;
      out.reported += luminance(se[v]) / l;
      const double d = l - lr, sr = luminance(rse[v]);
      squares += (d * d - sr * sr) / (lr * lr);
      ++out.sides;
    }
  }
  if (out.sides > 0) {
    out.reported /= double(out.sides);
    out.measured = std::sqrt(std::max(0.0, squares / double(out.sides)));
  }
  return out;
}

// The process's CPU time so far (user + system), seconds.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto s = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return s(usage.ru_utime) + s(usage.ru_stime);
}

// The share of the samples the front vertex sides took against every one taking every pass.
double sampleShare(const raytracer::VertexLightMaps& m) {
  double taken = 0.0, full = 0.0;
  for (uint32_t samples : m.frontSamples) {
    if (samples == 0) continue;
    taken += samples;
    full += m.samplesPerVertex;
  }
  return full > 0.0 ? taken / full : 1.0;
}

// Which points make a bake's p95 (--breakdown): the vertex sides of each node of the scene (inside the rooms
// or out, by interior()) and the baked texels of each light-textured node, each group with its points, how
// many lie at or above the p95 over all points and at or above the allocation's threshold (f × p95,
// kBakeAllocationFraction), and its mean relative error of luminance.
void printBreakdown(const sdb::Scene& sdbScene, const rdb::TraceRdb& rdb, const raytracer::VertexLightMaps& m) {
  struct Group {
    size_t points = 0, atP95 = 0, atThreshold = 0;
    double sum = 0.0;
  };
  std::vector<std::pair<std::string, float>> points;  // group name, relative error
  auto nodeName = [&](uint32_t mesh) {
    const auto it = sdbScene.nodes().find(sdb::NodeId{rdb.meshes[mesh].sdbNodeId});
    return it == sdbScene.nodes().end() || it->second.name.empty() ? "mesh " + std::to_string(mesh)
                                                                   : it->second.name;
  };
  for (uint32_t mi = 0; mi < rdb.meshes.size(); ++mi) {
    const rdb::TraceMesh& mesh = rdb.meshes[mi];
    for (uint32_t v = mesh.firstVertex; v < mesh.firstVertex + mesh.vertexCount; ++v) {
      for (int back = 0; back < (mesh.twoSided ? 2 : 1); ++back) {
        const double l = luminance(back ? m.backLux[v] : m.frontLux[v]);
        if (!(l > 0.0)) continue;
        const bool inside = interior(rdb.positionsM[v], back ? -rdb.normals[v] : rdb.normals[v]);
        points.emplace_back("vertex sides, " + nodeName(mi) + (inside ? ", inside" : ", outside"),
                            static_cast<float>(luminance(back ? m.backStdErrorLux[v] : m.frontStdErrorLux[v]) / l));
      }
    }
  }
  for (const raytracer::LightTexture& t : m.lightTextures) {
    for (size_t i = 0; i < t.frontLux.size(); ++i) {
      const double l = luminance(t.frontLux[i]);
      if (!t.baked[i] || !(l > 0.0)) continue;
      points.emplace_back("texels, " + nodeName(t.mesh), static_cast<float>(luminance(t.frontStdErrorLux[i]) / l));
    }
  }
  if (points.empty()) return;
  std::vector<float> errors;
  for (const auto& p : points) errors.push_back(p.second);
  const size_t k = std::min(errors.size() - 1, static_cast<size_t>(std::ceil(0.95 * static_cast<double>(errors.size()))) - 1);
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(k), errors.end());
  const float p95 = errors[k];
  std::map<std::string, Group> groups;
  for (const auto& [name, error] : points) {
    Group& g = groups[name];
    ++g.points;
    g.atP95 += error >= p95;
    g.atThreshold += error >= raytracer::kBakeAllocationFraction * p95;
    g.sum += error;
  }
  std::printf("where the p95 (%.2f %% over %zu points) is:\n| points | count | at or above the p95 | at or above %.2f × p95 | "
              "mean relative error |\n|---|---|---|---|---|\n",
              100.0 * p95, points.size(), double(raytracer::kBakeAllocationFraction));
  for (const auto& [name, g] : groups) {
    std::printf("| %s | %zu | %zu | %zu | %.2f %% |\n", name.c_str(), g.points, g.atP95, g.atThreshold,
                100.0 * g.sum / static_cast<double>(g.points));
  }
}

struct LitPatchRun {
  double seconds = 0.0;         // per bake; 0: samples instead
  uint32_t samples = 0;         // per bake when seconds is 0
  uint32_t referenceSamples = 0;
  std::vector<float> allocations;  // a bake of the lit patches with each allocation fraction
  bool gathering = true;           // the bake before lit patches, the baseline of the ratios
  bool breakdown = false;          // printBreakdown() after each bake
  std::string plotPath;
};

int runLitPatches(const std::string& scenePath, const LitPatchRun& run) {
  const cli::LitScene lit = cli::loadLitScene(scenePath, cli::DaylightOptions{});
  const rdb::TraceRdb rdb = rdb::buildTraceRdb(lit.scene);
  const raytracer::EmbreeScene scene(rdb);
  std::printf("%s: %zu vertices, %zu triangles; %s; bakes of %s\n", scenePath.c_str(), rdb.positionsM.size(),
              rdb.triangleCount(), lit.light.c_str(),
              run.seconds > 0.0 ? (std::to_string(run.seconds).substr(0, 5) + " s").c_str()
                                : (std::to_string(run.samples) + " samples").c_str());
  auto settingsOf = [&](bool patches, float allocationFraction) {
    raytracer::BakeSettings s;
    s.integrator.litPatches = patches;
    s.integrator.rouletteAfterLight = patches;
    s.integrator.portalContinuation = patches;
    if (!patches) s.integrator.rouletteWindow = 1.0f;
    s.estimate.firstPassSamples = 16;
    s.estimate.maxSamples = run.seconds > 0.0 ? 1u << 20 : run.samples;
    if (run.seconds > 0.0) s.estimate.timeLimitS = run.seconds;
    s.estimate.allocationFraction = allocationFraction;
    return s;
  };
  raytracer::BakeSettings refSettings = settingsOf(true, 0.0f);
  refSettings.estimate.maxSamples = run.referenceSamples;
  refSettings.estimate.timeLimitS = std::numeric_limits<double>::infinity();
  refSettings.estimate.seed = 1000;
  const auto refStart = std::chrono::steady_clock::now();
  const raytracer::VertexLightMaps reference = raytracer::bakeVertexLightMaps(rdb, scene, refSettings);
  std::printf("reference: lit patches, %u samples, seed 1000: %.1f s, p95 %.2f %%\n", run.referenceSamples,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - refStart).count(),
              100.0 * relativeErrorP95(reference));
  struct Bake {
    std::string name;
    bool patches = true;
    float allocation = 0.0f;
    raytracer::VertexLightMaps maps;
    double secondsTo2Percent = 0.0;
    double cpuSecondsTo2Percent = 0.0;
  };
  std::vector<Bake> bakes;
  if (run.gathering) bakes.push_back({"gathering (before lit patches)", false, 0.0f, {}, 0.0, 0.0});
  bakes.push_back({"lit patches, every point every pass", true, 0.0f, {}, 0.0, 0.0});
  for (float f : run.allocations) {
    bakes.push_back({"lit patches, allocation by error " + std::to_string(f).substr(0, 4) +
                         (f == raytracer::kBakeAllocationFraction ? " (default)" : ""),
                     true, f, {}, 0.0, 0.0});
  }
  for (Bake& bake : bakes) {
    raytracer::BakeSettings s = settingsOf(bake.patches, bake.allocation);
    s.estimate.seed = 1;
    const double cpuStart = cpuSeconds();
    std::vector<double> passCpu;  // CPU seconds at the end of each pass, since the bake started
    bake.maps = raytracer::bakeVertexLightMaps(rdb, scene, s, [&](const raytracer::ConvergencePoint&, uint32_t) {
      passCpu.push_back(cpuSeconds() - cpuStart);
      return true;
    });
    const double cpu = cpuSeconds() - cpuStart;
    const raytracer::VertexLightMaps& m = bake.maps;
    std::printf("\n%s%s:\n| samples | time (s) | CPU (s) | p95 | p95² × time (s) | p95² × 2 × CPU s of the pass |\n"
                "|---|---|---|---|---|---|\n",
                bake.name.c_str(),
                bake.patches ? (" (" + std::to_string(m.litPatchCells) + " regions, trained in " +
                                std::to_string(m.litPatchSeconds).substr(0, 4) + " s, not in the times)")
                                   .c_str()
                             : "");
    // The last column: the pass's own CPU time against the error it reached, which tends to the bake's
    // p95² × CPU s as passes double (each costs as much as all before it).
    for (size_t j = 0; j < m.history.size(); ++j) {
      const raytracer::ConvergencePoint& p = m.history[j];
      const double e2 = double(p.relativeErrorP95) * p.relativeErrorP95;
      const double passCpuS = passCpu[j] - (j > 0 ? passCpu[j - 1] : 0.0);
      std::printf("| %u | %.1f | %.1f | %.2f %% | %.3f | %.3f |\n", p.samples, p.seconds, passCpu[j],
                  100.0 * p.relativeErrorP95, e2 * p.seconds, e2 * passCpuS * 2.0);
    }
    const raytracer::ConvergencePoint& last = m.history.back();
    const double p95 = last.relativeErrorP95;
    const double scale = (p95 / 0.02) * (p95 / 0.02);
    bake.secondsTo2Percent = last.seconds * scale;
    bake.cpuSecondsTo2Percent = cpu * scale;
    if (run.breakdown) printBreakdown(lit.scene, rdb, m);
    const InteriorError ie = interiorError(rdb, m, reference);
    std::printf(
        "CPU %.1f s (p95² × CPU s %.3f); p95 2 %% extrapolated at %.0f s (%.0f CPU s); interior (%zu vertex "
        "sides) at %.0f s: mean relative error reported %.2f %%, measured %.2f %%; honesty %.2f; samples "
        "taken %.0f %% of every point every pass\n",
        cpu, p95 * p95 * cpu, bake.secondsTo2Percent, bake.cpuSecondsTo2Percent, ie.sides, last.seconds,
        100.0 * ie.reported, 100.0 * ie.measured, honesty(m, reference), 100.0 * sampleShare(m));
    std::fflush(stdout);
  }
  std::printf("\ntime to p95 = 2 %%, times sooner than %s (wall / CPU):\n", bakes[0].name.c_str());
  for (size_t k = 1; k < bakes.size(); ++k) {
    std::printf("  %s: %.2f / %.2f\n", bakes[k].name.c_str(),
                bakes[0].secondsTo2Percent / bakes[k].secondsTo2Percent,
                bakes[0].cpuSecondsTo2Percent / bakes[k].cpuSecondsTo2Percent);
  }
  if (!run.plotPath.empty()) {
    static constexpr std::array<uint8_t, 3> kColours[] = {
        {214, 39, 40}, {255, 127, 14}, {31, 119, 180}, {44, 160, 44}, {148, 103, 189}, {140, 86, 75}};
    std::vector<cli::ConvergenceCurve> curves;
    for (size_t k = 0; k < bakes.size(); ++k) {
      curves.push_back({bakes[k].maps.history, bakes[k].name,
                        kColours[(k + (run.gathering ? 0 : 1)) % std::size(kColours)]});
    }
    cli::ConvergencePlotRequest request;
    request.targetRelativeError = 0.02f;
    cli::drawConvergencePlot(curves, "The house: gathering, lit patches, allocation by error (p95)",
                             run.plotPath, request);
    std::printf("wrote %s\n", run.plotPath.c_str());
  }
  return 0;
}

int run(int argc, char** argv) {
  std::string scenePath = "scenes/house/house.json";
  std::vector<uint32_t> samples = {64, 256, 1024};
  uint32_t referenceSamples = 1024;
  double pathsPerSample = 8.0;
  double pilotFraction = 0.125;
  double litPatchSeconds = 0.0;
  bool litPatches = false;
  LitPatchRun litRun;
  litRun.allocations = {raytracer::kBakeAllocationFraction};
  bool samplesGiven = false;
  std::string plotPath;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--lit-patches" && i + 1 < argc) {
      litPatchSeconds = std::strtod(argv[++i], nullptr);
      litPatches = true;
      continue;
    }
    if (a == "--no-gathering") {
      litRun.gathering = false;
      continue;
    }
    if (a == "--breakdown") {
      litRun.breakdown = true;
      continue;
    }
    if (a == "--plot" && i + 1 < argc) {
      plotPath = argv[++i];
      continue;
    }
    if (a == "--allocation" && i + 1 < argc) {
      litRun.allocations.clear();
      for (const char* p = argv[++i]; *p;) {
        char* end = nullptr;
        const float f = std::strtof(p, &end);
        if (end == p || !(f > 0.0f && f <= 1.0f)) {
          std::fprintf(stderr, "fly-bench-light-paths: --allocation %s: expected fractions in (0, 1]\n",
                       argv[i]);
          return 2;
        }
        litRun.allocations.push_back(f);
        p = *end == ',' ? end + 1 : end;
      }
      continue;
    }
    if (a == "--samples" && i + 1 < argc) {
      samples = parseList(argv[++i]);
      samplesGiven = true;
    } else if (a == "--reference" && i + 1 < argc) {
      referenceSamples = static_cast<uint32_t>(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--paths-per-sample" && i + 1 < argc) {
      pathsPerSample = std::strtod(argv[++i], nullptr);
    } else if (a == "--pilot-fraction" && i + 1 < argc) {
      pilotFraction = std::strtod(argv[++i], nullptr);
    } else if (a.rfind("--", 0) != 0) {
      scenePath = a;
    } else {
      std::fprintf(stderr,
                   "usage: fly-bench-light-paths [SCENE] [--samples 64,256,1024] [--reference N] "
                   "[--paths-per-sample X] [--pilot-fraction F]\n"
                   "       fly-bench-light-paths [SCENE] --lit-patches SECONDS [--reference N] [--plot PNG] "
                   "[--allocation F,...] [--samples N] [--no-gathering] [--breakdown]\n");
      return 2;
    }
  }
  if (litPatches) {
    litRun.seconds = samplesGiven ? 0.0 : litPatchSeconds;
    litRun.samples = samples.empty() ? 256 : samples.front();
    litRun.referenceSamples = referenceSamples;
    litRun.plotPath = plotPath;
    return runLitPatches(scenePath, litRun);
  }
  const cli::LitScene lit = cli::loadLitScene(scenePath, cli::DaylightOptions{});
  const rdb::TraceRdb rdb = rdb::buildTraceRdb(lit.scene);
  const raytracer::EmbreeScene scene(rdb);
  size_t sides = 0;
  for (const rdb::TraceMesh& m : rdb.meshes) sides += size_t{m.vertexCount} * (m.twoSided ? 2 : 1);
  std::printf("%s: %zu vertices (%zu sides), %zu triangles; %s\n", scenePath.c_str(), rdb.positionsM.size(),
              sides, rdb.triangleCount(), lit.light.c_str());

  auto bake = [&](uint32_t n, bool lightPaths, uint64_t seed, Row& row) {
    raytracer::BakeSettings s;
    s.estimate.maxSamples = n;
    s.estimate.firstPassSamples = std::min<uint32_t>(n, 16);
    s.estimate.seed = seed;
    s.lightPaths.enabled = lightPaths;
    s.lightPaths.paths.batches = 8;
    s.lightPaths.paths.pathsPerBatch =
        std::max<uint32_t>(1024, static_cast<uint32_t>(pathsPerSample * double(n) * double(sides) / 8.0));
    s.lightPaths.pilotPathsPerBatch = std::max<uint32_t>(
        1024, static_cast<uint32_t>(pilotFraction * double(s.lightPaths.paths.pathsPerBatch)));
    s.lightPaths.pilotSamples = 16;
    const auto start = std::chrono::steady_clock::now();
    raytracer::VertexLightMaps m = raytracer::bakeVertexLightMaps(rdb, scene, s);
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    row.p95 = relativeErrorP95(m);
    row.rays = m.rays + m.lightPathRays;
    if (lightPaths) {
      std::printf("  (%u samples: light paths combined at %zu of %zu vertex sides, mean weight %.2f)\n", n,
                  m.lightPathCombinedSides, sides, m.lightPathMeanWeight);
    }
    return m;
  };
  Row refRow;
  const raytracer::VertexLightMaps reference = bake(referenceSamples, false, 1000, refRow);
  std::printf("reference: gathering, %u samples, seed 1000: %.1f s, p95 %.2f %%\n", referenceSamples,
              refRow.seconds, 100.0 * refRow.p95);
  std::printf(
      "| samples | gathering: time, p95, honesty | combined: time, p95, honesty | p95 ratio | "
      "efficiency (err² × time) |\n|---|---|---|---|---|\n");
  for (const uint32_t n : samples) {
    Row g, c;
    g.honesty = honesty(bake(n, false, 1, g), reference);
    c.honesty = honesty(bake(n, true, 1, c), reference);
    std::printf("| %u | %.1f s, %.2f %%, %.2f | %.1f s, %.2f %%, %.2f | %.2f | %.2f |\n", n, g.seconds,
                100.0 * g.p95, g.honesty, c.seconds, 100.0 * c.p95, c.honesty, g.p95 / c.p95,
                (g.p95 * g.p95 * g.seconds) / (c.p95 * c.p95 * c.seconds));
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace fly

int main(int argc, char** argv) {
  try {
    return fly::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fly-bench-light-paths: %s\n", e.what());
    return 3;
  }
}
