// fly-bench-baker: the vertex baker's performance figures, each as a ratio against a baseline measured in the
// same run, because the machine is shared and noisy (docs/architecture.md, "Performance figures"; results in
// docs/benchmarks.md).
//
//   1. Throughput: the baker's rays/s (sampling and shading included) against raw EmbreeScene queries on the
//      baker's own rays, logged from a bake and traced again from an array; and, as a floor, a minimal path
//      tracer (no light sampling, materials or statistics) against the same baseline on its own rays.
//   2. QMC against plain MC: RMSE of vertex irradiance at equal samples against a many-sample reference,
//      with all bounces, one bounce and direct light only.
//   3. Scaling: bake time for 10k, 100k and 1M triangles, 1 thread against all.
//   4. Memory: peak resident set size after the largest bake.
//   5. Textures: the baker's rays/s on the scene of part 1 with textured ground and boxes (base colour
//      textures, one box an alpha cut-out) against the same scene untextured.
//   6. Measured BRDFs and anisotropy: nanoseconds per eval + pdf and per sample of a tabulated table's lobe,
//      of the car-paint lobe and of the anisotropic GGX lobe against the analytic glossy Bsdf (diffuse +
//      isotropic GGX), one thread; and the baker's rays/s on the scene of part 1 with a measured ground and
//      car-paint boxes, and with anisotropic glossy materials (shaded in the tangent frame), against the same
//      scene with isotropic glossy ones.
//   7. Scaling in a sunlit interior (--part scaling-room): the room of part 1 tessellated to 20k and 1M
//      triangles, 1 thread against all, with rays/s and peak memory.
//
// Usage: fly-bench-baker [--quick] [--part throughput|qmc|scaling|scaling-room|textures|measured|atlas]...
// (--quick: 10k triangles only (part 7: 20k), a smaller QMC reference; --part: only the parts named)
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "raytracer/baker.h"
#include "raytracer/bsdf.h"
#include "raytracer/light_resolution.h"
#include "raytracer/car_paint_lobe.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "raytracer/sampler.h"
#include "raytracer/tabulated_lobe.h"
#include "raytracer/warp.h"
#include "rdb/trace_rdb.h"
#include "rdb/trace_rdb_build.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::raytracer {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void addSunAndSky(rdb::TraceRdb& rdb);

// A width × width RGBA texture of sRGB colours whose channels are uniform in [lo, hi] (a fixed PCG32
// stream), alpha 255, or with `stripes` alpha 0 on every other run of 8 columns.
std::vector<uint8_t> noiseTexture(uint32_t width, int lo, int hi, bool stripes, uint64_t stream) {
  Pcg32 rng(stream, 11);
  std::vector<uint8_t> texels;
  for (uint32_t y = 0; y < width; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c)
        texels.push_back(static_cast<uint8_t>(lo + int(rng.next() % uint32_t(hi - lo + 1))));
      texels.push_back(stripes && (x / 8) % 2 == 1 ? 0 : 255);
    }
  }
  return texels;
}

// The benchmark scene: a square ground of 2·cells² triangles, 40 m wide, with a 4 × 4 array of boxes (five
// faces of two triangles each) that cast shadows under a sun at 35° elevation and a sky brighter at the
// zenith. Ground albedo 0.5, boxes 0.7, so indirect light matters too. textured: the ground's albedo is a
// 512² noise texture (sRGB 160 … 215, a mean near 0.5) repeated every 4 m, the boxes' a 64² one (200 … 230,
// near 0.7), and the first box is an alpha cut-out of vertical stripes (half of it open).
rdb::TraceRdb makeScene(uint32_t cells, bool textured = false) {
  rdb::TraceRdbBuilder b;
  const uint32_t groundMaterial = b.material(Rgb(0.5f));
  const uint32_t solidBoxMaterial = b.material(Rgb(0.7f));
  const uint32_t cutOutMaterial = b.material(Rgb(0.7f));
  if (textured) {
    rdb::TraceTextureSlot slot;
    slot.texture = b.texture(512, 512, 4, noiseTexture(512, 160, 215, false, 1));
    b.rdb.materials[groundMaterial].diffuseColor = Rgb(1.0f);
    b.rdb.materials[groundMaterial].diffuseTexture = slot;
    slot.texture = b.texture(64, 64, 4, noiseTexture(64, 200, 230, false, 2));
    b.rdb.materials[solidBoxMaterial].diffuseColor = Rgb(1.0f);
    b.rdb.materials[solidBoxMaterial].diffuseTexture = slot;
    slot.texture = b.texture(64, 64, 4, noiseTexture(64, 200, 230, true, 3));
    b.rdb.materials[cutOutMaterial].diffuseColor = Rgb(1.0f);
    b.rdb.materials[cutOutMaterial].diffuseTexture = slot;
    b.rdb.materials[cutOutMaterial].alpha = rdb::TraceAlpha::kMask;
  }
  auto grid = [&b](const vec3& origin, const vec3& edgeU, const vec3& edgeV, uint32_t n, uint32_t material,
                   float uvScale = 1.0f) { b.grid(origin, edgeU, edgeV, n, material, false, uvScale); };

  constexpr float kHalfM = 20.0f;
  grid(vec3(-kHalfM, 0, -kHalfM), vec3(0, 0, 2 * kHalfM), vec3(2 * kHalfM, 0, 0), cells, groundMaterial,
       2.0f * kHalfM / 4.0f);
  for (int bz = 0; bz < 4; ++bz) {
    for (int bx = 0; bx < 4; ++bx) {
      const uint32_t boxMaterial = bx == 0 && bz == 0 ? cutOutMaterial : solidBoxMaterial;
      const float x0 = -16.0f + 9.0f * static_cast<float>(bx);
      const float z0 = -16.0f + 9.0f * static_cast<float>(bz);
      const float sx = 2.5f;
      const float sz = 1.5f + 0.5f * static_cast<float>(bx);
      const float h = 1.0f + 0.75f * static_cast<float>(bz);
      grid(vec3(x0, h, z0), vec3(0, 0, sz), vec3(sx, 0, 0), 1, boxMaterial);      // top, +Y
      grid(vec3(x0 + sx, 0, z0), vec3(0, h, 0), vec3(0, 0, sz), 1, boxMaterial);  // +X
      grid(vec3(x0, 0, z0), vec3(0, 0, sz), vec3(0, h, 0), 1, boxMaterial);       // −X
      grid(vec3(x0, 0, z0 + sz), vec3(sx, 0, 0), vec3(0, h, 0), 1, boxMaterial);  // +Z
      grid(vec3(x0, 0, z0), vec3(0, h, 0), vec3(sx, 0, 0), 1, boxMaterial);       // −Z
    }
  }

  addSunAndSky(b.rdb);
  for (const vec3& p : b.rdb.positionsM) b.rdb.boundsM.extend(p);
  return std::move(b.rdb);
}

