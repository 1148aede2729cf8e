// Monte-Carlo irradiance at points: the sensor of `fly illuminance` and, later, the baker's vertices and
// texels.
//
// E(p, n) = ∫_{H(n)} L_i(p, ω) cos θ dω (lux) at the sensor, by path tracing (Kajiya, "The rendering
// equation", SIGGRAPH 1986) with next-event estimation (light sampling) at every vertex whose BSDF has a
// non-delta lobe. Surfaces scatter by their material's Bsdf (raytracer/bsdf.h: diffuse, mirror or GGX
// reflection, thin-walled clear or frosted transmission, the SDB's energy rule at the actual angle; or a
// measured BRDF, tabulated or the car-paint model, evaluated and importance-sampled by its MeasuredLobe and
// combined with light sampling by the same multiple importance sampling).
//
// The sun: a disc of uniform radiance E_n / (π sin² θ_s), so that a surface facing it receives E_n, sampled
// uniformly in its cone at every non-delta vertex, without MIS; the sky table holds no sun, so a path adds
// the disc's radiance only when a ray leaving a delta lobe (a mirror) reaches it, and only with
// IntegratorSettings::caustics.
//
// The sky table: importance-sampled by a Distribution2D over its equal-area cells weighted by luminance, and
// combined with BSDF sampling (cosine sampling at the sensor) by multiple importance sampling with the power
// heuristic, β = 2 (Veach & Guibas, "Optimally combining sampling techniques for Monte Carlo rendering",
// SIGGRAPH 1995).
//
// Sky portals (IntegratorSettings::skyPortals): in a scene with clear glass, each plane of clear-glass
// triangles (a window, a skylight) is a portal for the points on its inner side: the side from which rays
// through the plane's panes reach the sky less often than from the other (found at start-up by rays from the
// panes over the upper hemisphere), and within the depth of the room behind it (the farthest hit of rays from
// the panes into that side) of its panes' box. Inside a building the sky table's directions are nearly all
// blocked by walls and roof, while the portals' pass through the windows. At a point x that is on the inner
// side of some portal planes, the sky's light sampling draws its direction from a mixture: with probability
// α (kPortalFraction, kSensorPortalFraction at the sensor) towards a point on those planes' panes, else from
// the sky table. The plane q is chosen with probability w_q(x) / Σ w (portalPlaneWeight: the solid angle of
// a disc of its pane area at its distance, times the share of rays from x's cell that reach its panes,
// portalVisibilityAt), the point uniform by area A_q on its panes. The mixture's density per steradian,
// (1 − α) p_table(d) + α p_portal(x, d), with p_portal the sum of w_q / Σ w · t² / (A_q |cos θ|) over the
// panes that the ray meets at distances t, is what the MIS weights use, for sampled and escaping
// directions alike: unbiased whatever the glass and the weights (a one-sample mixture of two
// techniques: Veach, "Robust Monte Carlo methods for light transport simulation", PhD thesis, 1997, ch. 9;
// portals as in Bitterli, Novák & Jarosz, "Portal-masked environment map sampling", EGSR 2015, and Cycles'
// portal lights). Points outside every portal plane's inner side sample the table alone. A density
// evaluation meets every portal plane once and tests the panes under the hit point: all of them, or for
// planes of more than kPanesWithoutGrid panes those of one cell of a grid over the plane. Without clear
// glass, or with more than kMaxPortalPlanes planes of it, there are no portals.
//
// Declared portals (TraceRdb::portalCornersM: the scene file's "portals", openings without glass such as a
// window hole) are candidates beside the clear-glass triangles, grouped by plane, probed for their inner side
// and gridded alike; a scene that declares some has portals without clear glass too.
//
// Continuations through portals (IntegratorSettings::portalContinuation): what a room sees through a window
// is not only sky, which the sky's light sampling above finds through the portals, but the sunlit ground and
// façades outside, which no light sampling aims at (the lit patches pick points on a lawn's huge triangles,
// nearly all hidden by the walls) and a cosine-sampled path from the ceiling finds through a window a few
// times in a hundred. Where the sensor or a Lambertian surface is on the inner side of portal planes, its
// continuation is drawn from a mixture: with probability α(x) towards a point uniform over the panes, else
// by the cosine; α(x) is kPortalContinuationFraction times the share of the panes' area below x (the
// ground is seen looking down through a window; from below the sill it shows only sky). The path's weight
// f |cos θ| / p and every MIS weight against the next vertex's light (sky, emitters, lit patches) use the
// mixture's density (1 − α) cos θ / π + α p_portal(x, d), so the estimate stays unbiased (Veach's one-sample
// model again).
//
// Emissive triangles: one chosen by area × luminance (× 2 when double-sided), a point uniform on it, its
// density converted to solid angle by dω = |cos θ_light| dA / r² (Pharr, Jakob & Humphreys, "Physically Based
// Rendering", 4th ed., ch. 4), and combined with BSDF sampling likewise. Light found after a delta lobe
// counts in full (light sampling cannot find it).
//
// Punctual lights: directional lights every one; point, spot and goniometric lights every one while there
// are at most kAllPunctualLights of them (deterministic: no variance from the choice), otherwise one per
// sample chosen by a Distribution1D over an estimate of its flux (lm: 4π I for a point, 2π (1 − cos θ_outer)
// I for a spot, 4π I × the table's mean for a goniometric light; luminance of the colour) and divided by its
// probability (pbrt-v4's PowerLightSampler; a light's distance is not considered).
//
// Clear glass (thin-walled, straight-through transmission): shadow rays pass through it with its
// transmittance T(θ) at the angle they cross it, and stop at anything else. A path that passes straight
// through keeps the MIS state of its last non-delta vertex (the light it then finds is also what that
// vertex's shadow rays find through the pane), and the passage is not a reflection (maxBounces). When the
// TraceRdb has no clear glass, shadow rays are plain occlusion queries.
//
// Russian roulette from the fourth path vertex on (the sensor is the first; earlier it made most of the noise
// of daylight bakes, integrator.cpp), as a weight window on the path's throughput relative to the sensor's,
// b = max component of β / π (β: the throughput with the sensor's π, the integrand's L cos θ over the
// cosine density), times the vertex's albedo a: a path continues surely while b a ≥ w
// (IntegratorSettings::rouletteWindow), and below it with survival probability q = b a / w and weight 1/q,
// so that its survivors carry b a = w (the weight window of MCNP, X-5 Monte Carlo Team, "MCNP — A General
// Monte Carlo N-Particle Transport Code", LA-UR-03-1987, 2003, ch. 2; in rendering Vorba & Křivánek,
// "Adjoint-driven Russian roulette and splitting in light transport simulation", SIGGRAPH 2016). Unbiased
// for any w > 0: a path ended with probability 1 − q loses what it would have gathered, and one that goes on
// gathers it with weight 1/q. w = 1 is throughput roulette (pbrt-v4's PathIntegrator): in a closed room of
// albedo ρ a surviving path keeps b = 1 and survives each bounce with probability ρ, so the number of
// bounces, geometric with mean ρ/(1 − ρ), makes the variance (a relative standard deviation of 0.9 per sample
// on a sphere of albedo 0.9, whose every wall vertex gathers the same light); the window w < 1 lets the
// throughput fall to w first, and the tail's weights and so its variance fall by w² (kRouletteWindow), for
// ln w / ln ρ more bounces. Past its first decision a path on Lambertian surfaces keeps b = w and survives each
// vertex with probability equal to its albedo, so the variance stays bounded even at ρ = 0.99. (A survival
// probability capped below the albedo, e.g. min(ρ, 0.95) at ρ = 0.99, would let weights grow faster than
// paths die: infinite variance.)
// The roulette is decided after the vertex's light sampling (IntegratorSettings::rouletteAfterLight: a path
// that ends there still gathers the light at the vertex; decided on arrival, a path through a window that
// reaches the dark sunlit ground ends there 4 times in 5 without its sunlight and gathers it with 5 times
// the weight when it survives).
//
// Materials at a hit (raytracer/surface_point.h): textures of every slot (base colour × COLOR_0, reflection,
// glossiness, transmission, emission, anisotropy and its rotation; bilinear, glTF wrap modes,
// KHR_texture_transform), with the energy rule applied to the point's colours. Emissive triangles with an
// emission texture are chosen by area × the material's mean emission over the texture's texels, and the
// texture is evaluated at the sampled point (and where a path hits), so emitter sampling stays unbiased.
//
// Alpha coverage: cut-outs (TraceAlpha::kMask) are left out by Embree's filter functions where coverage <
// alphaCutoff, for path rays and shadow rays alike (raytracer/embree_scene.h). Partial coverage (kBlend) is a
// delta lobe of the Bsdf that passes 1 − coverage straight through, unbent and without Fresnel; shadow rays
// pass it with that transmittance as they pass clear glass. The lobe is chosen with the vertex's lobe-choice
// dimension, so the estimate stays a function of (point, sample) alone.
//
// Shading normals: interpolated vertex normals, bent by normal maps, shade every hit; the geometric normal
// decides the side. Light arriving from below the geometric surface counts nothing, nor does a sampled
// direction that the shading and geometric normals put on different sides (no light through the back of a
// surface; the energy of those directions is lost, never gained: f |cos θ_s| integrates to at most the
// albedo over the directions kept). A path gathers radiance, for which f with the shading cosine is the
// correct integrand (Veach, PhD thesis, 1997, §5.3: the adjoint correction |ωo·N_s||ωi·N_g| / (|ωo·N_g|
// |ωi·N_s|) belongs to importance transport, which no path here carries). Where the direction back along a
// ray lies below the shading normal, the normal is bent towards the geometric one until it lies
// kMinShadingCos above (integrator.cpp), so that no facet of a smooth low-poly mesh turns black at grazing
// angles. The sensor integrates the hemisphere of the normal it is given.
//
// Next-event estimation to lit patches (IntegratorSettings::litPatches; docs/lit-patches.md): inside a sunlit
// room most light comes from the sun patches on the floor and the sky's light through the windows, reflected
// once; a path from the ceiling finds such a patch only by chance. At a vertex x that samples lights, in a
// region that LitPatches gives a distribution (its training rays mostly stay inside), a second strategy
// picks a triangle by that distribution and a point y on it, uniform or by the triangle's map of its sunlit
// part (IntegratorSettings::litPatchMaps; area density p_A(y) = P(t) m_t(y) / A_t, LitPatches::density), and
// adds f(x) |cos θ_x| V(x, y) L_d(y → x) / p_ω(y), p_ω = p_A r² / |cos θ_y|, where L_d(y → x) is the light
// sampling of the sun at y (IntegratorSettings::litPatchSky: and of the sky, with the same MIS weight
// against y's BSDF sampling that a path reaching y computes there), for y seen as the next vertex of the
// path. The path that reaches the same y by x's BSDF sampling (density p_b) and samples the sun there makes
// the same contribution; the two are combined by the power heuristic: the patch sample is weighted
// p_ω² / (p_ω² + p_b²) and the sun's light (and the sky's) of the path's vertex y p_b² / (p_ω² + p_b²), with p_ω
// evaluated for the triangle that the path hit in the distribution of x's region (0 where x has none, or
// after a mirror). The weights of every path sum to one: unbiased whatever the distribution (Veach & Guibas
// 1995). The patch sample uses two sampler groups of its own per path vertex (kPatchGroupBase).
//
// Anisotropic reflection (Bsdf): materials whose lobe has an orientation on the surface are shaded in the
// frame of the interpolated vertex tangents (TraceRdb::tangents, made perpendicular to the shading normal;
// surface_point.h, shadingFrameAt), every other material in any frame around the shading normal. The light
// paths from the sun (light_paths.h) use the same frames. Light sampling regularises an anisotropic lobe
// through its isotropic α (IntegratorSettings::caustics): its widths keep α_U α_V = α², so its peak density
// 1 / (π α_U α_V) is bounded as an isotropic lobe's of that α is.
//
// Reflection fog (rdb::TraceMaterial::reflectionFogDistanceM D, reflectionFogColor c; docs/materials-engine.md):
// what a reflection lobe at x shows along a ray that meets something at d (nothing: d = ∞) is mix(L, L_fog,
// t), t = min(d / D, 1), L_fog = c E(x) / π: the radiance of a Lambertian surface of albedo c at x. A path
// whose sample at x (weight W, its reflection lobe's share ρ per channel, s of the mean) meets d follows the fog
// with probability t s, weight ρ W / s, from a virtual vertex at x with that Lambertian Bsdf (light sampling
// and a cosine continuation, as any diffuse vertex), else the hit with weight (W − t ρ W) / (1 − t s): both
// terms in expectation, unbiased. Light sampling at x fades the reflection lobe alike (response), so that its
// MIS with the sampled rays combines estimates of one integrand.
//
// Not modelled: refraction through thick glass.
//
// Sides: the sensor integrates the hemisphere of n (pass −n for the back side of a two-sided surface). The
// back face of a one-sided material only transmits (Bsdf); without transmission it ends a path: it blocks
// light and reflects none. A double-sided material reflects and emits on both faces.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "raytracer/bsdf.h"
#include "raytracer/car_paint_lobe.h"
#include "raytracer/distribution.h"
#include "raytracer/embree_scene.h"
#include "raytracer/lit_patches.h"
#include "raytracer/progressive.h"
#include "raytracer/sampler.h"
#include "raytracer/surface_point.h"
#include "raytracer/tabulated_lobe.h"
#include "raytracer/warp.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// Longest path ever traced, whatever the settings: a guard against albedo 1 in a closed room, never reached
// by Russian roulette otherwise (at ρ = 0.99 a path is this long with probability 0.99^10000 ≈ 2·10⁻⁴⁴).
inline constexpr uint32_t kPathLengthGuard = 10000;

