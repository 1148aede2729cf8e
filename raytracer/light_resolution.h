// Where vertex light maps cannot carry the light, and which meshes therefore get automatic light textures.
// A vertex light map is linear across each triangle: it shows a sun patch, a shadow edge or the pool under a
// lamp only where vertices lie closer together than the pattern. For every triangle larger than two texels,
// the direct light of the sun's disc centre, of the punctual lights (Integrator::deltaDirectIrradiance:
// noise-free, one shadow ray per light) and of the emitters (each emissive triangle as four Lambertian point
// sources, the 64 brightest triangles) is evaluated at its corners and on a lattice inside it; a triangle
// whose interior differs from the corners' linear interpolation by more than a relative tolerance cannot be
// shown by its vertices. Triangles with an edge of a metre or more are counted too: sky light, reflected light
// and emitters vary over such distances (corners, the light falling off from a window). A mesh with enough
// of either area gets a light texture over all of it (charts over any shape: rdb/lightmap_uv.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

struct LightResolutionSettings {
  // The light textures' density, texels/m (the scene's bake texelsPerMetre); > 0. Triangles whose longest
  // edge is below two texels are not examined: their vertices are as dense as texels would be.
  float texelsPerMetre = 20.0f;
  // Interpolation error of the direct light, relative to the larger of the true and the interpolated value,
  // above which a point needs texels: 5 %, the tolerance of light maps against converged values (3σ + 5 %).
  float relativeTolerance = 0.05f;
  // Errors below this share of the scene's largest direct illuminance found are ignored (deep shade, a
  // lamp's far tail): 10⁻³.
  float absoluteShare = 1e-3f;
  // Triangles with an edge at least this long need texels whatever the direct light does, metres; > 0.
  float largeTriangleEdgeM = 1.0f;
  // A mesh gets a light texture when its triangles that need texels cover at least this many texels
  // (minNeedTexels / texelsPerMetre² m²).
  float minNeedTexels = 16.0f;
  // Interior points per triangle: a lattice of k² sub-triangle centroids, k = clamp(⌈edge·density / 8⌉, 2,
  // maxLatticeK).
  uint32_t maxLatticeK = 6;
  uint32_t threads = 0;  // 0: all hardware threads
};

// What one mesh got and why.
struct MeshLightResolution {
  uint32_t mesh = 0;                  // index into TraceRdb::meshes
  double areaM2 = 0.0;                // all its triangles
  double directVariationAreaM2 = 0.0; // triangles whose direct light their corners cannot interpolate
  double largeTriangleAreaM2 = 0.0;   // triangles with an edge ≥ largeTriangleEdgeM (and not counted above)
  // Per triangle of the mesh: the largest relative interpolation error of the direct light found inside it
  // (|E − E_interpolated| / max(E, E_interpolated)), 0 where not examined.
  std::vector<float> directInterpolationError;
  bool needsTexels = false;
  // In words, for the bake's summary and manifest: "sun patches or shadow edges on 12.3 m² of 40 m²" …
  std::string reason;
};

// Examines every mesh of rdb that may get an automatic light texture (TraceMesh::automaticLightTextureAllowed,
// none yet) and has triangles. Deterministic for any thread count. rays grows by the shadow rays traced.
std::vector<MeshLightResolution> analyseLightResolution(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                                        const Integrator& integrator,
                                                        const LightResolutionSettings& settings,
                                                        uint64_t& rays);

// Runs the analysis on rdb and gives every mesh that needs texels an automatic light texture
// (rdb::addAutomaticLightTexture) at settings.texelsPerMetre, at most maxAtlasSize² texels per mesh (the
// density reduced to fit). Returns the analysis, one entry per mesh examined. Builds its own Integrator
// (no lit patches or portals: only the sun's and punctual lights' direct light is evaluated).
std::vector<MeshLightResolution> addNeededLightTextures(rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                                        const LightResolutionSettings& settings,
                                                        int maxAtlasSize = 512, int paddingTexels = 2);

}  // namespace fly::raytracer
