// Light paths (particle tracing) from the sun for the vertex light maps: an unbiased estimate of every
// vertex side's hat-weighted one-ring irradiance from the sun's light, direct and reflected
// (docs/light-paths.md).
//
// Paths start on a disc perpendicular to the sun's direction that covers the scene's bounding sphere, with a
// direction drawn in the sun's cone with density cos γ / (π sin² θ_s) (γ from the cone's axis: the projected
// disc of the cone, so that the flux through the disc per unit area is exactly the sun's normal illuminance
// E_n of TraceSun). Each of N paths carries Φ = E_n · A_disc / N (lm). At a surface hit at p on triangle t
// the path deposits its flux on t's three vertices: vertex v's side (the side of v's normal the light arrives
// on) gets Φ · b_v(p) · c / ∫b_v dA, b_v the hat (barycentric) function, ∫b_v dA = (1/3) Σ of the areas of
// v's one-ring triangles, and c = cos θ_s / cos θ_g the ratio of the cosines of the arrival direction with
// the interpolated vertex normal (the sensor's normal in the baker) and with the geometric normal. Its
// expectation is ∫ b_v E dA / ∫ b_v dA with E the irradiance about the interpolated normal: the quantity the
// gathering estimator (raytracer/baker.h) estimates, exactly (c = 1) on flat faces.
// The path then scatters by the hit's Bsdf (raytracer/bsdf.h; clear glass and partial coverage pass it
// straight with their transmittance) in the frame of the integrator's shading normal with the adjoint
// correction |ωo·N_s||ωi·N_g| / (|ωo·N_g||ωi·N_s|) of importance transport (Veach, PhD thesis, 1997, §5.3),
// and ends by Russian roulette from its third surface vertex on (survival min(1, max component of the
// throughput × albedo)), as the integrator's paths do. The first scattering (after straight passages) is by
// the Bsdf with which the gathering estimator samples the sun (Integrator::Vertex::deltaLightBsdf: without
// IntegratorSettings::caustics, mirrors and sharp glossy lobes blurred to kRegularizedGlossiness), every
// later one by the surface's own: the adjoint of a gathering path, which scatters by the true Bsdfs up to the
// vertex whose light sample finds the sun. So the sun seen in a mirror is left out (blurred) alike.
//
// Deposits until the first non-straight scattering are the sun's direct part (what the baker keeps apart as
// E_sunDirect), later ones its reflected part.
//
// Quasi-Monte Carlo: batch b's paths are the points 0 … N−1 of the Owen-scrambled Sobol' sampler seeded with
// seed + b (group 0: the disc and the cone; group 1 + k: the k-th scattering's direction, lobe and roulette),
// independent scrambles, so the batch estimates are independent and identically distributed and their spread
// gives the standard error. Deposits are added per batch in path order: bit-identical for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "base/color.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

struct LightPathSettings {
  uint32_t pathsPerBatch = 1u << 16;
  uint32_t batches = 8;  // ≥ 2 for a standard error
  uint64_t seed = 0;
  uint32_t threads = 0;  // 0 = std::thread::hardware_concurrency()
};

// Per TraceRdb vertex, lux per channel: the sun's light on the front (the side of the vertex normal) and on
// the back (two-sided meshes only; 0 otherwise), split into the direct part and the reflected rest, each with
// its standard error (the spread of the batch estimates / √batches).
struct LightPathMaps {
  std::vector<Rgb> frontDirectLux, frontDirectStdErrorLux, backDirectLux, backDirectStdErrorLux;
  std::vector<Rgb> frontReflectedLux, frontReflectedStdErrorLux, backReflectedLux, backReflectedStdErrorLux;
  uint64_t paths = 0;
  uint64_t rays = 0;
  double seconds = 0.0;
};

class SunLightPaths {
 public:
  // Keeps references; all must outlive it. integrator gives the materials (its Bsdfs) and settings.
  SunLightPaths(const rdb::TraceRdb& rdb, const EmbreeScene& scene, const Integrator& integrator);

  // Whether the scene has a sun that lights it: otherwise trace() returns zero maps.
  bool hasSun() const { return integrator_.hasSun(); }

  LightPathMaps trace(const LightPathSettings& settings) const;

 private:
  struct Deposit {
    uint32_t slot;  // 4 v + 2 back + reflected
    Rgb lux;
  };
  // Traces path `index` of the batch whose sampler is seeded with batchSeed and appends its deposits.
  void tracePath(uint64_t batchSeed, uint32_t index, float areaPerPathM2, std::vector<Deposit>& out,
                 uint64_t& rays) const;
  // Adds the deposits of a hit at barycentric (b1, b2) of triangle t by light travelling along dir.
  void deposit(uint32_t t, const vec2& barycentric, const vec3& dir, const Rgb& fluxLm, bool reflected,
               std::vector<Deposit>& out) const;

  // The density per unit launch-disc area with which a path of direction −towardsSun starts at x on the
  // disc: the disc's uniform share and the window panes' (below).
  float launchDensity(const vec3& x, const vec3& towardsSun) const;

  const rdb::TraceRdb& rdb_;
  const EmbreeScene& scene_;
  const Integrator& integrator_;
  // Window panes (clear-glass triangles facing the sun, at most kMaxLaunchPanes): a share kPaneLaunchFraction
  // of the paths starts where its line through a point uniform on a pane (chosen by its area seen from the
  // sun) meets the disc, so that the sun's light into rooms is traced by many paths; the rest uniformly on
  // the disc. Each path carries E_n / (N p(x)), p the mixture's density on the disc: unbiased.
  std::vector<uint32_t> panes_;
  std::vector<float> paneCdf_;          // over panes_, by area × |cos| to the sun's axis, normalised
  std::vector<float> paneProbability_;  // per entry of panes_
  std::vector<float> hatAreaM2_;        // per vertex: ∫ b_v dA over its one-ring (0: no ring)
  std::vector<uint8_t> twoSided_;       // per vertex
  vec3 centreM_{0.0f};
  float discRadiusM_ = 0.0f;
  float launchDistanceM_ = 0.0f;
};

}  // namespace fly::raytracer