// Point, spot and goniometric lights evaluated every one at each vertex (no variance from a choice, at most
// this many shadow rays for them per vertex); with more, one is chosen by flux per vertex.
inline constexpr uint32_t kAllPunctualLights = 8;

// Clear panes a shadow ray passes at most; it is blocked at the next (a guard against stacked coplanar
// glass, not a limit real scenes reach).
inline constexpr uint32_t kMaxPanesPassed = 64;

// The glossiness (GGX α = glossiness²) below which IntegratorSettings::caustics = false blurs reflection
// lobes for light sampling of the sun and punctual lights at surface vertices.
inline constexpr float kRegularizedGlossiness = 0.3f;

// The share of sky light samples that go through the clear-glass portals when the scene has them.
inline constexpr float kPortalFraction = 0.25f;
// The same at the sensor, whose light straight from the sky is the largest part of a floor's noise indoors
// (docs/benchmarks.md, "Where the house's p95 is now"); the table keeps the rest for MIS.
inline constexpr float kSensorPortalFraction = 0.75f;

// The share of a continuation's samples that head through the portals where the sensor or a Lambertian
// surface is on their inner side (IntegratorSettings::portalContinuation).
inline constexpr float kPortalContinuationFraction = 0.25f;

// The least cos θ with which Integrator::portalPlaneWeight sees a portal plane.
inline constexpr float kPortalMinCosine = 0.2f;