// The sun at 35° elevation and 60° azimuth, and a sky rising from 2000 cd/m² at the horizon to 5000 cd/m² at
// the zenith, bluish.
void addSunAndSky(rdb::TraceRdb& rdb) {
  const float elevation = glm::radians(35.0f);
  const float azimuth = glm::radians(60.0f);
  rdb.hasSun = true;
  rdb.sun.directionWorld = glm::normalize(vec3(std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                                               std::cos(elevation) * std::sin(azimuth)));
  rdb.sun.normalIlluminanceLux = Rgb(90000.0f, 85000.0f, 78000.0f);
  // Radiance rising from 2000 cd/m² at the horizon to 5000 cd/m² at the zenith, bluish.
  constexpr uint32_t kSkyResolution = 16;
  rdb.sky.resolution = kSkyResolution;
  for (uint32_t j = 0; j < kSkyResolution; ++j) {
    const float mu = 1.0f - (static_cast<float>(j) + 0.5f) / kSkyResolution;
    for (uint32_t i = 0; i < kSkyResolution; ++i) {
      rdb.sky.radianceCdM2.push_back(Rgb(0.75f, 0.9f, 1.2f) * (2000.0f + 3000.0f * mu));
    }
  }
}

// The interior scene: a closed room 8 × 3 × 6 m (floor albedo 0.4, walls 0.6, ceiling 0.8, all facing in)
// with a 3 × 1.5 m window opening in the wall towards the sun, on a 100 m ground below it outside, under the
// same sun and sky: daylight through a window, the architect's everyday case. The room's surfaces are grids
// of about `triangles` triangles in all; the sun falls through the opening onto the floor.
rdb::TraceRdb makeRoomScene(uint32_t triangles) {
  rdb::TraceRdbBuilder b;
  const uint32_t floorMaterial = b.material(Rgb(0.4f));
  const uint32_t wallMaterial = b.material(Rgb(0.6f));
  const uint32_t ceilingMaterial = b.material(Rgb(0.8f));
  const uint32_t groundMaterial = b.material(Rgb(0.3f));
  // Cells per metre so that the room's 2·(48 + 18 + 24) m² hold about `triangles` triangles.
  const float perM = std::sqrt(static_cast<float>(triangles) / (2.0f * 180.0f));
  auto cells = [perM](float lengthM) {
    return std::max(1u, static_cast<uint32_t>(std::lround(lengthM * perM)));
  };
  auto grid = [&](const vec3& origin, const vec3& edgeU, const vec3& edgeV, uint32_t material) {
    b.grid(origin, edgeU, edgeV, cells(std::max(glm::length(edgeU), glm::length(edgeV))), material);
  };
  grid(vec3(-4, 0, -3), vec3(0, 0, 6), vec3(8, 0, 0), floorMaterial);    // floor, +Y
  grid(vec3(-4, 3, -3), vec3(8, 0, 0), vec3(0, 0, 6), ceilingMaterial);  // ceiling, −Y
  grid(vec3(-4, 0, -3), vec3(0, 3, 0), vec3(0, 0, 6), wallMaterial);     // x = −4, +X
  grid(vec3(4, 0, -3), vec3(0, 0, 6), vec3(0, 3, 0), wallMaterial);      // x = 4, −X
  grid(vec3(-4, 0, -3), vec3(8, 0, 0), vec3(0, 3, 0), wallMaterial);     // z = −3, +Z
  // z = 3, facing −Z, around the opening x ∈ [−1.5, 1.5], y ∈ [0.8, 2.3].
  grid(vec3(-4, 0, 3), vec3(0, 3, 0), vec3(2.5f, 0, 0), wallMaterial);
  grid(vec3(1.5f, 0, 3), vec3(0, 3, 0), vec3(2.5f, 0, 0), wallMaterial);
  grid(vec3(-1.5f, 0, 3), vec3(0, 0.8f, 0), vec3(3, 0, 0), wallMaterial);
  grid(vec3(-1.5f, 2.3f, 3), vec3(0, 0.7f, 0), vec3(3, 0, 0), wallMaterial);
  b.grid(vec3(-50, -0.05f, -50), vec3(0, 0, 100), vec3(100, 0, 0), 1, groundMaterial);  // outside, +Y
  addSunAndSky(b.rdb);
  for (const vec3& p : b.rdb.positionsM) b.rdb.boundsM.extend(p);
  return std::move(b.rdb);
}

