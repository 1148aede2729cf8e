// The sun through clear glass in the GL engine: a sun-view transmittance map, so that the real-time sun term
// of a surface behind a pane is T(θ) times what it is in the open, as the baker's shadow rays attenuate it
// (rdb::RasterMaterial: T(θ) = transmission · (1 − reflection · F(θ)), F Schlick's of fresnelF0, or 1 for
// uniform reflection; θ between the sun's direction and the pane's normal).
//
// The map. An orthographic view from the sun, fitted to the clear-glass triangles' projection (square texels
// of side t = extent / N, N = SunShadowSettings::transmittanceMapTexels), one RGBA32F target cleared to
// (1, 1, 1, −∞). Every glass triangle is drawn into it with blending: RGB multiplies by the pane's T(θ_sun)
// (glBlendFunc(GL_ZERO, GL_SRC_COLOR)), A keeps the largest height h = dot(p, sunDir) (metres along the
// direction towards the sun; GL_MAX), the pane nearest the sun. A texel thus holds the product of the T of
// every pane over its centre, and the height of the highest.
//
// The lookup (shaders::kSunGlassLookup, FLY_SUN_GLASS): a receiver at p reads the texel p projects into
// (nearest, no filtering: heights of different panes must not mix); outside the map, or where
// dot(p, sunDir) ≥ h − bias, it gets 1 (between the highest pane and the sun, or beside every pane), else
// the texel's RGB. The bias is 2 t: within a texel a pane's height varies by up to (√2 / 2) · t · tan θ from
// its height at the centre, so a pane's own surface and what touches it reads unattenuated up to
// tan θ = 2√2 (θ ≈ 70°). Panes do not attenuate their own sun term (kSceneFragment skips glass fragments).
//
// Limits. The edge of a pane's patch follows the texels (t), not the pane's edge: nearest lookup gives a
// jagged rim up to a texel wide; a window's frame, which casts its shadow volume (raster/sun_shadows.h),
// usually covers it. A receiver between two panes over one texel gets both panes' T (the map keeps only
// the product), where the baker's ray crosses only the upper one; and a receiver less than the bias behind a
// pane gets none.
//
// Built only when the scene has clear glass, a sun above the horizon and a program that draws the sun's
// term; rebuilt only when the sun's direction, the geometry, the materials or the map's size change.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "base/math.h"
#include "raster/sun_shadows.h"
#include "rdb/raster_rdb.h"

namespace fly::raster {

// What the last build drew (tests, `fly render`'s report).
struct SunGlassCounts {
  uint32_t glassTriangles = 0;  // clear-glass triangles drawn into the map
  uint32_t texels = 0;          // per side
  float texelSizeM = 0.0f;      // t
};

class SunGlassMap {
 public:
  explicit SunGlassMap(SunShadows::Compile compile);
  ~SunGlassMap();
  SunGlassMap(const SunGlassMap&) = delete;
  SunGlassMap& operator=(const SunGlassMap&) = delete;

  // The clear-glass triangles of `rdb` (rdb::RasterMaterial::transmission > 0) with their materials' T
  // inputs; then the next build() rebuilds. Returns their count.
  size_t setGlass(const rdb::RasterRdb& rdb);
  // Renders the map for the sun direction (unit, towards the sun) at `texels` per side when either differs
  // from the last build's or the glass changed; returns whether it did. Nothing without glass.
  bool build(const vec3& sunDirWorld, uint32_t texels);
  bool empty() const;

  // For the scene programs (shaders::kSunGlassLookup): the map (RGB the product of T, A the highest pane's
  // height in metres), world → (u, v in [0, 1] across the map, h = dot(p, sunDir) in metres), and the bias
  // (m).
  unsigned texture() const;
  const mat4& mapFromWorld() const;
  float biasM() const;
  SunGlassCounts counts() const;

 private:
  struct Gpu;
  std::unique_ptr<Gpu> gpu_;
  SunShadows::Compile compile_;
};

}  // namespace fly::raster