// Integrator::portalVisibilityAt: the grid's cells along the diagonal of the portal planes' boxes, the margin
// around those boxes that the grid covers (a share of that diagonal on each side: the floors and ceilings
// of the rooms behind), the points per cell and rays per point and plane, and the share added to every
// plane's.
inline constexpr float kPortalCellsAlongPortals = 24.0f;
inline constexpr float kPortalGridMargin = 0.5f;
inline constexpr uint32_t kPortalVisibilityOrigins = 4;
inline constexpr uint32_t kPortalVisibilityRays = 8;
inline constexpr float kPortalVisibilityFloor = 0.05f;

// Planes of clear glass beyond which sky portals are off: every sky density evaluation meets each one.
inline constexpr uint32_t kMaxPortalPlanes = 64;

// Panes in a portal plane up to which a density evaluation tests them all; planes of more get a grid.
inline constexpr uint32_t kPanesWithoutGrid = 8;

// IntegratorSettings::rouletteWindow's default. Against w = 1: on a closed sphere of albedo 0.9 the variance
// per sample falls 12× (1/w² = 16) for 2.3× the tracing time a sample; the house (scenes/house) reaches a
// given 95th percentile of the error 1.1× sooner; a sunlit room and a Cornell box, whose noise is not the
// paths' lengths, are unchanged; w = 0.1 costs those 13–24 % (docs/benchmarks.md, "Russian roulette as a
// weight window"; tests/cli/closed_sphere_test.cpp).
inline constexpr float kRouletteWindow = 0.25f;

