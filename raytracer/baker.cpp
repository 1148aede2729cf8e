#include "raytracer/baker.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <span>
#include <thread>
#include <utility>

#include "raytracer/enclosure.h"
#include "raytracer/sampler.h"
#include "rdb/vertex_weld.h"
#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

// The sampler group that places a sample in its vertex's one-ring, far above the integrator's groups
// (3 per path vertex from group 0, at most 3 · kPathLengthGuard of them), and ≡ 31 mod 32: the sampler keeps
// its seeds in a slot that only a path's 11th vertex shares (SobolSampler's group cache).
constexpr uint32_t kOneRingGroup = (1u << 20) + 31;

// In OneRingSource's ring entries: the triangle's two corners other than the vertex's, c + 1 and c + 2 mod 3,
// turn against the ring's order, so that sampling takes them as (c + 2, c + 1).
constexpr uint8_t kReversedCorners = 4;

// The barycentric coordinate b of a triangle's corner under the density 3b / A (the hat function of that
// corner, normalised: ∫ b dA = A / 3), by inversion. A uniform point on a triangle is Dirichlet(1, 1, 1) in
// its barycentrics; weighting by b makes it Dirichlet(2, 1, 1), whose b is Beta(2, 2) (Devroye, "Non-Uniform
// Random Variate Generation", 1986, ch. XI.4): density 6b(1 − b), CDF F(b) = 3b² − 2b³. With b = 1/2 + x,
// F = u reads 4x³ − 3x = 1 − 2u, and Viète's trigonometric solution (sin 3φ = 3 sin φ − 4 sin³ φ) gives its
// root in [−1/2, 1/2] as x = sin(asin(2u − 1) / 3). Given b the density is constant on the segment of
// constant b, so the other two coordinates split 1 − b uniformly.
// asin(2u − 1) / 3 lies in [−π/6, π/6], where sinCosQuarterPi needs no range reduction.
float sampleHatBarycentric(float u) {
  return 0.5f + sinCosQuarterPi(asinApprox(2.0f * u - 1.0f) / 3.0f).x;
}

// A number in [0, 4) that grows with the angle of d from +x counter-clockwise (the "diamond angle": the
// position along the unit diamond |x| + |y| = 1), for sorting by angle without trigonometry; 0 for d = 0.
float pseudoAngle(const vec2& d) {
  const float l1 = std::abs(d.x) + std::abs(d.y);
  if (!(l1 > 0.0f)) return 0.0f;
  const float x = d.x / l1;
  const float y = d.y / l1;
  if (y >= 0.0f) return x >= 0.0f ? y : 1.0f - x;
  return x < 0.0f ? 2.0f - y : 3.0f + x;
}

// The baker's points: every vertex with a valid one-ring, on its front, then on its back where its mesh is
// two-sided.
class OneRingSource final : public SampleSourceOf<OneRingSource> {
  friend SampleSourceOf<OneRingSource>;