// Ground cells for about `triangles` triangles (the boxes add 160).
uint32_t cellsFor(uint32_t triangles) {
  return static_cast<uint32_t>(std::lround(std::sqrt(static_cast<double>(triangles) / 2.0)));
}

VertexLightMaps bake(const rdb::TraceRdb& rdb, const EmbreeScene& scene, uint32_t samples, uint32_t threads,
                     SamplerKind sampler = SamplerKind::kSobol,
                     uint32_t replicates = EstimateSettings{}.replicates, uint64_t seed = 0,
                     uint32_t maxBounces = kPathLengthGuard) {
  BakeSettings settings;
  settings.integrator.maxBounces = maxBounces;
  settings.estimate.firstPassSamples = samples;
  settings.estimate.maxSamples = samples;
  settings.estimate.replicates = replicates;
  settings.estimate.sampler = sampler;
  settings.estimate.threads = threads;
  settings.estimate.seed = seed;
  return bakeVertexLightMaps(rdb, scene, settings);
}

// The baseline's rays: exactly those the baker traces, logged from a one-thread bake of the same settings
// (EmbreeScene::logRaysOfThisThread), in the order it traced them.
std::vector<LoggedRay> bakerRays(const rdb::TraceRdb& rdb, const EmbreeScene& scene, uint32_t samples) {
  std::vector<LoggedRay> rays;
  EmbreeScene::logRaysOfThisThread(&rays);
  const VertexLightMaps maps = bake(rdb, scene, samples, 1);
  EmbreeScene::logRaysOfThisThread(nullptr);
  if (rays.size() != maps.rays) {
    std::printf("  (logged %zu rays, the bake counted %llu: the baseline is not the baker's rays)\n",
                rays.size(), static_cast<unsigned long long>(maps.rays));
  }
  return rays;
}

// Rays per second of tracing `rays` on `threads` threads, each taking a contiguous share, over as many passes
// as make at least half a second (one pass of 16 threads is too short to time).
double rawRaysPerSecond(const EmbreeScene& scene, const std::vector<LoggedRay>& rays, uint32_t threads) {
  // One counter per thread, written once at the end: incrementing adjacent counters in the loop would share
  // a cache line between threads. Read afterwards so that no query can be optimised away.
  std::vector<uint64_t> hits(threads, 0);
  const Clock::time_point start = Clock::now();
  uint64_t traced = 0;
  do {
    std::vector<std::thread> workers;
    for (uint32_t t = 0; t < threads; ++t) {
      workers.emplace_back([&, t] {
        const size_t begin = rays.size() * t / threads;
        const size_t end = rays.size() * (t + 1) / threads;
        uint64_t local = 0;
        for (size_t i = begin; i < end; ++i) {
          const LoggedRay& r = rays[i];
          local += r.occlusion ? scene.occluded(r.origin, r.dir, r.tMaxM)
                               : scene.intersect(r.origin, r.dir, r.tMaxM).has_value();
        }
        hits[t] += local;
      });
    }
    for (std::thread& w : workers) w.join();
    traced += rays.size();
  } while (secondsSince(start) < 0.5);
  const double seconds = secondsSince(start);
  uint64_t total = 0;
  for (uint64_t h : hits) total += h;
  if (total == 0) std::printf("  (no ray hit anything: the baseline scene is wrong)\n");
  return static_cast<double>(traced) / seconds;
}

// A floor for the ratio: the least work that makes rays of the same kind. Every vertex (at the vertex itself,
// no one-ring), 64 paths of PCG32 numbers: a shadow ray to the sun's centre when it is above the surface, one
// to a cosine-distributed direction (standing in for the sky's), and a cosine-distributed continuation,
// from the hit point on (its geometric normal facing the ray) while a coin toss after the first bounce
// allows; no radiance, materials, MIS, statistics or Sobol' points. Returns its rays per second on one
// thread, and logs its rays into `log` when given.
double minimalTracerRaysPerSecond(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                  std::vector<LoggedRay>* log, uint64_t& rayCount) {
  constexpr uint32_t kSamples = 64;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const vec3 sun = rdb.sun.directionWorld;
  EmbreeScene::logRaysOfThisThread(log);
  const Clock::time_point start = Clock::now();
  uint64_t rays = 0;
  uint64_t hits = 0;
  for (size_t v = 0; v < rdb.positionsM.size(); ++v) {
    Pcg32 rng(v, 7);
    auto u01 = [&rng] { return static_cast<float>(rng.next() >> 8) * 0x1p-24f; };
    for (uint32_t s = 0; s < kSamples; ++s) {
      vec3 p = rdb.positionsM[v];
      vec3 n = rdb.normals[v];
      for (uint32_t depth = 0; depth < 64; ++depth) {
        const float magnitude = maxAbs(p);
        const vec3 origin = offsetRayOrigin(p, n, magnitude);
        const Onb frame = onb(n);
        if (glm::dot(n, sun) > 0.0f) {
          ++rays;
          hits += scene.occluded(origin, sun, kInf);
        }
        ++rays;
        hits += scene.occluded(origin, frame.toWorld(sampleCosineHemisphere(vec2(u01(), u01()))), kInf);
        const vec3 d = frame.toWorld(sampleCosineHemisphere(vec2(u01(), u01())));
        ++rays;
        const std::optional<Hit> hit = scene.intersect(origin, d, kInf);
        if (!hit || (depth > 0 && u01() < 0.5f)) break;
        const uint32_t t = hit->triangle;
        p = (1.0f - hit->barycentric.x - hit->barycentric.y) * rdb.positionsM[rdb.indices[3 * t]] +
            hit->barycentric.x * rdb.positionsM[rdb.indices[3 * t + 1]] +
            hit->barycentric.y * rdb.positionsM[rdb.indices[3 * t + 2]];
        n = glm::dot(hit->geometricNormal, d) < 0.0f ? hit->geometricNormal : -hit->geometricNormal;
      }
    }
  }
  const double seconds = secondsSince(start);
  EmbreeScene::logRaysOfThisThread(nullptr);
  if (hits == 0) std::printf("  (the minimal tracer's rays hit nothing)\n");
  rayCount = rays;
  return static_cast<double>(rays) / seconds;
}