struct IntegratorSettings {
  // Reflections of indirect light, ≥ 0 (0 = direct light only, which includes light through clear glass).
  // Paths end by Russian roulette long before the default; kPathLengthGuard caps it.
  uint32_t maxBounces = kPathLengthGuard;
  // Caustics of the sun and of punctual lights: their light reflected by mirrors and sharp glossy surfaces
  // onto diffuse ones (a window pane's image of the sun on a wall). Path tracing finds these paths rarely and
  // with huge values: a path leaving a mirror reaches the sun's 0.53° disc with a chance of ≈ 10⁻⁵ and a
  // radiance of ≈ 10⁹ cd/m², and a tile of GGX α = 0.01 under the sun glints towards a sensor from a tiny
  // spot. At practical sample counts most vertices see such a path not at all and a few see it with a
  // weight tens of times their whole irradiance: fireflies, with a standard error that cannot know the
  // event it has not seen.
  //   false (the default, as common light-map bakers): the sun found by a ray leaving a mirror is left out,
  //   and light sampling of the sun and of punctual lights at surface vertices evaluates reflection lobes
  //   sharper than kRegularizedGlossiness as if they had that glossiness (path regularisation, Kaplanyan &
  //   Dachsbacher, "Path Space Regularization for Holistic and Robust Light Transport", EG 2013): glints are
  //   blurred over a lobe of GGX α = 0.09 instead of lost, with nearly the same energy. Measured BRDFs
  //   likewise: a car paint's coat and flakes as GGX α ≥ 0.09, a table's highlights spread over half vectors
  //   within atan 0.09 of their own (TabulatedLobe::regularised). The sky and emitters seen in mirrors and
  //   glossy surfaces count exactly.
  //   true: all of it exactly (unbiased), for studies of glare, with many samples.
  bool caustics = false;
  // Sky portals at clear-glass triangles (above). Off gives the estimator of bakes before they existed
  // (resumed checkpoints), and a comparison.
  bool skyPortals = true;
  // Next-event estimation to lit patches (above), in scenes with a sun whose surfaces enclose some region
  // (LitPatches); off gives path sampling alone, for resumed checkpoints of bakes without it and for
  // comparisons.
  bool litPatches = true;
  // How the patch samples and path sampling share the paths that both can make: by the power heuristic, or
  // all to one of them, a check of the weights (tests): kPatchesOnly is unbiased only where the regions'
  // distributions hold every directly lit triangle in sight, kPathsOnly gives path sampling's answer at the
  // cost of both.
  enum class LitPatchWeights { kPowerHeuristic, kPatchesOnly, kPathsOnly };
  LitPatchWeights litPatchWeights = LitPatchWeights::kPowerHeuristic;
  // Whether the patch sample gathers the sky's light at y besides the sun's. Off (the default), it gathers
  // the sun's alone, one ray fewer: the sky's light reflected at y is left to path sampling, whose MIS
  // weight for it is then 1, and the regions' distributions follow the sun's light alone. On gives the
  // estimator of bakes before the choice existed (resumed checkpoints), and a comparison.
  bool litPatchSky = false;
  // Maps of where the sun lights large triangles (LitPatches, kMaxMapLevel): the patch sample's point drawn
  // where the light is on a triangle that the sun lights in part, rather than uniformly. Off gives the
  // estimator of bakes before the maps existed (resumed checkpoints), and a comparison.
  bool litPatchMaps = true;
  // Continuations through the portals (above): where a path leaves the sensor or a Lambertian surface on
  // the inner side of some portal planes, kPortalContinuationFraction of its continuations head for a point
  // uniform on their panes, the rest follow the cosine, and every weight uses the mixture's density. The
  // light that comes in through windows is not the sky's alone: the sunlit ground and façades outside are
  // seen through them too, and a cosine-sampled path from the ceiling finds them rarely. Off gives the
  // estimator of bakes before it existed (resumed checkpoints), and a comparison.
  bool portalContinuation = true;
  // Training points spread over triangles that are large for the lit patches' regions (LitPatches,
  // kTrainingPointsPerCellSide), besides the vertices. Off gives the estimator of bakes before they existed
  // (resumed checkpoints).
  bool litPatchInteriorTraining = true;
  // Russian roulette at a vertex after its lights are sampled (and before its continuation), rather than
  // when the vertex is reached: a path that ends there still gathers the vertex's direct light (above).
  // Off gives the estimator of bakes before it existed (resumed checkpoints), and a comparison.
  bool rouletteAfterLight = true;
  // The weight window of Russian roulette (above), in (0, 1]: paths continue surely while their throughput
  // relative to the sensor's times the vertex's albedo is at least this. 1 gives throughput roulette, the
  // estimator of bakes before the window existed (resumed checkpoints), and a comparison.
  float rouletteWindow = kRouletteWindow;
};

