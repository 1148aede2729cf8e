#include "raytracer/light_paths.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>

#include "raytracer/sampler.h"
#include "raytracer/surface_point.h"
#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

// Russian roulette from this surface vertex on (the first hit is vertex 1), as the integrator's paths.
constexpr uint32_t kFirstRouletteHit = 3;

// The least cosine between the shading normal and the arrival direction (the integrator's kMinShadingCos):
// the shading normal is bent towards the geometric one until the arrival direction is this far above it.
constexpr float kMinShadingCos = 0.01f;

// The share of paths launched through window panes when the scene has any (SunLightPaths::panes_), and the
// most pane triangles for which that is done (each launch density tests them all).
constexpr float kPaneLaunchFraction = 0.5f;
constexpr size_t kMaxLaunchPanes = 256;

// The sampler group of a path's launch choice (window pane or disc), far above the scattering groups.
constexpr uint32_t kLaunchGroup = 1u << 21;

// Paths traced by one task: its deposits stay in memory until they are added in path order.
constexpr uint32_t kPathsPerChunk = 2048;

}  // namespace

SunLightPaths::SunLightPaths(const rdb::TraceRdb& rdb, const EmbreeScene& scene, const Integrator& integrator)
    : rdb_(rdb), scene_(scene), integrator_(integrator) {
  const size_t vertexCount = rdb.positionsM.size();
  hatAreaM2_.assign(vertexCount, 0.0f);
  for (uint32_t t = 0; t < rdb.triangleCount(); ++t) {
    const float area = scene.triangleAreaM2(t);
    if (!(area > 0.0f) || !std::isfinite(area)) continue;
    for (size_t c = 0; c < 3; ++c) hatAreaM2_[rdb.indices[3 * size_t{t} + c]] += area / 3.0f;
  }
  twoSided_.assign(vertexCount, 0);
  for (const rdb::TraceMesh& mesh : rdb.meshes) {
    if (!mesh.twoSided) continue;
    const size_t end = std::min<size_t>(size_t{mesh.firstVertex} + mesh.vertexCount, vertexCount);
    for (size_t v = mesh.firstVertex; v < end; ++v) twoSided_[v] = 1;
  }
  vec3 lo(std::numeric_limits<float>::infinity());
  vec3 hi(-std::numeric_limits<float>::infinity());
  for (const vec3& p : rdb.positionsM) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (vertexCount == 0) lo = hi = vec3(0.0f);
  centreM_ = 0.5f * (lo + hi);
  const float radiusM = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  // The disc lies 2 radii from the centre towards the sun; a direction up to θ_s off the axis shifts the
  // bounding sphere's shadow on it by at most 3 radii · tan θ_s.
  launchDistanceM_ = 2.0f * radiusM;
  const float tanSun = std::tan(std::min(rdb.sun.halfAngleRad, 0.5f));
  discRadiusM_ = radiusM * (1.0f + 3.0f * tanSun) * 1.001f;

  if (!integrator.hasSun()) return;
  double total = 0.0;
  for (uint32_t t = 0; t < rdb.triangleCount(); ++t) {
    const uint32_t mi = rdb.triangleMaterial[t];
    if (!integrator.frontBsdfs_[mi].hasClearTransmission()) continue;
    const float seen =
        scene.triangleAreaM2(t) * std::abs(glm::dot(scene.triangleNormal(t), rdb.sun.directionWorld));
    if (!(seen > 0.0f) || !std::isfinite(seen)) continue;
    panes_.push_back(t);
    total += seen;
    paneCdf_.push_back(static_cast<float>(total));
  }
  if (panes_.size() > kMaxLaunchPanes || !(total > 0.0)) {
    panes_.clear();
    paneCdf_.clear();
    return;
  }
  float below = 0.0f;
  for (float& c : paneCdf_) {
    c = static_cast<float>(c / total);
    paneProbability_.push_back(c - below);
    below = c;
  }
  paneCdf_.back() = 1.0f;
}