// Part 5: rays/s of the textured scene against the untextured one, baker runs alternating, best of each.
void benchTextures(uint32_t maxThreads) {
  constexpr uint32_t kSamples = 64;
  constexpr int kRepetitions = 3;
  const rdb::TraceRdb plain = makeScene(cellsFor(10000));
  const rdb::TraceRdb textured = makeScene(cellsFor(10000), true);
  const EmbreeScene plainScene(plain);
  const EmbreeScene texturedScene(textured);
  std::printf("\n5. Textures: %zu triangles, %u samples per vertex, best of %d\n", plain.triangleCount(),
              kSamples, kRepetitions);
  for (uint32_t threads : maxThreads > 1 ? std::vector<uint32_t>{1, maxThreads} : std::vector<uint32_t>{1}) {
    double plainRate = 0.0, texturedRate = 0.0, plainSampleRate = 0.0, texturedSampleRate = 0.0;
    for (int r = 0; r < kRepetitions; ++r) {
      const VertexLightMaps a = bake(plain, plainScene, kSamples, threads);
      const VertexLightMaps t = bake(textured, texturedScene, kSamples, threads);
      plainRate = std::max(plainRate, static_cast<double>(a.rays) / a.seconds);
      texturedRate = std::max(texturedRate, static_cast<double>(t.rays) / t.seconds);
      plainSampleRate = std::max(plainSampleRate, 1.0 / a.seconds);
      texturedSampleRate = std::max(texturedSampleRate, 1.0 / t.seconds);
    }
    std::printf(
        "   threads %u: untextured %.3g rays/s, textured %.3g rays/s: ratio %.2f (bake time ratio "
        "untextured/textured %.2f)\n",
        threads, plainRate, texturedRate, texturedRate / plainRate, texturedSampleRate / plainSampleRate);
  }
}

// A table of a rough metal with a little diffuse (GGX α 0.25, F0 (0.9, 0.7, 0.5), separable Smith masking, plus
// 0.1/π), tabulated at the table's own samples.
std::shared_ptr<const BrdfTable> roughMetalTable() {
  std::vector<Rgb> samples(BrdfTable::kSamples, Rgb(0.0f));
  const std::vector<uint8_t>& valid = BrdfTable::validSamples();
  CarPaintBrdf metal;  // the car-paint model without coat or base: one GGX lobe
  metal.coatIor = 1.0f;
  metal.lobes[0] = {Rgb(0.9f, 0.7f, 0.5f), 0.25f};
  for (int i = 0; i < BrdfTable::kThetaHalfRes; ++i) {
    for (int j = 0; j < BrdfTable::kThetaDiffRes; ++j) {
      for (int k = 0; k < BrdfTable::kPhiDiffRes; ++k) {
        const size_t index = BrdfTable::sampleIndex(i, j, k);
        if (!valid[index]) continue;
        vec3 wi, wo;
        directionsOf(BrdfTable::sampleAngles(i, j, k), wi, wo);
        samples[index] = metal.evalPerSr(wi, wo) + Rgb(0.1f / kPiF);
      }
    }
  }
  return std::make_shared<const BrdfTable>(std::move(samples));
}