class Integrator {
 public:
  // Keeps references to rdb and scene, which must outlive it. Throws std::invalid_argument when
  // settings.rouletteWindow is not in (0, 1], the sky table's size is not resolution², or a material index
  // is out of range.
  Integrator(const rdb::TraceRdb& rdb, const EmbreeScene& scene, IntegratorSettings settings = {});
  ~Integrator();

  // One sample of the irradiance in lux at p (world, metres) on the side of unit normal n. The caller starts
  // the sample (sampler.startSample); this uses 3 groups of dimensions per path vertex from group 0: (sun,
  // sky), (continuation, emitter), (Russian roulette, BSDF lobe choice, punctual light choice), and computes
  // only the dimensions it needs (no lobe choice on a Lambertian surface, no emitter without emitters).
  // `rays` grows by the rays traced. Finite and ≥ 0 for finite input. When p lies on a triangle, pass the
  // triangle's EmbreeScene::triangleMagnitudeM as surfaceMagnitudeM so that rays leave it far enough
  // (rayOffsetM); a free sensor needs none.
  // sunDirectLux, when given, receives the part of the returned sample that arrived straight from the sun's
  // disc at p: the sensor's sun sample (through clear panes and partial coverage with their transmittance),
  // the only way the disc reaches the sensor directly (its continuation is a cosine sample, never a mirror,
  // and the sky table holds no sun). The sample minus it is the same path's estimate of everything else:
  // the sky, lights, emitters and all reflected light, the sun's included (FLY §3's sunlight mode bakes that
  // and draws the sun's direct term in real time). 0 without a sun.
  // sunLux, when given, receives the part of the returned sample that came from the sun at all: its light
  // sampled at every vertex (and, with caustics, found after a mirror), direct and reflected; what the light
  // paths from the sun (raytracer/light_paths.h) also estimate.
  template <class S>
  Rgb sampleIrradiance(const vec3& p, const vec3& n, S& sampler, uint64_t& rays,
                       float surfaceMagnitudeM = 0.0f, Rgb* sunDirectLux = nullptr,
                       Rgb* sunLux = nullptr) const;

  // The irradiance in lux at p on the side of unit normal n from the sun's disc centre and the punctual lights
  // alone, each with one shadow ray (through clear panes, with their transmittance): deterministic, no sky,
  // emitters or reflected light. What the light-resolution analysis compares between a triangle's corners and
  // its interior (raytracer/light_resolution.h). surfaceMagnitudeM as for sampleIrradiance.
  Rgb deltaDirectIrradiance(const vec3& p, const vec3& n, uint64_t& rays, float surfaceMagnitudeM = 0.0f) const;

  // Whether the scene has a sun that lights it (sunLights): only then has sampleIrradiance a sun-direct part.
  bool hasSun() const { return sunOneMinusCos_ > 0.0f; }
  // Whether next-event estimation to lit patches runs: IntegratorSettings::litPatches, a sun, and some
  // enclosed region with lit surfaces in sight (LitPatches).
  bool usesLitPatches() const { return litPatches_ != nullptr; }
  // Its regions with a distribution (0 without).
  size_t litPatchCells() const { return litPatches_ ? litPatches_->cellCount() : 0; }
  // Its triangles with a map of where the sun lights them (LitPatches::mapCount; 0 without).
  size_t litPatchMaps() const { return litPatches_ ? litPatches_->mapCount() : 0; }
  // Whether some material has reflection fog (rdb::TraceMaterial::hasReflectionFog).
  bool hasReflectionFog() const { return !fogBsdfs_.empty(); }

 private:
  friend class SunLightPaths;  // the light paths (raytracer/light_paths.h) scatter by the same Bsdfs

  struct Vertex {
    vec3 p;            // on the surface (not offset)
    vec3 n;            // unit shading normal on the side being lit (the side of the path's previous vertex)
    vec3 ng;           // unit geometric normal on that side (n at the sensor): ray offsets, light leaks
    float magnitudeM;  // for rayOffsetM()
    const Bsdf* bsdf;  // null at the sensor, which weighs incident light by cos θ
    // For light sampling of the sun and punctual lights: bsdf, or without caustics its regularised twin
    // (IntegratorSettings::caustics); null at the sensor.
    const Bsdf* deltaLightBsdf;
    Onb frame;     // around n (surface vertices; shadingFrameAt)
    vec3 woLocal;  // towards the previous vertex, in frame (surface vertices)
    // Reflection fog of the material (rdb::TraceMaterial): its distance (∞: none) and the Lambertian Bsdf of
    // albedo fogColor that stands in for the reflection lobes where the fog wins (sampleIrradiance).
    float fogDistanceM = std::numeric_limits<float>::infinity();
    const Bsdf* fogBsdf = nullptr;
    // Where v's continuation mixes the portals with the cosine (portalContinuationShare): portalWeight(v.p),
    // and the portals' share; sampling, response()'s density and every MIS weight use the mixture.
    float portalWeight = 0.0f;
    float portalShare = 0.0f;  // the share α of v's continuations that head through the portals (0: none)
  };