float SunLightPaths::launchDensity(const vec3& x, const vec3& towardsSun) const {
  const float disc = 1.0f / (kPiF * discRadiusM_ * discRadiusM_);
  if (panes_.empty()) return disc;
  // A pane point q maps to the disc point x = q + u·towardsSun: dA_disc = dA_pane |n·ω| / |s·ω| (s the disc's
  // normal, the sun's axis).
  const float cosAxis = std::abs(glm::dot(rdb_.sun.directionWorld, towardsSun));
  float pane = 0.0f;
  for (size_t i = 0; i < panes_.size(); ++i) {
    const uint32_t t = panes_[i];
    const vec3& p0 = rdb_.positionsM[rdb_.indices[3 * size_t{t}]];
    const vec3 e1 = rdb_.positionsM[rdb_.indices[3 * size_t{t} + 1]] - p0;
    const vec3 e2 = rdb_.positionsM[rdb_.indices[3 * size_t{t} + 2]] - p0;
    // The line x + u·towardsSun against the triangle (Möller–Trumbore, any u).
    const vec3 h = glm::cross(towardsSun, e2);
    const float a = glm::dot(e1, h);
    if (!(std::abs(a) > 0.0f)) continue;
    const vec3 sv = x - p0;
    const float b1 = glm::dot(sv, h) / a;
    if (b1 < 0.0f || b1 > 1.0f) continue;
    const vec3 qv = glm::cross(sv, e1);
    const float b2 = glm::dot(towardsSun, qv) / a;
    if (b2 < 0.0f || b1 + b2 > 1.0f) continue;
    const float cosPane = std::abs(glm::dot(scene_.triangleNormal(t), towardsSun));
    if (cosPane > 0.0f) pane += paneProbability_[i] * cosAxis / (scene_.triangleAreaM2(t) * cosPane);
  }
  return (1.0f - kPaneLaunchFraction) * disc + kPaneLaunchFraction * pane;
}

void SunLightPaths::deposit(uint32_t t, const vec2& barycentric, const vec3& dir, const Rgb& fluxLm,
                            bool reflected, std::vector<Deposit>& out) const {
  const vec3& ng = scene_.triangleNormal(t);
  const float cosGeometric = std::abs(glm::dot(ng, dir));
  if (!(cosGeometric > 0.0f)) return;
  const float b[3] = {1.0f - barycentric.x - barycentric.y, barycentric.x, barycentric.y};
  vec3 interpolated(0.0f);
  for (size_t k = 0; k < 3; ++k) interpolated += b[k] * rdb_.normals[rdb_.indices[3 * size_t{t} + k]];
  for (size_t k = 0; k < 3; ++k) {
    const uint32_t v = rdb_.indices[3 * size_t{t} + k];
    if (!(hatAreaM2_[v] > 0.0f) || !(b[k] > 0.0f)) continue;
    // The vertex's sides as the baker's sensor has them (baker.cpp, OneRingSource::sampleAt): the front is
    // the geometric normal's side towards the vertex normal; the sensor's normal is the interpolated one,
    // or that geometric normal where it is degenerate or points to the other side.
    const vec3 ngFront = glm::dot(ng, rdb_.normals[v]) >= 0.0f ? ng : -ng;
    const bool back = glm::dot(ngFront, dir) > 0.0f;  // the light arrives travelling into the front
    if (back && !twoSided_[v]) continue;
    vec3 n = glm::dot(interpolated, interpolated) > 0.0f ? glm::normalize(interpolated) : ngFront;
    if (!(glm::dot(n, ngFront) > 0.0f)) n = ngFront;
    if (back) n = -n;
    const float cosSensor = -glm::dot(n, dir);
    if (!(cosSensor > 0.0f)) continue;
    const float weight = b[k] * cosSensor / (cosGeometric * hatAreaM2_[v]);
    out.push_back({4 * v + (back ? 2u : 0u) + (reflected ? 1u : 0u), fluxLm * weight});
  }
}