 public:
  // weld: coincident vertices of a mesh with equal normals are one point (rdb/vertex_weld.h), whose ring is
  // the union of theirs; off, every vertex is a point of its own.
  OneRingSource(const rdb::TraceRdb& rdb, const EmbreeScene& scene, const Integrator& integrator, bool weld)
      : rdb_(rdb), scene_(scene), integrator_(integrator) {
    const size_t vertexCount = rdb.positionsM.size();
    weldRep_.resize(vertexCount);
    std::iota(weldRep_.begin(), weldRep_.end(), 0u);
    if (weld && !rdb.normals.empty()) {
      for (const rdb::TraceMesh& mesh : rdb.meshes) {
        if (size_t{mesh.firstVertex} + mesh.vertexCount > vertexCount) continue;
        const auto positions = std::span<const vec3>(rdb.positionsM).subspan(mesh.firstVertex, mesh.vertexCount);
        Bounds3 bounds;
        for (const vec3& p : positions) bounds.extend(p);
        const std::vector<uint32_t> rep = rdb::weldCoincidentVertices(
            positions, std::span<const vec3>(rdb.normals).subspan(mesh.firstVertex, mesh.vertexCount),
            rdb::weldToleranceM(glm::length(bounds.max - bounds.min)));
        for (uint32_t i = 0; i < mesh.vertexCount; ++i) weldRep_[mesh.firstVertex + i] = mesh.firstVertex + rep[i];
      }
    }
    // The one-rings in compressed rows: every triangle of non-zero area once per corner, in the ring of the
    // corner's welded point.
    ringOffsets_.assign(vertexCount + 1, 0);
    for (size_t t = 0; t < rdb.triangleCount(); ++t) {
      if (!isValid(static_cast<uint32_t>(t))) continue;
      for (int c = 0; c < 3; ++c) ++ringOffsets_[weldRep_[rdb.indices[3 * t + static_cast<size_t>(c)]] + 1];
    }
    for (size_t v = 0; v < vertexCount; ++v) ringOffsets_[v + 1] += ringOffsets_[v];
    ringTriangles_.resize(ringOffsets_.back());
    ringCorners_.resize(ringOffsets_.back());
    ringCdfM2_.resize(ringOffsets_.back());
    std::vector<uint32_t> fill(ringOffsets_.begin(), ringOffsets_.end() - 1);
    for (uint32_t t = 0; t < rdb.triangleCount(); ++t) {
      if (!isValid(t)) continue;
      for (uint8_t c = 0; c < 3; ++c) {
        const uint32_t slot = fill[weldRep_[rdb.indices[3 * size_t{t} + c]]]++;
        ringTriangles_[slot] = t;
        ringCorners_[slot] = c;
      }
    }
    // Each ring in order of angle around its vertex, and each triangle's other two corners in the same
    // turning sense (sampleAt: the first sample coordinate then walks once around the vertex, continuously
    // across the edges that neighbouring triangles share).
    orderRingsAroundVertices();
    // Cumulative areas per ring, to pick a triangle by area: one flat array for all rings rather than a
    // Distribution1D (and its vectors) per vertex.
    for (size_t v = 0; v < vertexCount; ++v) {
      float sum = 0.0f;
      for (uint32_t j = ringOffsets_[v]; j < ringOffsets_[v + 1]; ++j) {
        sum += scene.triangleAreaM2(ringTriangles_[j]);
        ringCdfM2_[j] = sum;
      }
    }

    meshOfVertex_.assign(vertexCount, 0);
    for (uint32_t m = 0; m < rdb.meshes.size(); ++m) {
      const rdb::TraceMesh& mesh = rdb.meshes[m];
      const size_t end = std::min<size_t>(size_t{mesh.firstVertex} + mesh.vertexCount, vertexCount);
      for (size_t v = mesh.firstVertex; v < end; ++v) meshOfVertex_[v] = m;
    }
    twoSided_.assign(vertexCount, false);
    for (const rdb::TraceMesh& mesh : rdb.meshes) {
      if (!mesh.twoSided) continue;
      const size_t end = std::min<size_t>(size_t{mesh.firstVertex} + mesh.vertexCount, vertexCount);
      for (size_t v = mesh.firstVertex; v < end; ++v) twoSided_[v] = true;
    }
    for (uint32_t v = 0; v < vertexCount; ++v) {
      if (hasRing(v)) pointVertex_.push_back(v);
    }
    frontCount_ = pointVertex_.size();
    for (size_t i = 0; i < frontCount_; ++i) {
      if (twoSided_[pointVertex_[i]]) pointVertex_.push_back(pointVertex_[i]);
    }
    // Vertex sides inside closed objects (raytracer/enclosure.h), tested along the vertex's normal from
    // half-way between it and its ring's centroid: from a corner itself, rays slip out along the edges.
    hidden_.assign(pointVertex_.size(), 0);
    uint64_t rays = 0;
    const float reachM = enclosureReachM(rdb);
    for (size_t i = 0; i < pointVertex_.size(); ++i) {
      const uint32_t v = pointVertex_[i];
      const uint32_t t = ringTriangles_[ringOffsets_[v]];
      vec3 centroid(0.0f);
      for (uint32_t j = ringOffsets_[v]; j < ringOffsets_[v + 1]; ++j) {
        const uint32_t* c = &rdb.indices[3 * size_t{ringTriangles_[j]}];
        centroid += (rdb.positionsM[c[0]] + rdb.positionsM[c[1]] + rdb.positionsM[c[2]]) / 3.0f;
      }
      centroid /= float(ringOffsets_[v + 1] - ringOffsets_[v]);
      const vec3& ng = scene.triangleNormal(t);
      vec3 n = rdb.normals.empty() ? ng : rdb.normals[v];
      n = glm::dot(n, n) > 0.0f ? glm::normalize(n) : ng;
      if (isBack(i)) n = -n;
      const vec3 p = glm::mix(rdb.positionsM[v], centroid, 0.5f);
      hidden_[i] = isEnclosed(scene, p, n, scene.triangleMagnitudeM(t), reachM, rays) ? 1 : 0;
    }
  }