  // Σ over the lights of ∫ L_i f |cos θ| dω at v by light sampling (f = 1 and the hemisphere of n at the
  // sensor), MIS-weighted where BSDF sampling also finds the light. Uses the sampler's group `group`;
  // uEmitter and uPunctual choose an emitter point and a punctual light.
  // allLights: also the sky and emitters (v.bsdf has a non-delta lobe); else the sun and punctual lights
  // only. sunPart, when given, receives the sun's share of the result.
  // sunSkyPart, when given, receives the sun's and the sky's share (what a lit patch's sample gathers with
  // IntegratorSettings::litPatchSky);
  // sunSkyOnly leaves out the punctual lights and emitters (the lit patch's own light).
  template <class S>
  Rgb directLight(const Vertex& v, bool allLights, uint32_t group, const vec2& uEmitter, float uPunctual,
                  S& sampler, uint64_t& rays, Rgb* sunPart = nullptr, Rgb* sunSkyPart = nullptr,
                  bool sunSkyOnly = false) const;
  // The path vertex at x on the triangle point `at` of geometric normal ng, reached by a ray along unit d:
  // its side, shading normal (bent where the direction back along the ray lies below it) and scattering
  // functions (built in point and pointDeltaLight where the material varies), or none where the ray meets
  // the surface edge-on or no light leaves it back along the ray.
  std::optional<Vertex> vertexAt(const vec3& x, const TrianglePoint& at, const vec3& ng, const vec3& d,
                                 std::optional<Bsdf>& point, std::optional<Bsdf>& pointDeltaLight) const;
  // The next-event estimation to lit patches at v (surface or sensor) from its region `cell`: the patch
  // sample's MIS-weighted f |cos θ| V L_d / p_ω, its sun part in sunPart. Uses the sampler groups
  // kPatchGroupBase + 2 depth (the point) and + 1 (the patch's sun, and sky).
  template <class S>
  Rgb litPatchLight(const Vertex& v, uint32_t cell, uint32_t depth, S& sampler, uint64_t& rays,
                    Rgb& sunPart) const;
  // A one-sample estimate (the seed's) of the luminance (cd/m²) of the direct light that the patch samples
  // gather (the sun's; with IntegratorSettings::litPatchSky also the sky's) that the hit point reflects back
  // along the ray of unit direction d: LitPatches' training weights.
  float directlyLitRadiance(const Hit& hit, const vec3& d, uint64_t seed) const;
  // The mean of directlyLitRadiance over kFaceRadianceSamples points of triangle t's front or back face,
  // seen along its normal.
  float faceRadiance(uint32_t t, bool front) const;
  void buildLitPatches();
  // The weight of a patch sample of density pdfPatch that path sampling makes with density pdfPath
  // (IntegratorSettings::litPatchWeights); path sampling's is one minus it.
  float patchWeight(float pdfPatch, float pdfPath) const;
  Rgb punctualLight(const rdb::TracePunctualLight& light, const Vertex& v, uint64_t& rays) const;
  // v's response to light arriving from world direction d from a source at distance distM (∞: the sun, the
  // sky, directional lights): f |cos θ| (cos θ at the sensor; θ from the shading normal), with the reflection
  // lobe faded by v's reflection fog, f − fogFraction(distM) f_reflection (the fog's own light is gathered
  // apart, sampleIrradiance), and the density per steradian with which v's continuation samples d. False
  // when v takes no light from d, also where d lies on the other side of the geometric surface than of the
  // shading one (no light through the back of a surface). bsdf: v.bsdf or v.deltaLightBsdf.
  // The density per steradian with which the continuation of v (the sensor, or a Lambertian surface) samples
  // unit direction d at cos θ = n · d > 0: the cosine's, mixed with v's directional guide where it has one.
  float continuationPdf(const Vertex& v, float cosTheta, const vec3& d) const;
  // The continuation of v (the sensor, or a Lambertian surface) from u: the direction d, its cos θ and its
  // density (continuationPdf). False where d lies below v's shading normal (no light comes from there).
  bool sampleContinuation(const Vertex& v, vec2 u, vec3& d, float& cosTheta, float& pdf) const;
  // A point on the panes of the portal planes whose inner side x is on (weight = portalWeight(x) > 0), from
  // u ∈ [0, 1)²: a plane with probability portalPlaneWeight(x, q) / weight, a point uniform by area on its
  // panes.
  vec3 portalPoint(const vec3& x, float weight, const vec2& u) const;
  bool response(const Vertex& v, const Bsdf* bsdf, const vec3& d, Rgb& fCos, float& pdf,
                float distM = std::numeric_limits<float>::infinity()) const;
  // The fraction of light that reaches origin from unit direction dir over [0, tMaxM] (tMaxM may be ∞): 1
  // when nothing is in the way, the product of T(θ) of the clear panes crossed, 0 when anything else is hit:
  // one occlusion query (EmbreeScene::transmittance), which stops at the first opaque surface it meets.
  // `rays` grows by one.
  Rgb visibility(const vec3& origin, const vec3& dir, float tMaxM, uint64_t& rays) const;
  // The point of a hit from its barycentrics, more precise than origin + t·d (Wächter & Binder 2019).
  vec3 hitPoint(const Hit& hit) const;
  // The sky table's cell towards world direction d with d.y ≥ 0: an index into rdb.sky.radianceCdM2 and
  // skyPdfPerSr_.
  uint32_t skyCell(const vec3& d) const;
  // The share of the continuations at x that head through the portals (portalContinuation): at most
  // kPortalContinuationFraction, times the share of the portals' panes that lie below x (what is seen
  // through a window from below its sill is the sky, which the sky's light sampling finds through the
  // portals already; the sunlit ground and façades outside are seen looking down). areaM2 receives
  // portalWeight(x).
  float portalContinuationShare(const vec3& x, float& weight) const;
  // How much portalPoint() favours plane q seen from x: the solid angle of a disc of the plane's pane area
  // facing x at the distance of its box's centre, A cos θ / (t² + A / π) (the on-axis solid angle of a disc,
  // 2π (1 − t / √(t² + A / π)), to first order in A / t², bounded by π near it), with cos θ at least
  // kPortalMinCosine (a window seen edge-on from beside it still fills part of the view). Any positive
  // weight keeps the estimate unbiased; this one spends the samples on the windows that light x the most.
  // visibility: portalVisibilityAt(x).
  float portalPlaneWeight(const vec3& x, uint32_t q, const float* visibility) const;
  // A point on plane q's panes, uniform by area for u uniform in [0, 1)².
  vec3 planePoint(uint32_t q, const vec2& u) const;
  // Per cell of a grid of side portalCellSizeM_ over the portal planes' boxes grown by kPortalGridMargin of
  // their diagonal on every side (portalGridCells_ cells from portalGridOriginM_; outside it every share is
  // 1, portalOutsideGrid_), for each portal plane the share of the rays from
  // kPortalVisibilityOrigins points in the cell to kPortalVisibilityRays points on the plane's panes that
  // reach the pane (through clear glass): which windows the points of the cell see, and which inner walls
  // and deep reveals hide from them. portalPlaneWeight scales by it, plus kPortalVisibilityFloor (a
  // window that the cell's rays missed keeps some weight). A pure function of the cell, kept in a table that
  // the threads fill as they first meet a cell (each slot written once, by the thread that claims it; a
  // thread that finds a slot still being filled computes its own copy), so the bake is deterministic for any
  // thread count. The shares of x's cell, one per portal plane; valid until the calling thread's next call.
  const float* portalVisibilityAt(const vec3& x) const;
  void computePortalVisibility(const glm::ivec3& cell, float* out) const;
  struct PortalVisibilityTable;
  std::unique_ptr<PortalVisibilityTable> portalVisibility_;
  float portalCellSizeM_ = 1.0f;
  vec3 portalGridOriginM_{0.0f};
  glm::uvec3 portalGridCells_{0};
  std::vector<float> portalOutsideGrid_;
  // Σ portalPlaneWeight(x, q) over the portal planes whose inner side x is on (0: none, and always without
  // portals).
  float portalWeight(const vec3& x) const;
  // Density per steradian with which directLight's sky sampling draws world direction d (d.y ≥ 0) from x,
  // given portalWeight(x): the sky table's for d's cell, mixed with the portals' when that weight is not 0.
  float skyLightPdf(const vec3& x, const vec3& d, uint32_t cell, float portalWeight, float portalFraction) const;
  // p_portal(x, d), the density per steradian of portalPoint()'s direction, for weight = portalWeight(x) > 0.
  float portalPdf(const vec3& x, const vec3& d, float weight) const;
  // Whether x is on plane q's inner side.
  bool insidePortal(const vec3& x, uint32_t q) const;
  // Fills portals_ and portalPlanes_ from the clear-glass triangles and the declared portals' triangles;
  // leaves them empty (no portals) beyond kMaxPortalPlanes.
  void buildPortals();
  // Density per steradian with which directLight samples the point at distance distM on emissive triangle t,
  // seen at |cos θ_light| = absCosLight.
  float emitterPdf(uint32_t t, float distM, float absCosLight) const;
  // The scattering functions at a point of material mi, on its front face or not: the material's own, or
  // for a material that varies over its surface the point's, built in `point` and `pointDeltaLight`.
  struct PointBsdfs {
    const Bsdf* bsdf;
    const Bsdf* deltaLight;  // for light sampling of the sun and punctual lights (Vertex::deltaLightBsdf)
  };
  PointBsdfs bsdfsAt(uint32_t mi, bool front, const TrianglePoint& at, std::optional<Bsdf>& point,
                     std::optional<Bsdf>& pointDeltaLight) const;

