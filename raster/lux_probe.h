// The viewer's lux probe: the baked illuminance, and its standard error, at the surface under the mouse. A
// ray through the pixel (the renderer's projection: raster/renderer.h, View) is intersected on the CPU with
// the RasterRdb's triangles (Möller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle Intersection"), and
// the bake's per-vertex values are interpolated at the hit with its barycentric coordinates, as the GL engine
// interpolates the vertex light map across a triangle. No GL: the viewer and the tests call it alike.
#pragma once

#include <cstdint>
#include <optional>

#include "base/color.h"
#include "base/math.h"
#include "raster/renderer.h"
#include "rdb/light_map_store.h"
#include "rdb/lightmap_uv.h"
#include "rdb/raster_rdb.h"

namespace fly::raster {

struct PickRay {
  vec3 originWorld{0.0f};
  vec3 dirWorld{0.0f, 0.0f, -1.0f};  // unit
};

// The ray through the point (xPx, yPx) of an image widthPx × heightPx seen through `view` (x to the right and
// y down from the image's top left corner, pixel centres at half-integers, as a window's cursor).
// Perspective: from the eye; orthographic: from the near plane's point, along the view direction.
PickRay pickRay(const View& view, double xPx, double yPx, uint32_t widthPx, uint32_t heightPx);

// Where `pointWorld` appears in that image (pixels from the top left, as pickRay takes them); nullopt for a
// point behind a perspective view's eye.
std::optional<vec2> projectToImage(const View& view, const vec3& pointWorld, uint32_t widthPx,
                                   uint32_t heightPx);

// The nearest triangle the ray hits (either face), at distance > 0.
struct SurfaceHit {
  uint32_t triangle = 0;  // index of the triangle (its vertices: rdb.indices[3·triangle + 0..2])
  uint32_t mesh = 0;      // index into rdb.meshes
  float distanceM = 0.0f;
  // The hit point's barycentric coordinates: weights of the triangle's three vertices, summing to 1.
  vec3 barycentric{1.0f, 0.0f, 0.0f};
  vec3 pointWorld{0.0f};
  // The ray meets the back of the surface: the side of −(interpolated vertex normal).
  bool back = false;
};
std::optional<SurfaceHit> pickSurface(const rdb::RasterRdb& rdb, const PickRay& ray);
// Of the hits at 0 < distance ≤ maxDistanceM, the one nearest the ray's point at targetDistanceM (metres
// along it): the surface nearest a given point, on either side of it (fly probe). pickSurface: target 0, no
// limit.
// Of coincident surfaces at the same distance, the one whose front faces the ray (as back-face culling shows).
std::optional<SurfaceHit> pickSurfaceNear(const rdb::RasterRdb& rdb, const PickRay& ray,
                                          float targetDistanceM, float maxDistanceM);

// What the probe reads at a hit on a baked surface.
struct LuxReading {
  vec3 pointWorld{0.0f};
  uint32_t sdbNodeId = 0;
  bool back = false;  // the back side's light map (two-sided meshes)
  // The bake's irradiance there, lux per channel, and its luminance (photometric: the illuminance).
  Rgb illuminanceLux{0.0f};
  float illuminanceLuminanceLux = 0.0f;
  // The standard error of illuminanceLuminanceLux, lux: the vertices' estimates are independent, so the
  // interpolation Σ wᵢ Eᵢ has the error √(Σ wᵢ² σᵢ²), with each vertex's σᵢ the luminance of its per-channel
  // standard errors (the channels come from the same samples, as the bake's manifest takes it); from a light
  // texture, its texel's. nullopt when the store kept no standard errors for the mesh.
  std::optional<float> stdErrorLuminanceLux;
  // The value is the texel of the mesh's light texture at the interpolated light-map UV (the bake's mean over
  // the texel's footprint) instead of the vertices' interpolation.
  bool fromLightTexture = false;
};

// The baked illuminance at `hit`, or nullopt when the hit mesh has no light map. `store` supplies the
// standard errors (rdb::MeshLightMap::frontStdErrorLux, its light texture's frontStdErrorLux; found by the
// mesh's SDB ids), may be null.
std::optional<LuxReading> probeIlluminance(const rdb::RasterRdb& rdb, const rdb::LightMapStore* store,
                                           const SurfaceHit& hit);

}  // namespace fly::raster
