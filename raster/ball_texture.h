// FLY's ball textures (§4): per measured material (rdb::RasterMeasuredBrdf) and frame, the image of a unit
// ball of that material under the current lights, seen along the view direction, which the scene pass
// applies to the material's objects by reflection mapping (shaders/scene_glsl.h, FLY_MEASURED).
//
// FLY computed the ball at the vertices of a mesh refined around each light's reflection direction, because a
// 2004 GPU could evaluate the BRDF only per vertex; here a compute pass evaluates it at every texel, so every
// texel is exact (no interpolation between vertices, no refinement to place) and all lights go into one pass
// (docs/ball-textures.md). Lights are distant lights from the centre of the material's objects: the sun, and
// point, spot and goniometric lights by their direction and illuminance there (distantLights), except those
// near the objects, which the scene pass evaluates per pixel (BallSettings::nearLightRadii); the
// environment (the sky image, or the directional ambient term's two hemispheres) is integrated over a grid of
// half vectors per texel of a smaller image of its own that the ball reads bilinearly (shaders/
// ball_texture_glsl.h, kBallCompute).
//
// Each ball has two layers of RGBA32F: the lights and the environment, and the sun alone (so the sun's shadow
// pass and its glass transmittance can drop or scale it); a = the luminance of the irradiance (lux) the
// layer's light gives a surface with the texel's normal (the light-map modes' ratio, raster/renderer.h). A
// ball is remade only when what it depends on changes: the view's rotation, its lights (directions and
// illuminance), its environment, its BRDF or the settings; its frame (ballFrame) follows the direction from
// the material's objects to the eye, so in a perspective view walking past them remakes it too. Needs a
// current context.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "raster/sun_shadows.h"
#include "rdb/raster_rdb.h"

namespace fly::raster {

struct BallSettings {
  uint32_t sizePx = 256;       // N × N texels per ball, [8, 4096]
  // The environment term is made at M × M texels, [4, N], and read bilinearly by the ball: the sky is smooth
  // and its integral over a lobe smoother, so a quarter of the ball's resolution costs 1/16 of the work.
  uint32_t envSizePx = 64;
  uint32_t envGridSteps = 16;  // the environment quadrature's half-vector grid, steps per axis, [1, 256]
  // Point, spot and goniometric lights nearer to a material's centre than this many times the radius of its
  // objects (RasterMeasuredBrdf::radiusM) are evaluated per pixel, with each pixel's own direction and
  // distance, instead of as distant lights in its ball (at most kMaxNearLights, the nearest): the distant-light
  // approximation errs by about 1.6 R/d (docs/ball-textures.md). [0, ∞); 0 puts every light in the ball.
  float nearLightRadii = 50.0f;

  bool operator==(const BallSettings&) const = default;
};

// The most lamps a measured material's pixels evaluate themselves (BallSettings::nearLightRadii).
inline constexpr uint32_t kMaxNearLights = 8;

// A light as a distant light from a point: the unit direction towards it (world) and the illuminance it
// gives a surface there facing it (lux).
struct DistantLight {
  vec3 toLightWorld{0, 1, 0};
  Rgb illuminanceLux{0.0f};
  uint32_t light = 0;  // index into RasterRdb::lights
};

// A ball's frame: the view's rotation, and in a perspective view turned by the least rotation that takes the
// direction from `centreM` to the eye onto +Z, so that the ball is seen as the material's objects are and
// sphere mapping errs only by the objects' own angular extent, not by their angle off the view axis (a
// centre behind the eye keeps the view's rotation).
mat3 ballFrame(const mat3& viewFromWorld, const vec3& eyeM, bool orthographic, const vec3& centreM);

// The scene's lights (not the sun) as distant lights from `centreM`: directional ones as they are, point,
// spot and goniometric ones towards their position with I(direction) · window / d² (the same falloffs as
// the Phong's, shaders/scene_glsl.h). Lights at the centre itself or giving nothing there are left out.
std::vector<DistantLight> distantLights(const rdb::RasterRdb& rdb, const vec3& centreM);

// What lights the balls in a frame.
struct BallLighting {
  mat3 viewFromWorld{1.0f};  // the view's rotation
  vec3 eyeM{0.0f};           // perspective: the eye (world)
  bool orthographic = false;
  bool sun = false;
  vec3 sunDirWorld{0, 1, 0};  // unit, towards the sun
  Rgb sunLux{0.0f};           // the sun's illuminance on a surface facing it
  // The environment: the sky image (unit 1 while the balls are made; the renderer's sky texture), or two
  // uniform hemispheres of radiance upLux / π above the horizon and downLux / π below, or none.
  enum class Environment { kNone, kHemispheres, kSky } environment = Environment::kNone;
  unsigned skyTexture = 0;
  uint64_t skyVersion = 0;  // changes whenever the sky image does
  Rgb upLux{0.0f}, downLux{0.0f};
};

class BallTextures {
 public:
  explicit BallTextures(SunShadows::Compile compile);
  ~BallTextures();
  BallTextures(const BallTextures&) = delete;
  BallTextures& operator=(const BallTextures&) = delete;

  // std::invalid_argument for values out of range.
  void setSettings(const BallSettings& settings);
  const BallSettings& settings() const { return settings_; }
  // Uploads the BRDFs of `rdb` (its measuredBrdfs); every ball is made again at the next update.
  void setBrdfs(const rdb::RasterRdb& rdb);
  // Makes the balls whose inputs changed since they were last made; returns how many it made.
  int update(const rdb::RasterRdb& rdb, const BallLighting& lighting);

  // The GL_TEXTURE_2D_ARRAY of all balls: brdf k's layers are 2k (lights and environment) and 2k + 1 (sun).
  unsigned texture() const;
  // Ball k's frame as last made: the view's rotation, turned (perspective) so that its +Z points from the
  // material's centre to the eye (ballFrame).
  const mat3& ballFromWorld(uint32_t k) const { return ballFromWorld_.at(k); }
  // The lights ball k leaves to its material's pixels (indices into RasterRdb::lights), as of the last update.
  const std::vector<int>& nearLights(uint32_t k) const { return nearLights_.at(k); }
  // The BRDFs' block buffer and table texture (shaders/ball_texture_glsl.h, kMeasuredBrdf), which the scene
  // pass reads for the near lights; the texture is 0 without tables.
  unsigned brdfBuffer() const;
  unsigned tableTexture() const;
  // One layer read back, RGBA floats, N × N, rows from the bottom (y = −1) up.
  std::vector<float> readLayer(uint32_t layer) const;

 private:
  struct Gpu;
  std::unique_ptr<Gpu> gpu_;
  SunShadows::Compile compile_;
  BallSettings settings_;
  std::vector<std::vector<float>> keys_;  // per ball: what it was made from (empty: not made)
  std::vector<mat3> ballFromWorld_;
  std::vector<std::vector<int>> nearLights_;
  uint32_t brdfCount_ = 0;
};

}  // namespace fly::raster