  const rdb::TraceRdb& rdb_;
  const EmbreeScene& scene_;
  IntegratorSettings settings_;
  std::optional<Distribution2D> skyDistribution_;  // over (φ / 2π, 1 − μ); none without a sky
  std::vector<float> skyPdfPerSr_;  // per sky cell: the density per steradian of directLight's sky samples
  std::optional<Distribution1D> emitterDistribution_;  // over rdb.emissiveTriangles; none without emitters
  std::vector<float> emitterPmfOfTriangle_;            // per triangle, 0 when not emissive
  Rgb sunRadianceCdM2_{0.0f};
  Onb sunFrame_{};  // around the sun's direction
  float sunOneMinusCos_ = 0.0f;
  // Measured BRDFs: one lobe per measured table (rdb.brdfTables) and, without caustics, one per regularised
  // table (TabulatedLobe::regularised), then per car-paint material one and, without caustics, its
  // regularised twin; per material the lobe for its Bsdfs and for those of delta-light sampling (null for
  // analytic materials). Built before the Bsdfs, which point at them.
  std::vector<std::unique_ptr<const MeasuredLobe>> measuredLobes_;
  std::vector<const MeasuredLobe*> materialLobe_;
  std::vector<const MeasuredLobe*> deltaLightMaterialLobe_;
  std::vector<Bsdf> frontBsdfs_;  // per material: front face (either face when double-sided)
  std::vector<Bsdf> backBsdfs_;   // per material: back face (transmission only when one-sided)
  // The same for light sampling of the sun and punctual lights: regularised without caustics.
  std::vector<Bsdf> deltaLightFrontBsdfs_;
  std::vector<Bsdf> deltaLightBackBsdfs_;
  // Per material, when some material has reflection fog: the Lambertian Bsdf of albedo reflectionFogColor
  // (Vertex::fogBsdf); empty otherwise.
  std::vector<Bsdf> fogBsdfs_;
  // Per material: evaluated per point (textures, or COLOR_0 in the TraceRdb; raytracer/surface_point.h).
  std::vector<uint8_t> varies_;
  // Some material passes light straight through (clear glass or partial coverage: visibility()).
  bool passesStraight_ = false;
  // visibility()'s surfaces that pass light: per material and per triangle whether they may (clear glass,
  // partial coverage), and paneTransmittance (T(θ) of the point's Bsdf, 0 where it does not pass).
  std::vector<uint8_t> materialMayPass_;
  std::vector<uint8_t> trianglePasses_;
  EmbreeScene::PassThrough passThrough_{};
  static Rgb paneTransmittance(const void* user, const Hit& hit, const vec3& dir);
  bool hasClearGlass_ = false;  // some material is clear glass (sky portals)
  // Sky portals: a clear-glass triangle as a corner and two edges, with its unit normal, its area summed
  // with those before it in its plane, and what a barycentric test of a point in its plane needs.
  struct Portal {
    vec3 p0;
    vec3 e1;
    vec3 e2;
    vec3 n;
    float cumulativeAreaM2;
    float e1e1, e1e2, e2e2, invDenominator;  // e·e products and 1 / (e1e1 e2e2 − e1e2²)
  };
  // Portals in one plane n · p = offsetM, within a box; points x with inward · x > inwardOffsetM +
  // insideMarginM and within the region box are on its inner side.
  struct PortalPlane {
    vec3 n;
    float offsetM;
    vec3 boxMinM;
    vec3 boxMaxM;
    uint32_t first;  // its portals: portals_[first … first + count)
    uint32_t count;
    float areaM2;
    vec3 inward;
    float inwardOffsetM;
    float insideMarginM;
    vec3 regionMinM;  // the box grown by the depth of what lies behind the plane on its inner side
    vec3 regionMaxM;
    // A grid over the plane for planes of many panes (cells > 0): in-plane axes from the first corner, the
    // grid's lower corner and cells per metre along them, its cells per side, and the first of its cells in
    // portalCellStart_.
    vec3 axisU{0.0f};
    vec3 axisV{0.0f};
    vec3 origin{0.0f};
    vec2 gridMinM{0.0f};
    float cellsPerM = 0.0f;
    uint32_t cells = 0;
    uint32_t firstCell = 0;
  };
  std::vector<Portal> portals_;  // grouped by plane
  std::vector<PortalPlane> portalPlanes_;
  // The grids' cells: cell c lists portalCellItems_[portalCellStart_[c] … portalCellStart_[c + 1]), the
  // indices into portals_ of the panes whose box overlaps it.
  std::vector<uint32_t> portalCellStart_;
  std::vector<uint32_t> portalCellItems_;
  // The grid cell of plane q under a point at in-plane coordinates localM, clamped into the grid.
  static glm::uvec2 cellOf(const PortalPlane& q, const vec2& localM);
  // Gives plane q, whose portals are in portals_, a grid in portalCellStart_ and portalCellItems_ when it has
  // more than kPanesWithoutGrid panes; marginM widens the grid and each pane's cells.
  void buildPortalGrid(PortalPlane& q, float marginM);
  std::unique_ptr<const LitPatches> litPatches_;  // null: no next-event estimation to lit patches
  std::vector<uint32_t> directionalLights_;  // indices into rdb.punctualLights
  std::vector<uint32_t> positionalLights_;   // point, spot and goniometric lights
  // Over positionalLights_ by flux, when there are more than kAllPunctualLights.
  std::optional<Distribution1D> positionalDistribution_;
};

// Whether rdb's sun lights the scene: it has one, above the horizon (a sun below it has no illuminance).
// Inline: the checkpoint reader (and its fuzz target, which links no Embree) asks it too.
inline bool sunLights(const rdb::TraceRdb& rdb) {
  return rdb.hasSun && luminance(rdb.sun.normalIlluminanceLux) > 0.0f;
}

// Progressive passes over all points in parallel. A point's samples depend only on (seed + point index,
// replicate, sample index), and each point's statistics are updated in sample order by one thread, so the
// result is bit-identical for any thread count. points and normals have the same size, surfaceMagnitudesM the
// same or none (free sensors; see sampleIrradiance); std::invalid_argument otherwise.
EstimateResult estimateIrradiance(const Integrator& integrator, std::span<const vec3> points,
                                  std::span<const vec3> normals, const EstimateSettings& settings,
                                  std::span<const float> surfaceMagnitudesM = {});

}  // namespace fly::raytracer
