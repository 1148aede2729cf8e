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
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

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

int run(int argc, char** argv) {
  std::string scenePath = "scenes/house/house.json";
  std::vector<uint32_t> samples = {64, 256, 1024};
  uint32_t referenceSamples = 1024;
  double pathsPerSample = 8.0;
  double pilotFraction = 0.125;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--samples" && i + 1 < argc) {
      samples = parseList(argv[++i]);
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
                   "[--paths-per-sample X] [--pilot-fraction F]\n");
      return 2;
    }
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
