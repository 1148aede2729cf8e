// Screen-space ambient occlusion for simple mode, where no light map holds the scene's own shadowing of its
// ambient light: a depth pre-pass of the opaque scene, a normal-oriented hemisphere estimate per pixel
// (shaders/ambient_occlusion_glsl.h, kAoCompute) and a depth-aware 4×4 blur, at full resolution. The scene
// programs multiply their directional ambient term alone by the result (FLY_SSAO); the lamps' and the sun's
// direct light are not occluded (they have their own shadows or none). Made and compiled only when enabled.
// Needs a current context for its whole life.
#pragma once

#include <functional>

#include "base/math.h"
#include "raster/sun_shadows.h"

namespace fly::raster {

struct AmbientOcclusionSettings {
  bool enabled = false;  // off: nothing is made, compiled or run, and the image is what it is without
  float radiusM = 0.5f;  // the hemisphere's radius in metres, (0, 1e4]: occluders farther away do not count
};

class AmbientOcclusion {
 public:
  explicit AmbientOcclusion(SunShadows::Compile compile);
  ~AmbientOcclusion();
  AmbientOcclusion(const AmbientOcclusion&) = delete;
  AmbientOcclusion& operator=(const AmbientOcclusion&) = delete;

  // Draws the opaque scene's depth (drawDepth issues the draws with the scene's vertex array bound; the depth
  // program is bound here) from clipFromCamera · cameraFromWorld into its own depth target, then estimates
  // and blurs the occlusion. The result, texture(), is an R16F image of widthPx × heightPx in [0, 1] (1:
  // open).
  void run(const mat4& clipFromCamera, const mat4& cameraFromWorld, bool orthographic, uint32_t widthPx,
           uint32_t heightPx, float radiusM, const std::function<void()>& drawDepth);
  unsigned texture() const { return ao_; }

 private:
  void resize(uint32_t widthPx, uint32_t heightPx);
  SunShadows::Compile compile_;
  unsigned depthProgram_ = 0, aoProgram_ = 0, blurProgram_ = 0;
  unsigned depth_ = 0, fbo_ = 0, raw_ = 0, ao_ = 0;
  uint32_t width_ = 0, height_ = 0;
};

}  // namespace fly::raster