// Part 6: per-call cost of the measured lobes against the analytic Bsdf, and the baker's rays/s with them.
void benchMeasured(uint32_t maxThreads) {
  const std::shared_ptr<const BrdfTable> table = roughMetalTable();
  Clock::time_point start = Clock::now();
  const TabulatedLobe tabulated(table, 1.0f);
  const double tabulatedBuildS = secondsSince(start);
  CarPaintBrdf paint;
  paint.baseAlbedo = Rgb(0.1f);
  paint.lobes[0] = {Rgb(0.45f, 0.46f, 0.48f), 0.2f};
  paint.lobes[1] = {Rgb(0.1f), 0.5f};
  paint.coatIor = 1.5f;
  paint.coatAlpha = 0.01f;
  start = Clock::now();
  const CarPaintBsdfLobe carPaint(paint);
  const double carPaintBuildS = secondsSince(start);
  start = Clock::now();
  const auto regularisedTable = TabulatedLobe::regularised(*table, std::atan(kRegularizedGlossiness * kRegularizedGlossiness));
  const double regulariseS = secondsSince(start);
  rdb::TraceMaterial glossy;
  glossy.diffuse = glossy.diffuseColor = Rgb(0.5f);
  glossy.reflection = Rgb(1.0f);
  glossy.reflectionGlossiness = 0.5f;
  rdb::TraceMaterial measured = glossy;
  measured.brdfTable = 0;
  rdb::TraceMaterial painted = glossy;
  painted.carPaint = paint;
  rdb::TraceMaterial brushed = glossy;  // the brushed-metal preset's anisotropy, turned
  brushed.anisotropyU = 0.6f;
  brushed.anisotropyV = 0.1f;
  brushed.anisotropyRotationRad = 0.3f;
  const Bsdf analytic(glossy, true);
  const Bsdf anisotropicBsdf(brushed, true);
  const Bsdf tabulatedBsdf(measured, true, 1.0f, &tabulated);
  const Bsdf carPaintBsdf(painted, true, 1.0f, &carPaint);

  constexpr uint32_t kCalls = 1u << 20;
  std::vector<vec3> wo(kCalls), wi(kCalls);
  std::vector<vec3> u(kCalls);
  RandomSampler sampler(5);
  for (uint32_t i = 0; i < kCalls; ++i) {
    sampler.startSample(i);
    wo[i] = sampleCosineHemisphere(sampler.next2D());
    wi[i] = sampleCosineHemisphere(sampler.next2D());
    u[i] = vec3(sampler.next1D(), sampler.next2D());
  }
  std::printf(
      "\n6. Measured BRDFs: build %.0f ms (table lobe), %.0f ms (regularised table), %.1f ms (car-paint lobe); ns per "
      "call, one thread, best of 3\n",
      1e3 * tabulatedBuildS, 1e3 * regulariseS, 1e3 * carPaintBuildS);
  double analyticEval = 0.0, analyticSample = 0.0;
  for (const auto& [name, bsdf] :
       {std::pair{"analytic (diffuse + GGX)", &analytic}, std::pair{"measured table", &tabulatedBsdf},
        std::pair{"car paint", &carPaintBsdf}, std::pair{"anisotropic GGX", &anisotropicBsdf}}) {
    double evalNs = std::numeric_limits<double>::infinity(), sampleNs = evalNs;
    float sink = 0.0f;
    for (int r = 0; r < 3; ++r) {
      start = Clock::now();
      for (uint32_t i = 0; i < kCalls; ++i) sink += bsdf->eval(wo[i], wi[i]).g + bsdf->pdf(wo[i], wi[i]);
      evalNs = std::min(evalNs, 1e9 * secondsSince(start) / kCalls);
      start = Clock::now();
      Bsdf::Sample s;
      for (uint32_t i = 0; i < kCalls; ++i) {
        if (bsdf->sample(wo[i], u[i].x, vec2(u[i].y, u[i].z), s)) sink += s.weight.g;
      }
      sampleNs = std::min(sampleNs, 1e9 * secondsSince(start) / kCalls);
    }
    if (bsdf == &analytic) {
      analyticEval = evalNs;
      analyticSample = sampleNs;
    }
    std::printf("   %-24s eval + pdf %6.1f ns (%.1f× analytic), sample %6.1f ns (%.1f× analytic)%s\n", name, evalNs,
                evalNs / analyticEval, sampleNs, sampleNs / analyticSample, sink == 0.0f ? " (no work?)" : "");
  }

  // The baker: ground a measured table, boxes car paint, against the same scene analytic.
  constexpr uint32_t kSamples = 64;
  constexpr int kRepetitions = 3;
  const rdb::TraceRdb plain = makeScene(cellsFor(10000));
  rdb::TraceRdb withMeasured = plain;
  withMeasured.brdfTables.push_back({"rough metal", table});
  withMeasured.materials[0].brdfTable = 0;
  withMeasured.materials[1].carPaint = paint;
  withMeasured.materials[2].carPaint = paint;
  // Glossy materials (diffuse + GGX, glossiness 0.5) everywhere, isotropic and anisotropic: the second reads
  // tangents (generated from the UVs) and shades in their frame.
  rdb::TraceRdb withGlossy = plain;
  for (rdb::TraceMaterial& m : withGlossy.materials) {
    m.reflection = glossy.reflection;
    m.reflectionGlossiness = glossy.reflectionGlossiness;
    m.diffuse = normalIncidenceDiffuse(m);
  }
  rdb::TraceRdb withAnisotropic = withGlossy;
  for (rdb::TraceMaterial& m : withAnisotropic.materials) {
    m.anisotropyU = brushed.anisotropyU;
    m.anisotropyV = brushed.anisotropyV;
    m.anisotropyRotationRad = brushed.anisotropyRotationRad;
  }
  withAnisotropic.tangents = rdb::generateTangents(withAnisotropic.positionsM, withAnisotropic.normals,
                                                   withAnisotropic.uv0, withAnisotropic.indices);
  const EmbreeScene plainScene(plain);
  const EmbreeScene measuredScene(withMeasured);
  const EmbreeScene glossyScene(withGlossy);
  const EmbreeScene anisotropicScene(withAnisotropic);
  std::printf("   baker, %zu triangles, %u samples per vertex, best of %d:\n", plain.triangleCount(), kSamples,
              kRepetitions);
  for (uint32_t threads : maxThreads > 1 ? std::vector<uint32_t>{1, maxThreads} : std::vector<uint32_t>{1}) {
    double plainRate = 0.0, measuredRate = 0.0;
    for (int r = 0; r < kRepetitions; ++r) {
      const VertexLightMaps a = bake(plain, plainScene, kSamples, threads);
      const VertexLightMaps m = bake(withMeasured, measuredScene, kSamples, threads);
      plainRate = std::max(plainRate, static_cast<double>(a.rays) / a.seconds);
      measuredRate = std::max(measuredRate, static_cast<double>(m.rays) / m.seconds);
    }
    std::printf("   threads %u: analytic %.3g rays/s, measured %.3g rays/s: ratio %.2f\n", threads, plainRate,
                measuredRate, measuredRate / plainRate);
    double glossyRate = 0.0, anisotropicRate = 0.0;
    for (int r = 0; r < kRepetitions; ++r) {
      const VertexLightMaps g = bake(withGlossy, glossyScene, kSamples, threads);
      const VertexLightMaps a = bake(withAnisotropic, anisotropicScene, kSamples, threads);
      glossyRate = std::max(glossyRate, static_cast<double>(g.rays) / g.seconds);
      anisotropicRate = std::max(anisotropicRate, static_cast<double>(a.rays) / a.seconds);
    }
    std::printf("   threads %u: isotropic glossy %.3g rays/s, anisotropic glossy %.3g rays/s: ratio %.2f\n",
                threads, glossyRate, anisotropicRate, anisotropicRate / glossyRate);
  }
}