void SunLightPaths::tracePath(uint64_t batchSeed, uint32_t index, float areaPerPathM2,
                              std::vector<Deposit>& out, uint64_t& rays) const {
  const rdb::TraceSun& sun = rdb_.sun;
  const Onb sunFrame = onb(sun.directionWorld);
  SobolSampler sampler(batchSeed);
  sampler.startSample(index);
  sampler.startGroup(0);
  const vec2 disc = discRadiusM_ * sampleConcentricDisk(sampler.next2D());
  // Cosine-weighted in the cone: a uniform point of the cone's projected disc of radius sin θ_s.
  const vec2 cone = std::sin(sun.halfAngleRad) * sampleConcentricDisk(sampler.next2D());
  const vec3 towardsSun = glm::normalize(
      sunFrame.toWorld(vec3(cone.x, cone.y, std::sqrt(std::max(0.0f, 1.0f - glm::dot(cone, cone))))));
  const vec3 discCentre = centreM_ + launchDistanceM_ * sun.directionWorld;
  vec3 origin = discCentre + sunFrame.toWorld(vec3(disc.x, disc.y, 0.0f));
  if (!panes_.empty()) {
    sampler.startGroup(kLaunchGroup);
    const float uChoice = sampler.next1D();
    const float uPane = sampler.next1D();
    const vec2 uPoint = sampler.next2D();
    if (uChoice < kPaneLaunchFraction) {
      const size_t i = std::min<size_t>(
          static_cast<size_t>(std::upper_bound(paneCdf_.begin(), paneCdf_.end(), uPane) - paneCdf_.begin()),
          panes_.size() - 1);
      const uint32_t t = panes_[i];
      const vec3 b = sampleUniformTriangle(uPoint);
      const vec3 q = b.x * rdb_.positionsM[rdb_.indices[3 * size_t{t}]] +
                     b.y * rdb_.positionsM[rdb_.indices[3 * size_t{t} + 1]] +
                     b.z * rdb_.positionsM[rdb_.indices[3 * size_t{t} + 2]];
      // Back along the path's direction to the disc's plane.
      const float u = glm::dot(discCentre - q, sun.directionWorld) / glm::dot(towardsSun, sun.directionWorld);
      origin = q + u * towardsSun;
    }
  }
  vec3 dir = -towardsSun;
  // areaPerPathM2 = A_disc / N, so E_n / (N p(x)) = E_n · areaPerPathM2 / (A_disc p(x)).
  const float density = launchDensity(origin, towardsSun);
  Rgb flux = sun.normalIlluminanceLux * areaPerPathM2 / (kPiF * discRadiusM_ * discRadiusM_ * density);
  bool reflected = false;
  std::optional<Bsdf> pointBsdf, pointDeltaLightBsdf;
  for (uint32_t hitIndex = 1; hitIndex <= kPathLengthGuard; ++hitIndex) {
    ++rays;
    const std::optional<Hit> hit = scene_.intersect(origin, dir, std::numeric_limits<float>::infinity());
    if (!hit) break;
    const uint32_t t = hit->triangle;
    deposit(t, hit->barycentric, dir, flux, reflected, out);

    const bool front = glm::dot(hit->geometricNormal, dir) < 0.0f;
    const uint32_t mi = rdb_.triangleMaterial[t];
    const rdb::TraceMaterial& m = rdb_.materials[mi];
    const TrianglePoint at{t, hit->barycentric};
    // The first scattering of the sun's light by the Bsdf that the gathering estimator's sun samples use
    // (regularised without caustics: Vertex::deltaLightBsdf), every later one by the surface's own, as a
    // gathering path scatters at the vertices before the one that samples the sun.
    const Integrator::PointBsdfs bsdfs = integrator_.bsdfsAt(mi, front, at, pointBsdf, pointDeltaLightBsdf);
    const Bsdf& bsdf = reflected ? *bsdfs.bsdf : *bsdfs.deltaLight;
    if (bsdf.isBlack()) break;
    const vec3 side = front ? hit->geometricNormal : -hit->geometricNormal;
    const float cosGeometric = -glm::dot(side, dir);
    if (!(cosGeometric > 0.0f)) break;
    // The shading normal as the integrator bends it (integrator.cpp).
    vec3 ns = shadingNormalAt(rdb_, m, at, hit->geometricNormal);
    if (!front) ns = -ns;
    const float cosShading = -glm::dot(ns, dir);
    if (cosShading < kMinShadingCos)
      ns = glm::normalize(ns + ((kMinShadingCos - cosShading) / cosGeometric) * side);
    const Onb frame = shadingFrameAt(rdb_, m, at, ns, front);
    // ωo points back towards where the light came from; the sampled ωi is where it goes.
    const vec3 wo = frame.toLocal(-dir);
    if (!(wo.z > 0.0f)) break;

    sampler.startGroup(hitIndex);
    const vec2 uContinue = sampler.next2D();
    const float uLobe = sampler.next1D();
    const float uRoulette = sampler.next1D();
    if (hitIndex >= kFirstRouletteHit) {
      const float q = std::min(1.0f, maxComponent(bsdf.albedo(wo.z)) * maxComponent(flux) /
                                         maxComponent(sun.normalIlluminanceLux * areaPerPathM2));
      if (!(uRoulette < q)) break;
      flux /= q;
    }
    vec3 d;
    if (bsdf.isLambertian()) {
      const vec3 wi = sampleCosineHemisphere(uContinue);
      if (!(wi.z > 0.0f)) break;
      d = glm::normalize(frame.toWorld(wi));
      if (!(glm::dot(d, side) > 0.0f)) break;
      flux *= bsdf.lambertAlbedo();
      reflected = true;
    } else {
      Bsdf::Sample s;
      if (!bsdf.sample(wo, uLobe, uContinue, s)) break;
      d = glm::normalize(frame.toWorld(s.wi));
      if (s.lobe != Bsdf::Lobe::kStraight) {
        if ((glm::dot(d, side) > 0.0f) != (s.wi.z > 0.0f)) break;
        reflected = true;
      }
      flux *= s.weight;
    }
    // The adjoint correction for shading normals (1 where they agree with the geometric normal).
    const float cosInShading = std::abs(glm::dot(ns, d));
    if (!(cosInShading > 0.0f)) break;
    flux *= (wo.z * std::abs(glm::dot(side, d))) / (cosGeometric * cosInShading);
    if (!(maxComponent(flux) > 0.0f) || !std::isfinite(maxComponent(flux))) break;
    const vec3 x = integrator_.hitPoint(*hit);
    origin = offsetRayOrigin(x, glm::dot(side, d) > 0.0f ? side : -side,
                             std::max(maxAbs(x), scene_.triangleMagnitudeM(t)));
    dir = d;
  }
}