  size_t pointCount() const override { return pointVertex_.size(); }
  bool keepsSunDirect() const override { return integrator_.hasSun(); }
  bool isHidden(size_t point) const override { return hidden_[point] != 0; }
  // Per mesh, its fronts and its backs.
  uint32_t groupCount() const override {
    return 2 * std::max<uint32_t>(1, static_cast<uint32_t>(rdb_.meshes.size()));
  }
  uint32_t groupOf(size_t point) const override {
    return 2 * meshOfVertex_[pointVertex_[point]] + (isBack(point) ? 1 : 0);
  }

  // Per point, the weight w of the light paths' estimate of the sun's reflected light
  // (LightPathBakeSettings): the samples become G − w S_G. Empty (or 0) for the gathering estimate alone.
  void setSunReflectedWeights(std::vector<float> weights) { sunReflectedWeights_ = std::move(weights); }

  // One gathering sample of point `point` with the sun's reflected part S_G apart (sunReflectedLux), for the
  // pilot of the combination.
  template <class S>
  Rgb sampleSplit(size_t point, S& sampler, uint64_t& rays, Rgb& sunReflectedLux) const {
    Rgb sunLux(0.0f);
    const PointSample sample = sampleWith(point, sampler, rays, &sunLux);
    sunReflectedLux = sunLux - sample.sunDirectLux;
    return sample.lux;
  }

  bool hasRing(uint32_t v) const { return ringOffsets_[v + 1] > ringOffsets_[v]; }
  // The vertex whose point carries v's values (v itself unless welded to a lower-numbered vertex).
  uint32_t weldedTo(uint32_t v) const { return weldRep_[v]; }
  bool isTwoSided(uint32_t v) const { return twoSided_[v]; }
  uint32_t pointVertex(size_t point) const { return pointVertex_[point]; }
  bool isBack(size_t point) const { return point >= frontCount_; }