void benchThroughput(uint32_t maxThreads, const char* name, const rdb::TraceRdb& rdb) {
  constexpr uint32_t kSamples = 64;
  // Baker and baseline alternate, and each keeps its best run: the one least slowed by the machine's other
  // load.
  constexpr int kRepetitions = 3;
  const EmbreeScene scene(rdb);
  std::vector<LoggedRay> rays = bakerRays(rdb, scene, kSamples);
  std::printf(
      "1. Throughput, %s: %zu triangles, %zu vertices, %u samples per vertex (Sobol, %u replicates), best "
      "of %d\n",
      name, rdb.triangleCount(), rdb.positionsM.size(), kSamples,
      replicatesFor(EstimateSettings{}, rdb.positionsM.size()), kRepetitions);
  for (uint32_t threads : maxThreads > 1 ? std::vector<uint32_t>{1, maxThreads} : std::vector<uint32_t>{1}) {
    double raw = 0.0;
    double baker = 0.0;
    uint64_t bakerRays = 0;
    for (int r = 0; r < kRepetitions; ++r) {
      raw = std::max(raw, rawRaysPerSecond(scene, rays, threads));
      const VertexLightMaps maps = bake(rdb, scene, kSamples, threads);
      baker = std::max(baker, static_cast<double>(maps.rays) / maps.seconds);
      bakerRays = maps.rays;
    }
    std::printf(
        "   threads %u: baker %.3g rays/s (%.2f rays per vertex sample), raw %.3g rays/s (%zu rays a pass): "
        "ratio %.2f\n",
        threads, baker,
        static_cast<double>(bakerRays) / static_cast<double>(rdb.positionsM.size() * kSamples), raw,
        rays.size(), baker / raw);
  }
  // Freed first: part 4's peak memory is the process's, and should be the 1M-triangle bake's.
  std::vector<LoggedRay>().swap(rays);
  std::vector<LoggedRay> minimalRays;
  uint64_t minimalCount = 0;
  minimalTracerRaysPerSecond(rdb, scene, &minimalRays, minimalCount);
  double minimal = 0.0;
  double minimalRaw = 0.0;
  for (int r = 0; r < kRepetitions; ++r) {
    minimalRaw = std::max(minimalRaw, rawRaysPerSecond(scene, minimalRays, 1));
    minimal = std::max(minimal, minimalTracerRaysPerSecond(rdb, scene, nullptr, minimalCount));
  }
  std::printf(
      "   floor, a minimal path tracer on 1 thread: %.3g rays/s (%.2f rays per vertex sample), raw %.3g "
      "rays/s on its rays: ratio %.2f\n",
      minimal, static_cast<double>(minimalCount) / static_cast<double>(rdb.positionsM.size() * 64),
      minimalRaw, minimal / minimalRaw);
}

std::vector<double> frontLuminance(const VertexLightMaps& maps) {
  std::vector<double> y(maps.frontLux.size());
  for (size_t v = 0; v < y.size(); ++v) y[v] = luminance(maps.frontLux[v]);
  return y;
}

// Root mean square over vertices and seeds of the difference from the reference, in lux.
double rmse(const rdb::TraceRdb& rdb, const EmbreeScene& scene, const std::vector<double>& reference,
            uint32_t samples, uint32_t threads, SamplerKind sampler, uint32_t replicates, uint32_t seeds,
            uint32_t maxBounces) {
  double sum = 0.0;
  for (uint32_t s = 0; s < seeds; ++s) {
    // Seeds far from the reference's, so that no point shares its scrambling with the reference.
    const uint64_t seed = 1000000u * (s + 1);
    const std::vector<double> y =
        frontLuminance(bake(rdb, scene, samples, threads, sampler, replicates, seed, maxBounces));
    for (size_t v = 0; v < y.size(); ++v) sum += (y[v] - reference[v]) * (y[v] - reference[v]);
  }
  return std::sqrt(sum / static_cast<double>(reference.size() * seeds));
}