LightPathMaps SunLightPaths::trace(const LightPathSettings& settings) const {
  const auto start = std::chrono::steady_clock::now();
  const size_t vertexCount = rdb_.positionsM.size();
  LightPathMaps maps;
  for (std::vector<Rgb>* m :
       {&maps.frontDirectLux, &maps.frontDirectStdErrorLux, &maps.backDirectLux, &maps.backDirectStdErrorLux,
        &maps.frontReflectedLux, &maps.frontReflectedStdErrorLux, &maps.backReflectedLux,
        &maps.backReflectedStdErrorLux}) {
    m->assign(vertexCount, Rgb(0.0f));
  }
  if (!hasSun() || settings.pathsPerBatch == 0 || settings.batches == 0) return maps;
  const uint32_t threads =
      settings.threads > 0 ? settings.threads : std::max(1u, std::thread::hardware_concurrency());
  const float areaPerPathM2 = kPiF * discRadiusM_ * discRadiusM_ / static_cast<float>(settings.pathsPerBatch);
  const size_t slots = 4 * vertexCount;
  std::vector<double> batchSum(3 * slots), sum(3 * slots, 0.0), sumSq(3 * slots, 0.0);
  const uint32_t chunks = (settings.pathsPerBatch + kPathsPerChunk - 1) / kPathsPerChunk;
  // Chunks traced at a time before their deposits are added (bounds the memory of deposits).
  const uint32_t window = std::max(1u, 4 * threads);
  std::vector<std::vector<Deposit>> deposits(window);
  std::vector<uint64_t> chunkRays(window);
  for (uint32_t b = 0; b < settings.batches; ++b) {
    const uint64_t batchSeed = settings.seed + b;
    std::fill(batchSum.begin(), batchSum.end(), 0.0);
    for (uint32_t first = 0; first < chunks; first += window) {
      const uint32_t count = std::min(window, chunks - first);
      std::atomic<uint32_t> next{0};
      auto work = [&] {
        for (uint32_t c; (c = next.fetch_add(1)) < count;) {
          deposits[c].clear();
          chunkRays[c] = 0;
          const uint32_t begin = (first + c) * kPathsPerChunk;
          const uint32_t end = std::min(settings.pathsPerBatch, begin + kPathsPerChunk);
          for (uint32_t i = begin; i < end; ++i)
            tracePath(batchSeed, i, areaPerPathM2, deposits[c], chunkRays[c]);
        }
      };
      std::vector<std::thread> pool;
      for (uint32_t k = 1; k < std::min(threads, count); ++k) pool.emplace_back(work);
      work();
      for (std::thread& th : pool) th.join();
      for (uint32_t c = 0; c < count; ++c) {
        maps.rays += chunkRays[c];
        for (const Deposit& d : deposits[c]) {
          for (size_t ch = 0; ch < 3; ++ch) batchSum[3 * size_t{d.slot} + ch] += double{d.lux[int(ch)]};
        }
      }
    }
    for (size_t i = 0; i < batchSum.size(); ++i) {
      sum[i] += batchSum[i];
      sumSq[i] += batchSum[i] * batchSum[i];
    }
  }
  const double n = settings.batches;
  std::vector<Rgb>* means[4] = {&maps.frontDirectLux, &maps.frontReflectedLux, &maps.backDirectLux,
                                &maps.backReflectedLux};
  std::vector<Rgb>* errors[4] = {&maps.frontDirectStdErrorLux, &maps.frontReflectedStdErrorLux,
                                 &maps.backDirectStdErrorLux, &maps.backReflectedStdErrorLux};
  for (size_t v = 0; v < vertexCount; ++v) {
    for (size_t s = 0; s < 4; ++s) {
      for (size_t ch = 0; ch < 3; ++ch) {
        const size_t i = 3 * (4 * v + s) + ch;
        const double mean = sum[i] / n;
        const double variance = n > 1.0 ? std::max(0.0, (sumSq[i] - n * mean * mean) / (n - 1.0)) : 0.0;
        (*means[s])[v][int(ch)] = static_cast<float>(mean);
        (*errors[s])[v][int(ch)] = static_cast<float>(std::sqrt(variance / n));
      }
    }
  }
  maps.paths = uint64_t{settings.pathsPerBatch} * settings.batches;
  maps.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return maps;
}

}  // namespace fly::raytracer
