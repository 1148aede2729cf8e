// Monte-Carlo irradiance at points: the sensor of `fly illuminance` and, later, the baker's vertices and
// texels.
//
// E(p, n) = ∫_{H(n)} L_i(p, ω) cos θ dω (lux), by path tracing on Lambertian surfaces (Kajiya, "The rendering
// equation", SIGGRAPH 1986) with next-event estimation at every vertex.
//
// The sun: a disc of uniform radiance E_n / (π sin² θ_s), so that a surface facing it receives E_n, sampled
// uniformly in its cone; only by next-event estimation (a cosine-sampled ray that escapes sees the sky table,
// which holds no sun).
//
// The sky table: importance-sampled by a Distribution2D over its equal-area cells weighted by luminance, and
// combined with cosine sampling by multiple importance sampling with the power heuristic, β = 2 (Veach &
// Guibas, "Optimally combining sampling techniques for Monte Carlo rendering", SIGGRAPH 1995).
//
// Emissive triangles: one chosen by area × luminance (× 2 when double-sided), a point uniform on it, its
// density converted to solid angle by dω = |cos θ_light| dA / r² (Pharr, Jakob & Humphreys, "Physically Based
// Rendering", 4th ed., ch. 4), and combined with cosine sampling likewise.
//
// Punctual lights: every one, deterministically (they are deltas).
//
// Indirect light: cosine-sampled continuation, albedo = TraceMaterial::diffuse. Russian roulette from bounce
// 2 on, with survival probability q = min(1, max component of the path's throughput relative to the sensor's)
// and weight 1/q (as pbrt-v4's PathIntegrator): unbiased, and in a closed room of albedo ρ the throughput
// stays at 1 while a path survives each bounce with probability ρ, so the variance stays bounded even at ρ =
// 0.99. (A survival probability capped below ρ², e.g. min(ρ, 0.95) at ρ = 0.99, would let weights grow faster
// than paths die: infinite variance.)
//
// Not yet: specular reflection and transmission (glass), shading normals (surfaces shade with their geometric
// normal), light selection by power for many punctual lights.
//
// Sides: the sensor integrates the hemisphere of n (pass −n for the back side of a two-sided surface). A path
// that reaches the back face of a one-sided material ends there: it blocks light and reflects none. A
// double-sided material reflects and emits on both faces.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "raytracer/distribution.h"
#include "raytracer/embree_scene.h"
#include "raytracer/progressive.h"
#include "raytracer/sampler.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// Longest path ever traced, whatever the settings: a guard against albedo 1 in a closed room, never reached
// by Russian roulette otherwise (at ρ = 0.99 a path is this long with probability 0.99^10000 ≈ 2·10⁻⁴⁴).
inline constexpr uint32_t kPathLengthGuard = 10000;

struct IntegratorSettings {
  // Reflections of indirect light, ≥ 0 (0 = direct light only). Paths end by Russian roulette long before the
  // default; kPathLengthGuard caps it.
  uint32_t maxBounces = kPathLengthGuard;
};

class Integrator {
 public:
  // Keeps references to rdb and scene, which must outlive it. Throws std::invalid_argument when the sky
  // table's size is not resolution², or a material index is out of range.
  Integrator(const rdb::TraceRdb& rdb, const EmbreeScene& scene, IntegratorSettings settings = {});

  // One sample of the irradiance in lux at p (world, metres) on the side of unit normal n. The caller starts
  // the sample (sampler.startSample); this uses 3 groups of dimensions per path vertex from group 0. `rays`
  // grows by the rays traced. Finite and ≥ 0 for finite input. When p lies on a triangle, pass the triangle's
  // EmbreeScene::triangleMagnitudeM as surfaceMagnitudeM so that rays leave it far enough (rayOffsetM); a
  // free sensor needs none.
  template <class S>
  Rgb sampleIrradiance(const vec3& p, const vec3& n, S& sampler, uint64_t& rays,
                       float surfaceMagnitudeM = 0.0f) const;

 private:
  struct Vertex {
    vec3 p;            // on the surface (not offset)
    vec3 n;            // unit, the side being lit
    float magnitudeM;  // for rayOffsetM()
  };

  // ∫ L_i cos θ dω over the hemisphere of v.n from the lights by next-event estimation, MIS-weighted where
  // cosine sampling also finds the light. Uses the sampler's group `group` and the first pair of group + 1.
  template <class S>
  Rgb directLight(const Vertex& v, uint32_t group, S& sampler, uint64_t& rays) const;
  Rgb punctualLight(const rdb::TracePunctualLight& light, const Vertex& v, uint64_t& rays) const;
  // Sky radiance towards world direction d (black below the horizon), and the density per steradian with
  // which directLight samples d.
  Rgb skyRadiance(const vec3& d) const;
  float skyPdf(const vec3& d) const;
  // Density per steradian with which directLight samples the point at distance distM on emissive triangle t,
  // seen at |cos θ_light| = absCosLight.
  float emitterPdf(uint32_t t, float distM, float absCosLight) const;

  const rdb::TraceRdb& rdb_;
  const EmbreeScene& scene_;
  IntegratorSettings settings_;
  std::optional<Distribution2D> skyDistribution_;      // over (φ / 2π, 1 − μ); none without a sky
  std::optional<Distribution1D> emitterDistribution_;  // over rdb.emissiveTriangles; none without emitters
  std::vector<float> emitterPmfOfTriangle_;            // per triangle, 0 when not emissive
  Rgb sunRadianceCdM2_{0.0f};
  float sunOneMinusCos_ = 0.0f;
};

// Progressive passes over all points in parallel. A point's samples depend only on (seed + point index,
// replicate, sample index), and each point's statistics are updated in sample order by one thread, so the
// result is bit-identical for any thread count. points and normals have the same size, surfaceMagnitudesM the
// same or none (free sensors; see sampleIrradiance); std::invalid_argument otherwise.
EstimateResult estimateIrradiance(const Integrator& integrator, std::span<const vec3> points,
                                  std::span<const vec3> normals, const EstimateSettings& settings,
                                  std::span<const float> surfaceMagnitudesM = {});

}  // namespace fly::raytracer