// Run with all bounces (what the baker does), with one bounce and with direct light only (maxBounces = 1, 0),
// which shows how much of QMC's advantage the high-dimensional indirect paths take away.
void benchQmc(uint32_t threads, bool quick, uint32_t maxBounces) {
  const uint32_t referenceSamples = quick ? 2048 : 16384;
  constexpr uint32_t kSeeds = 4;
  const rdb::TraceRdb rdb = makeScene(24);
  const EmbreeScene scene(rdb);
  const Clock::time_point start = Clock::now();
  const std::vector<double> reference =
      frontLuminance(bake(rdb, scene, referenceSamples, threads, SamplerKind::kSobol, 1, 7, maxBounces));
  std::printf(
      "\n2. QMC against MC, %s: %zu vertices, reference %u Sobol samples (1 replicate, %.1f s); RMSE "
      "of vertex luminance over %u seeds\n",
      maxBounces == 0   ? "direct light only"
      : maxBounces == 1 ? "direct light and one bounce"
                        : "all bounces",
      rdb.positionsM.size(), referenceSamples, secondsSince(start), kSeeds);
  double meanReference = 0.0;
  for (double y : reference) meanReference += y / static_cast<double>(reference.size());
  std::printf("   mean vertex illuminance %.0f lx\n", meanReference);
  constexpr std::array<uint32_t, 4> kReplicates = {8, 4, 2, 1};
  std::printf("   %8s %10s", "samples", "RMSE MC");
  for (uint32_t k : kReplicates) std::printf("   QMC K=%u", k);
  for (uint32_t k : kReplicates) std::printf("  MC/QMC K=%u", k);
  std::printf("\n");
  const std::vector<uint32_t> counts =
      quick ? std::vector<uint32_t>{16, 64} : std::vector<uint32_t>{16, 64, 256};
  for (uint32_t samples : counts) {
    const double mc =
        rmse(rdb, scene, reference, samples, threads, SamplerKind::kRandom, 1, kSeeds, maxBounces);
    std::array<double, kReplicates.size()> qmc{};
    for (size_t i = 0; i < kReplicates.size(); ++i) {
      qmc[i] = rmse(rdb, scene, reference, samples, threads, SamplerKind::kSobol, kReplicates[i], kSeeds,
                    maxBounces);
    }
    std::printf("   %8u %7.1f lx", samples, mc);
    for (double q : qmc) std::printf(" %7.1f lx", q);
    for (double q : qmc) std::printf(" %11.2f", mc / q);
    std::printf("\n");
  }
}