 private:
  // Sorts every ring's entries by the angle of their triangle's centroid around the vertex, in the plane
  // normal to the sum of the ring's (area-weighted) triangle normals, and marks the entries whose two other
  // corners, taken in the order (c + 1, c + 2), turn the other way (kReversedCorners). Any order samples the
  // same density; this one makes sampleAt's map from the unit square onto the ring continuous across shared
  // edges, so that stratified samples stay stratified on the ring.
  void orderRingsAroundVertices() {
    std::vector<std::pair<float, uint32_t>> order;
    std::vector<uint32_t> triangles;
    std::vector<uint8_t> corners;
    for (size_t v = 0; v < rdb_.positionsM.size(); ++v) {
      const uint32_t begin = ringOffsets_[v];
      const uint32_t end = ringOffsets_[v + 1];
      if (end - begin < 2) continue;
      const vec3& pv = rdb_.positionsM[v];
      auto corner = [&](uint32_t t, uint32_t k) {
        return rdb_.positionsM[rdb_.indices[3 * size_t{t} + k % 3]];
      };
      vec3 axis(0.0f);
      for (uint32_t j = begin; j < end; ++j) {
        const uint32_t t = ringTriangles_[j];
        axis += glm::cross(corner(t, 1) - corner(t, 0), corner(t, 2) - corner(t, 0));
      }
      // A fold whose normals cancel: any axis orders it (the order only affects stratification).
      const Onb frame = onb(glm::dot(axis, axis) > 0.0f ? glm::normalize(axis) : vec3(0.0f, 0.0f, 1.0f));
      auto local = [&](const vec3& p) {
        const vec3 l = frame.toLocal(p - pv);
        return vec2(l.x, l.y);
      };
      order.clear();
      for (uint32_t j = begin; j < end; ++j) {
        const uint32_t t = ringTriangles_[j];
        const uint32_t c = ringCorners_[j];
        const vec3 centroid = (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0f;
        order.emplace_back(pseudoAngle(local(centroid)), j);
        // From corner c + 1 to c + 2 should turn the way the angle grows (counter-clockwise in the frame).
        const vec2 a = local(corner(t, c + 1));
        const vec2 b = local(corner(t, c + 2));
        if (a.x * b.y - a.y * b.x < 0.0f) ringCorners_[j] = static_cast<uint8_t>(c | kReversedCorners);
      }
      std::stable_sort(order.begin(), order.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      triangles.clear();
      corners.clear();
      for (const auto& [unused, j] : order) {
        triangles.push_back(ringTriangles_[j]);
        corners.push_back(ringCorners_[j]);
      }
      std::copy(triangles.begin(), triangles.end(), ringTriangles_.begin() + begin);
      std::copy(corners.begin(), corners.end(), ringCorners_.begin() + begin);
    }
  }

  bool isValid(uint32_t t) const {
    const float area = scene_.triangleAreaM2(t);
    return area > 0.0f && std::isfinite(area) &&
           glm::dot(scene_.triangleNormal(t), scene_.triangleNormal(t)) > 0.0f;
  }

  // Irradiance at a point of the vertex's one-ring drawn with density b_v(x) / ∫ b_v dA over the ring (a
  // triangle by area, then the hat density 3 b_v / A in it), so that the mean of the samples is the
  // hat-weighted average ∫ b_v E dA / ∫ b_v dA.
  template <class S>
  PointSample sampleAt(size_t point, S& sampler, uint64_t& rays) const {
    const float w = sunReflectedWeights_.empty() ? 0.0f : sunReflectedWeights_[point];
    if (!(w > 0.0f)) return sampleWith(point, sampler, rays, nullptr);
    Rgb sunLux(0.0f);
    PointSample sample = sampleWith(point, sampler, rays, &sunLux);
    sample.lux -= w * (sunLux - sample.sunDirectLux);
    return sample;
  }

  // sunLux, when given, receives the sample's light from the sun (Integrator::sampleIrradiance).
  template <class S>
  PointSample sampleWith(size_t point, S& sampler, uint64_t& rays, Rgb* sunLux) const {
    const uint32_t v = pointVertex_[point];
    sampler.startGroup(kOneRingGroup);
    const vec2 u = sampler.next2D();
    const uint32_t begin = ringOffsets_[v];
    const uint32_t end = ringOffsets_[v + 1];
    const float x = u.x * ringCdfM2_[end - 1];
    // Entries whose sum is ≤ x, counted without branches (a ring has ~6; a branch per entry mispredicts).
    uint32_t j = begin;
    for (uint32_t k = begin; k + 1 < end; ++k) j += ringCdfM2_[k] <= x ? 1u : 0u;
    // The remainder of u.x within the chosen triangle's interval, uniform again: it places the point.
    const float below = j == begin ? 0.0f : ringCdfM2_[j - 1];
    const float s = std::clamp((x - below) / (ringCdfM2_[j] - below), 0.0f, 1.0f);
    const uint32_t t = ringTriangles_[j];
    const uint32_t c = ringCorners_[j] & 3u;
    const bool reversed = (ringCorners_[j] & kReversedCorners) != 0;

    // In the triangle (V, A, B), the point V + r ((1 − s)(A − V) + s (B − V)) has b_V = 1 − r, and dA ∝ r dr
    // ds: under the hat density ∝ b_V dA, s is uniform and b_V is Beta(2, 2) (sampleHatBarycentric). s runs
    // along the edge opposite V from one neighbour of the ring to the next (the angle around V), b_V from the
    // rim to V (the radius).
    const float bV = sampleHatBarycentric(u.y);
    const float bB = (1.0f - bV) * s;
    float b[3];
    b[c] = bV;
    b[(c + (reversed ? 2 : 1)) % 3] = std::max(0.0f, 1.0f - bV - bB);
    b[(c + (reversed ? 1 : 2)) % 3] = bB;
    vec3 p(0.0f);
    vec3 n(0.0f);
    for (size_t k = 0; k < 3; ++k) {
      const uint32_t vk = rdb_.indices[3 * size_t{t} + k];
      p += b[k] * rdb_.positionsM[vk];
      n += b[k] * rdb_.normals[vk];
    }
    n = glm::normalize(n);
    // The geometric normal on the side of the vertex's normal; it replaces a shading normal that is
    // degenerate or points to the other side of the surface.
    const vec3& ng = scene_.triangleNormal(t);
    const vec3 ngFront = glm::dot(ng, rdb_.normals[v]) >= 0.0f ? ng : -ng;
    if (!(glm::dot(n, ngFront) > 0.0f)) n = ngFront;
    if (isBack(point)) n = -n;
    PointSample sample;
    sample.lux = integrator_.sampleIrradiance(p, n, sampler, rays, scene_.triangleMagnitudeM(t),
                                              &sample.sunDirectLux, sunLux);
    return sample;
  }

  const rdb::TraceRdb& rdb_;
  const EmbreeScene& scene_;
  const Integrator& integrator_;
  std::vector<uint32_t> weldRep_;      // per vertex: weldedTo
  std::vector<uint32_t> ringOffsets_;  // vertex v's ring: entries ringOffsets_[v] … ringOffsets_[v + 1] − 1
  std::vector<uint32_t> ringTriangles_;
  // Which corner of the triangle the vertex is (bits 0–1), and kReversedCorners.
  std::vector<uint8_t> ringCorners_;
  std::vector<float> ringCdfM2_;        // the ring's areas summed up to and including this entry
  std::vector<bool> twoSided_;          // per vertex: of a two-sided mesh
  std::vector<uint32_t> meshOfVertex_;  // per vertex: its TraceMesh (0 for none)
  std::vector<uint32_t> pointVertex_;   // per point: the fronts, then the backs
  std::vector<uint8_t> hidden_;         // per point: inside a closed object (isHidden)
  size_t frontCount_ = 0;
  std::vector<float> sunReflectedWeights_;  // per point (setSunReflectedWeights)
};

// The pilot's relative standard error of the light paths' estimate at a point above which their variance
// there is taken as unknown and the point keeps the gathering estimate alone (weight 0). With 8 batches, a
// point reached by a handful of paths has a relative error near 1 and a spread that says little.
constexpr double kMaxPilotRelativeError = 0.25;

// The seed of the light paths of a bake of seed `seed`, and of the two pilots: scrambles of their own (the
// gathering samplers are seeded with seed + point).
uint64_t lightPathSeed(uint64_t seed, uint64_t stream) {
  return detail::mix64(seed ^ (0x6c69676874706174ull + stream));
}

// The combination's weight per vertex point (LightPathBakeSettings) from the pilots: `pilot.pilotSamples`
// gathering samples per point and light paths of their own seeds, in luminance.
std::vector<float> combinationWeights(const OneRingSource& source, const SunLightPaths& lightPaths,
                                      const BakeSettings& settings, uint64_t& paths, uint64_t& rays) {
  const LightPathBakeSettings& lp = settings.lightPaths;
  LightPathSettings pilotPaths;
  pilotPaths.pathsPerBatch = lp.pilotPathsPerBatch;
  pilotPaths.batches = 8;
  pilotPaths.seed = lightPathSeed(settings.estimate.seed, 1);
  pilotPaths.threads = settings.estimate.threads;
  const LightPathMaps pilot = lightPaths.trace(pilotPaths);
  paths += pilot.paths;
  rays += pilot.rays;
  // The light paths' variance of the mean at the bake's budget: the pilot's, scaled by the paths' ratio.
  const double pathRatio =
      double(pilot.paths) / (double(lp.paths.pathsPerBatch) * double(std::max(lp.paths.batches, 1u)));
  const double n = lp.plannedSamples > 0 ? lp.plannedSamples : settings.estimate.maxSamples;
  const size_t points = source.pointCount();
  std::vector<float> weights(points, 0.0f);
  const uint32_t threads = settings.estimate.threads > 0 ? settings.estimate.threads
                                                         : std::max(1u, std::thread::hardware_concurrency());
  std::atomic<size_t> next{0};
  std::vector<uint64_t> threadRays(threads, 0);
  const uint64_t pilotSeed = lightPathSeed(settings.estimate.seed, 2);
  auto work = [&](uint32_t k) {
    for (size_t i; (i = next.fetch_add(1)) < points;) {
      SobolSampler sampler(pilotSeed + i);
      double sumG = 0.0, sumS = 0.0, sumGS = 0.0, sumSS = 0.0;
      for (uint32_t j = 0; j < lp.pilotSamples; ++j) {
        sampler.startSample(j);
        Rgb sunReflected;
        const double g = luminance(source.sampleSplit(i, sampler, threadRays[k], sunReflected));
        const double sr = luminance(sunReflected);
        sumG += g;
        sumS += sr;
        sumGS += g * sr;
        sumSS += sr * sr;
      }
      const double m = lp.pilotSamples;
      if (m < 2.0) continue;
      const double covGS = (sumGS - sumG * sumS / m) / (m - 1.0);
      const double varS = (sumSS - sumS * sumS / m) / (m - 1.0);
      const uint32_t v = source.pointVertex(i);
      const bool back = source.isBack(i);
      const double meanL = luminance((back ? pilot.backReflectedLux : pilot.frontReflectedLux)[v]);
      const double se = luminance((back ? pilot.backReflectedStdErrorLux : pilot.frontReflectedStdErrorLux)[v]);
      // Where the pilot's paths reached the point too rarely for their spread to mean anything (a point that
      // no path reached has a spread of 0), the light paths' error is unknown: the gathering estimate alone.
      if (!(meanL > 0.0) || !(se < kMaxPilotRelativeError * meanL)) continue;
      const double varL = se * se * pathRatio;
      const double denominator = varS + n * varL;
      if (denominator > 0.0 && std::isfinite(covGS)) {
        weights[i] = static_cast<float>(std::clamp(covGS / denominator, 0.0, 1.0));
      }
    }
  };
  std::vector<std::thread> pool;
  for (uint32_t k = 1; k < threads; ++k) pool.emplace_back(work, k);
  work(0);
  for (std::thread& t : pool) t.join();
  for (uint64_t r : threadRays) rays += r;
  return weights;
}

// Vertices without a ring take the mean of their already known neighbours along the mesh's edges (all
// triangles, degenerate ones included; the back only on two-sided meshes), repeated until nothing changes;
// the rest stay 0. Every map of `maps` (front values and their errors, sun-direct parts) is filled alike.
// Returns their count.
size_t fillFromNeighbours(const rdb::TraceRdb& rdb, const OneRingSource& source, std::vector<bool>& known,
                          VertexLightMaps& maps) {
  const size_t vertexCount = known.size();
  struct Map {
    std::vector<Rgb>* values;
    bool back;
  };
  std::vector<Map> all;
  for (auto [values, back] : {std::pair{&maps.frontLux, false},
                              {&maps.frontStdErrorLux, false},
                              {&maps.backLux, true},
                              {&maps.backStdErrorLux, true},
                              {&maps.frontSunDirectLux, false},
                              {&maps.frontSunDirectStdErrorLux, false},
                              {&maps.backSunDirectLux, true},
                              {&maps.backSunDirectStdErrorLux, true},
                              {&maps.frontSunDirectSpreadLux, false},
                              {&maps.backSunDirectSpreadLux, true}}) {
    if (!values->empty()) all.push_back({values, back});
  }
  std::vector<std::vector<Rgb>> sums(all.size());
  for (;;) {
    for (std::vector<Rgb>& s : sums) s.assign(vertexCount, Rgb(0.0f));
    std::vector<uint32_t> counts(vertexCount, 0);
    for (size_t t = 0; t < rdb.triangleCount(); ++t) {
      for (size_t a = 0; a < 3; ++a) {
        for (size_t d = 1; d < 3; ++d) {
          const uint32_t to = rdb.indices[3 * t + a];
          const uint32_t from = rdb.indices[3 * t + (a + d) % 3];
          if (known[to] || !known[from]) continue;
          for (size_t m = 0; m < all.size(); ++m) sums[m][to] += (*all[m].values)[from];
          ++counts[to];
        }
      }
    }
    bool changed = false;
    for (size_t v = 0; v < vertexCount; ++v) {
      if (counts[v] == 0) continue;
      const float inv = 1.0f / static_cast<float>(counts[v]);
      const bool twoSided = source.isTwoSided(static_cast<uint32_t>(v));
      for (size_t m = 0; m < all.size(); ++m) {
        if (!all[m].back || twoSided) (*all[m].values)[v] = sums[m][v] * inv;
      }
      known[v] = true;
      changed = true;
    }
    if (!changed) break;
  }
  return static_cast<size_t>(std::count(known.begin(), known.end(), false));
}

// The vertex sides, then the texels: one set of points for one progressive run.
class JoinedSource final : public SampleSourceOf<JoinedSource> {
  friend SampleSourceOf<JoinedSource>;

 public:
  JoinedSource(const SampleSource& first, const SampleSource& second) : first_(first), second_(second) {}
  size_t pointCount() const override { return first_.pointCount() + second_.pointCount(); }
  uint32_t groupCount() const override { return first_.groupCount() + second_.groupCount(); }
  // Both sources use the same integrator, so they keep the sun's direct part alike.
  bool keepsSunDirect() const override { return first_.keepsSunDirect(); }
  bool isHidden(size_t point) const override {
    const size_t n = first_.pointCount();
    return point < n ? first_.isHidden(point) : second_.isHidden(point - n);
  }
  uint32_t groupOf(size_t point) const override {
    const size_t n = first_.pointCount();
    return point < n ? first_.groupOf(point) : first_.groupCount() + second_.groupOf(point - n);
  }

 private:
  template <class S>
  PointSample sampleAt(size_t point, S& sampler, uint64_t& rays) const {
    const size_t n = first_.pointCount();
    return point < n ? first_.sample(point, sampler, rays) : second_.sample(point - n, sampler, rays);
  }
  const SampleSource& first_;
  const SampleSource& second_;
};

// The nearest-rank 95th percentile of the relative standard error of luminance of the sun-direct part, over
// the points it reaches (mean > 0); 0 for none.
float sunDirectRelativeErrorP95(const std::vector<IrradianceEstimate>& points) {
  std::vector<float> rel;
  for (const IrradianceEstimate& e : points) {
    const float mean = luminance(e.sunDirectMeanLux);
    if (mean > 0.0f) rel.push_back(luminance(e.sunDirectStdErrorLux) / mean);
  }
  if (rel.empty()) return 0.0f;
  const size_t k = std::min(rel.size() - 1, static_cast<size_t>(std::ceil(0.95 * double(rel.size()))) - 1);
  std::nth_element(rel.begin(), rel.begin() + static_cast<std::ptrdiff_t>(k), rel.end());
  return rel[k];
}

}  // namespace

VertexLightMaps bakeVertexLightMaps(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                    const BakeSettings& settings, const BakeProgress& progress,
                                    const BakeCheckpointing& checkpointing) {
  const auto integratorStart = std::chrono::steady_clock::now();
  const Integrator integrator(rdb, scene, settings.integrator);
  // Welding would give a light path's deposit at one vertex to the ring of all: only for gathering alone.
  OneRingSource vertexSource(rdb, scene, integrator, !settings.lightPaths.enabled);
  VertexLightMaps maps;
  maps.litPatchCells = integrator.litPatchCells();
  maps.litPatchSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - integratorStart).count();
  // The light paths and the combination's weights: deterministic functions of the settings, so a resumed
  // bake computes them again alike.
  std::optional<LightPathMaps> lightPathMaps;
  std::vector<float> weights;
  // Reflection fog is gathered only: the light paths' scattering has no fog, so with it they would estimate
  // another quantity than the gathering's sun part (docs/light-paths.md).
  if (settings.lightPaths.enabled && integrator.hasSun() && !integrator.hasReflectionFog()) {
    const auto start = std::chrono::steady_clock::now();
    const SunLightPaths lightPaths(rdb, scene, integrator);
    weights = combinationWeights(vertexSource, lightPaths, settings, maps.lightPaths, maps.lightPathRays);
    LightPathSettings pathSettings = settings.lightPaths.paths;
    pathSettings.seed = lightPathSeed(settings.estimate.seed, 0);
    pathSettings.threads = settings.estimate.threads;
    lightPathMaps = lightPaths.trace(pathSettings);
    maps.lightPaths += lightPathMaps->paths;
    maps.lightPathRays += lightPathMaps->rays;
    for (float w : weights) {
      if (w > 0.0f) {
        ++maps.lightPathCombinedSides;
        maps.lightPathMeanWeight += w;
      }
    }
    if (maps.lightPathCombinedSides > 0) maps.lightPathMeanWeight /= double(maps.lightPathCombinedSides);
    vertexSource.setSunReflectedWeights(weights);
    maps.lightPathSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const TexelSource texelSource(rdb, scene, integrator);
  const JoinedSource source(vertexSource, texelSource);
  BakeCheckpoint localState;
  BakeCheckpoint& state = checkpointing.state ? *checkpointing.state : localState;
  if (state.progress.started()) maps.history = state.history;
  const PassCallback afterPass = [&](const EstimateResult& soFar, uint64_t passRays, double passSeconds) {
    ConvergencePoint point;
    point.seconds = soFar.seconds;
    point.samples = soFar.samplesPerPoint;
    point.relativeErrorP95 = soFar.relativeErrorP95;
    point.raysPerSecond = passSeconds > 0.0 ? static_cast<double>(passRays) / passSeconds : 0.0;
    point.trainingSeconds = maps.litPatchSeconds + maps.lightPathSeconds;
    if (source.keepsSunDirect()) point.sunDirectRelativeErrorP95 = sunDirectRelativeErrorP95(soFar.points);
    maps.history.push_back(point);
    state.history = maps.history;
    return !progress || progress(point, settings.estimate.maxSamples);
  };
  Checkpointing driverCheckpoints;
  if (checkpointing.save) {
    driverCheckpoints.intervalS = checkpointing.intervalS;
    driverCheckpoints.save = [&](const ProgressState&) { checkpointing.save(state); };
  }
  // The time limit bounds the training before the passes too.
  const double trainingS = maps.litPatchSeconds + maps.lightPathSeconds;
  EstimateSettings estimate = settings.estimate;
  if (std::isfinite(estimate.timeLimitS)) estimate.timeLimitS = std::max(0.0, estimate.timeLimitS - trainingS);
  const EstimateResult result =
      estimateProgressively(source, estimate, afterPass, state.progress, driverCheckpoints);

  const size_t vertexCount = rdb.positionsM.size();
  maps.frontLux.assign(vertexCount, Rgb(0.0f));
  maps.frontStdErrorLux.assign(vertexCount, Rgb(0.0f));
  maps.backLux.assign(vertexCount, Rgb(0.0f));
  maps.backStdErrorLux.assign(vertexCount, Rgb(0.0f));
  maps.frontSamples.assign(vertexCount, 0);
  const bool sun = source.keepsSunDirect();
  if (sun) {
    for (std::vector<Rgb>* m : {&maps.frontSunDirectLux, &maps.frontSunDirectStdErrorLux,
                                &maps.backSunDirectLux, &maps.backSunDirectStdErrorLux,
                                &maps.frontSunDirectSpreadLux, &maps.backSunDirectSpreadLux}) {
      m->assign(vertexCount, Rgb(0.0f));
    }
  }
  const size_t vertexPoints = vertexSource.pointCount();
  maps.hiddenVertexSides.assign(std::max<size_t>(1, rdb.meshes.size()), 0);
  for (size_t i = 0; i < vertexPoints; ++i) {
    const uint32_t v = vertexSource.pointVertex(i);
    const IrradianceEstimate& e = result.points[i];
    const bool back = vertexSource.isBack(i);
    Rgb meanLux = e.meanLux;
    Rgb stdErrorLux = e.stdErrorLux;
    if (lightPathMaps && weights[i] > 0.0f) {
      // G − w S_G + w S_L; the two estimates are independent, so their variances add. Noise can take the
      // sum below 0 where the light is faint; it is clamped there.
      const float w = weights[i];
      const Rgb& sL = (back ? lightPathMaps->backReflectedLux : lightPathMaps->frontReflectedLux)[v];
      const Rgb& sLError =
          (back ? lightPathMaps->backReflectedStdErrorLux : lightPathMaps->frontReflectedStdErrorLux)[v];
      meanLux = glm::max(meanLux + w * sL, Rgb(0.0f));
      stdErrorLux = glm::sqrt(stdErrorLux * stdErrorLux + (w * w) * sLError * sLError);
    }
    (back ? maps.backLux : maps.frontLux)[v] = meanLux;
    (back ? maps.backStdErrorLux : maps.frontStdErrorLux)[v] = stdErrorLux;
    if (sun) {
      (back ? maps.backSunDirectLux : maps.frontSunDirectLux)[v] = e.sunDirectMeanLux;
      (back ? maps.backSunDirectStdErrorLux : maps.frontSunDirectStdErrorLux)[v] = e.sunDirectStdErrorLux;
      (back ? maps.backSunDirectSpreadLux : maps.frontSunDirectSpreadLux)[v] = e.sunDirectSpreadLux;
    }
    if (!back) maps.frontSamples[v] = e.samples;
    if (vertexSource.isHidden(i)) ++maps.hiddenVertexSides[vertexSource.groupOf(i) / 2];
  }
  // Welded vertices take their point's values.
  for (uint32_t v = 0; v < vertexCount; ++v) {
    const uint32_t r = vertexSource.weldedTo(v);
    if (r == v) continue;
    for (std::vector<Rgb>* m : {&maps.frontLux, &maps.frontStdErrorLux, &maps.backLux, &maps.backStdErrorLux,
                                &maps.frontSunDirectLux, &maps.frontSunDirectStdErrorLux, &maps.backSunDirectLux,
                                &maps.backSunDirectStdErrorLux, &maps.frontSunDirectSpreadLux,
                                &maps.backSunDirectSpreadLux}) {
      if (!m->empty()) (*m)[v] = (*m)[r];
    }
    maps.frontSamples[v] = maps.frontSamples[r];
  }
  std::vector<bool> known(vertexCount);
  for (uint32_t v = 0; v < vertexCount; ++v) known[v] = vertexSource.hasRing(vertexSource.weldedTo(v));
  maps.unfilledVertices = fillFromNeighbours(rdb, vertexSource, known, maps);
  maps.lightTextures =
      texelSource.finish(std::span<const IrradianceEstimate>(result.points).subspan(vertexPoints));
  maps.samplesPerVertex = result.samplesPerPoint;
  maps.replicates = result.replicates;
  maps.rays = result.rays;
  maps.seconds = result.seconds;
  return maps;
}

}  // namespace fly::raytracer
