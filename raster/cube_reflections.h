// Cube environment maps of curved reflectors (FLY §5; rdb::RasterRdb::cubeReflectors): per reflector, the
// scene without it rendered into six 90° views from its centre, each view's luminance image (cd/m²,
// shaders::kLuminanceEncoding) stored as a face of an EnvironmentLight's source cube, which then gets the
// GGX-prefiltered levels its glossiness reads (raster/environment_light.h). The renderer draws the views
// (Renderer::render: only when the scene, its light or the mode changed, not every frame) and shades the
// reflector by the split sum with these maps in place of the sky's. A reflector with reflection fog
// (rdb::RasterMaterial::reflectionFogDistanceM D) keeps per texel, in alpha, the fog's share t = min(d / D, 1)
// of what the texel shows, d its distance from the centre (1 for the sky), prefiltered with the radiance; the
// reflector's fragment fades what its lobe sees to the fog by it. Needs a current context.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "raster/environment_light.h"
#include "raster/renderer.h"

namespace fly::raster {

// A reflector's maps: 64² faces (a face texel spans 1.4° at its centre), 6 prefiltered levels (α = 0, 0.04,
// 0.16 … 1) of 128 GGX samples a texel, an 8² irradiance cube, a 32² split-sum table.
inline constexpr EnvironmentSettings kCubeReflectionSettings{.cubePx = 64, .radianceLevels = 6,
                                                             .prefilterSamples = 128, .irradiancePx = 8,
                                                             .irradianceQuadPx = 16, .tablePx = 32,
                                                             .tableSamples = 512};

class CubeReflections {
 public:
  explicit CubeReflections(EnvironmentLight::Compile compile, const EnvironmentSettings& settings = kCubeReflectionSettings);
  ~CubeReflections();
  CubeReflections(const CubeReflections&) = delete;
  CubeReflections& operator=(const CubeReflections&) = delete;

  // The view of face f (0 … 5 = +X, −X, +Y, −Y, +Z, −Z) from `centreM`: 90° square, near plane `nearM`,
  // oriented so that pixel (x, y) of its image (rows from the bottom, as GL draws them) is texel (x, y) of the
  // face in the OpenGL cube-map table (no mirroring: the view's basis is right-handed).
  static View faceView(uint32_t face, const vec3& centreM, float nearM);

  uint32_t facePx() const { return settings_.cubePx; }
  // A face drawn: its luminance texture (GL_RG32UI, kLuminanceEncoding) and, for reflection fog, its depth
  // texture (a depth format read as depth, 1 = nothing) with the view's worldFromClip.
  struct Face {
    unsigned luminance = 0;
    unsigned depth = 0;
    mat4 worldFromClip{1.0f};
  };
  // Captures reflector k (made on first use): drawFace(view) draws one face into a facePx² target, which
  // becomes the face; then the maps are built. fogDistanceM: the reflector's reflection fog distance (m; ∞:
  // none, and drawFace need return no depth).
  void capture(uint32_t k, const vec3& centreM, float nearM, float fogDistanceM,
               const std::function<Face(const View&)>& drawFace);
  // Reflector k's maps (capture must have run for it).
  const EnvironmentLight& maps(uint32_t k) const { return *maps_.at(k); }
  size_t count() const { return maps_.size(); }

 private:
  EnvironmentLight::Compile compile_;
  EnvironmentSettings settings_;
  unsigned decode_ = 0;  // compute program: a face's luminance image into the source cube
  std::vector<std::unique_ptr<EnvironmentLight>> maps_;
};

}  // namespace fly::raster