void benchScaling(uint32_t maxThreads, bool quick) {
  constexpr uint32_t kSamples = 16;
  std::printf("\n3. Scaling: %u samples per vertex (Sobol, %u replicates); bake time without the BVH build\n",
              kSamples, replicatesFor(EstimateSettings{}, cellsFor(10000) * cellsFor(10000)));
  std::printf("   %10s %10s %10s %12s %12s %9s\n", "triangles", "vertices", "BVH build", "1 thread",
              (std::to_string(maxThreads) + " threads").c_str(), "speed-up");
  const std::vector<uint32_t> sizes =
      quick ? std::vector<uint32_t>{10000} : std::vector<uint32_t>{10000, 100000, 1000000};
  for (uint32_t triangles : sizes) {
    const rdb::TraceRdb rdb = makeScene(cellsFor(triangles));
    const Clock::time_point start = Clock::now();
    const EmbreeScene scene(rdb);
    const double buildSeconds = secondsSince(start);
    const double one = bake(rdb, scene, kSamples, 1).seconds;
    const double many = bake(rdb, scene, kSamples, maxThreads).seconds;
    std::printf("   %10zu %10zu %8.2f s %10.2f s %10.2f s %9.2f\n", rdb.triangleCount(),
                rdb.positionsM.size(), buildSeconds, one, many, one / many);
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  // ru_maxrss is in KiB on Linux.
  std::printf("\n4. Memory: peak resident set size after the %s-triangle bake: %.0f MiB\n",
              quick ? "10k" : "1M", static_cast<double>(usage.ru_maxrss) / 1024.0);
}

// The sunlit interior at scale: the room of makeRoomScene with its surfaces tessellated to about 20k and 1M
// triangles (--quick: 20k only), each baked on all threads, on 1 thread and on all threads again, the same
// samples: the ratio is the 1-thread time over the mean of the two all-thread runs, and the repeat shows
// whether the order matters (first touches of memory, the machine's other load). Prints the BVH build, the
// bake times, rays/s, and the process's peak resident set size (ru_maxrss) after the largest scene, which
// is that bake's when this part runs alone (--part scaling-room).
void benchScalingRoom(uint32_t maxThreads, bool quick) {
  // makeRoomScene's grids are square in cells, so its surfaces get about 1.68 times the triangles asked for:
  // 12k give 20k, 600k give 1.0M.
  const std::vector<std::pair<uint32_t, uint32_t>> sizesAndSamples =
      quick ? std::vector<std::pair<uint32_t, uint32_t>>{{12000, 16}}
            : std::vector<std::pair<uint32_t, uint32_t>>{{12000, 64}, {600000, 16}};
  std::printf("\n7. Scaling in a sunlit interior: room 8 × 3 × 6 m with a window under sun and sky; bake time "
              "without the BVH build, %u threads, 1 thread, %u threads again\n", maxThreads, maxThreads);
  std::printf("   %10s %10s %8s %10s %10s %10s %10s %12s %12s %9s\n", "triangles", "vertices", "samples",
              "BVH build", "N threads", "1 thread", "N again", "rays/s 1", "rays/s N", "speed-up");
  for (const auto& [requested, samples] : sizesAndSamples) {
    const rdb::TraceRdb rdb = makeRoomScene(requested);
    const Clock::time_point start = Clock::now();
    const EmbreeScene scene(rdb);
    const double buildSeconds = secondsSince(start);
    const VertexLightMaps first = bake(rdb, scene, samples, maxThreads);
    const VertexLightMaps one = bake(rdb, scene, samples, 1);
    const VertexLightMaps again = bake(rdb, scene, samples, maxThreads);
    const double many = 0.5 * (first.seconds + again.seconds);
    std::printf("   %10zu %10zu %8u %8.2f s %8.2f s %8.2f s %8.2f s %12.3g %12.3g %9.2f\n", rdb.triangleCount(),
                rdb.positionsM.size(), samples, buildSeconds, first.seconds, one.seconds, again.seconds,
                static_cast<double>(one.rays) / one.seconds, static_cast<double>(again.rays) / many,
                one.seconds / many);
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  // ru_maxrss is in KiB on Linux.
  std::printf("   peak resident set size %.0f MiB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
}

// Automatic light textures at scale (raytracer/light_resolution.h): the analysis of where vertices cannot
// carry the light and the atlases it asks for, on the open ground and the sunlit room at about 1M triangles
// (--quick: 20k), against the BVH build of the same scene (the baseline of this run). Memory: the texels'
// values a bake keeps (irradiance, sun-direct part, their errors and spread: 7 RGB floats per texel side)
// and the atlas's corner UVs, besides the process's peak resident set size.
void benchAtlas(uint32_t maxThreads, bool quick) {
  std::printf("\n8. Automatic light textures: analysis and atlases, %u threads\n", maxThreads);
  std::printf("   %-12s %10s %10s %10s %12s %8s %10s %12s %12s\n", "scene", "triangles", "BVH build",
              "analysis", "analysis/BVH", "meshes", "textured", "texels", "atlas MiB");
  const uint32_t ground = quick ? 20000 : 1000000;
  const uint32_t room = quick ? 12000 : 600000;
  for (int which = 0; which < 2; ++which) {
    rdb::TraceRdb rdb = which == 0 ? makeScene(cellsFor(ground)) : makeRoomScene(room);
    const Clock::time_point start = Clock::now();
    const EmbreeScene scene(rdb);
    const double buildSeconds = secondsSince(start);
    const Clock::time_point analysisStart = Clock::now();
    LightResolutionSettings settings;
    settings.threads = maxThreads;
    const std::vector<MeshLightResolution> analysis = addNeededLightTextures(rdb, scene, settings);
    const double analysisSeconds = secondsSince(analysisStart);
    size_t textured = 0, texels = 0, bytes = 0;
    for (const rdb::TraceLightTexture& lt : rdb.lightTextures) {
      textured += lt.automatic ? 1 : 0;
      const size_t n = size_t(lt.width) * lt.height;
      const size_t sides = rdb.meshes[lt.mesh].twoSided ? 2 : 1;
      texels += n;
      bytes += n * sides * 7 * sizeof(Rgb) + lt.cornerUv.size() * sizeof(vec2);
    }
    std::printf("   %-12s %10zu %8.2f s %8.2f s %12.2f %8zu %10zu %12zu %12.1f\n", which == 0 ? "open ground" : "sunlit room",
                rdb.triangleCount(), buildSeconds, analysisSeconds, analysisSeconds / buildSeconds, analysis.size(),
                textured, texels, double(bytes) / (1024.0 * 1024.0));
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("   peak resident set size %.0f MiB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
}

}  // namespace
}  // namespace fly::raytracer

int main(int argc, char** argv) {
  bool quick = false;
  // Which parts to run: all unless --part names some.
  bool throughput = false;
  bool qmc = false;
  bool scaling = false;
  bool textures = false;
  bool measured = false;
  bool scalingRoom = false;
  bool atlas = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--part") == 0 && i + 1 < argc) {
      const std::string part = argv[++i];
      if (part == "throughput") {
        throughput = true;
      } else if (part == "qmc") {
        qmc = true;
      } else if (part == "scaling") {
        scaling = true;
      } else if (part == "textures") {
        textures = true;
      } else if (part == "measured") {
        measured = true;
      } else if (part == "scaling-room") {
        scalingRoom = true;
      } else if (part == "atlas") {
        atlas = true;
      } else {
        std::fprintf(stderr, "fly-bench-baker: unknown part '%s'; use throughput, qmc, scaling, scaling-room, textures, measured or atlas\n",
                     part.c_str());
        return 2;
      }
    } else {
      std::fprintf(stderr,
                   "fly-bench-baker: unknown option '%s'; usage: fly-bench-baker [--quick] "
                   "[--part throughput|qmc|scaling|scaling-room|textures|measured|atlas]...\n",
                   argv[i]);
      return 2;
    }
  }
  if (!throughput && !qmc && !scaling && !textures && !measured && !scalingRoom && !atlas) {
    throughput = qmc = scaling = textures = measured = scalingRoom = atlas = true;
  }
  const uint32_t threads = std::max(1u, std::thread::hardware_concurrency());
  if (throughput) {
    fly::raytracer::benchThroughput(threads, "open ground with boxes",
                                    fly::raytracer::makeScene(fly::raytracer::cellsFor(10000)));
    fly::raytracer::benchThroughput(threads, "room lit through a window",
                                    fly::raytracer::makeRoomScene(10000));
  }
  if (qmc) {
    fly::raytracer::benchQmc(threads, quick, fly::raytracer::kPathLengthGuard);
    fly::raytracer::benchQmc(threads, quick, 1);
    fly::raytracer::benchQmc(threads, quick, 0);
  }
  if (scaling) fly::raytracer::benchScaling(threads, quick);
  if (textures) fly::raytracer::benchTextures(threads);
  if (measured) fly::raytracer::benchMeasured(threads);
  if (scalingRoom) fly::raytracer::benchScalingRoom(threads, quick);
  if (atlas) fly::raytracer::benchAtlas(threads, quick);
  return 0;
}
