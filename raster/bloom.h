// Bloom (glare): the light of the sun's disc and of bright highlights scattered around them, as in the eye
// and the camera's lens, on the linear luminance image before the display transform (tone mapping), where the
// light's energy is still known (the thesis's order: bright part, blur, combine, then tone-map). The part of
// each pixel above a threshold, B = L · max(Y − T, 0) / Y, is blurred at every scale of a mip chain (2×2 box
// down, 3×3 tent up; shaders/bloom_glsl.h) and the fraction `strength` of it moved there: L' = L − k B +
// k blur(B). The kernel's weights sum to 1, so the image's energy (Σ L over the pixels) is kept: glare
// redistributes light, it adds none (exact away from the image's edges, where the coarse levels' bilinear
// reads clamp). Made and compiled only when enabled. Needs a current context for its whole life.
#pragma once

#include <cstdint>

#include "raster/sun_shadows.h"

namespace fly::raster {

struct BloomSettings {
  float strength = 0.0f;  // k in [0, 1]: the fraction of the light above the threshold that spreads; 0: off
  // T relative to the exposure: the exposed value x = L / Lmax (base/tone_map.h, Lmax = 1.2 · 2^EV100 cd/m²)
  // above which light glows, > 0. 1: what the display saturates at with the linear operator.
  float thresholdExposed = 1.0f;
};

class Bloom {
 public:
  explicit Bloom(SunShadows::Compile compile);
  ~Bloom();
  Bloom(const Bloom&) = delete;
  Bloom& operator=(const Bloom&) = delete;

  // `luminance` (RG32UI, shaders::kLuminanceEncoding, widthPx × heightPx) with its glare, into an image of
  // the same kind that this object owns and returns; `exposureScale` is 1 / Lmax in m²/cd.
  unsigned apply(unsigned luminance, uint32_t widthPx, uint32_t heightPx, float exposureScale,
                 const BloomSettings& settings);

 private:
  void resize(uint32_t widthPx, uint32_t heightPx);
  SunShadows::Compile compile_;
  unsigned firstDown_ = 0, down_ = 0, up_ = 0, composite_ = 0;
  unsigned chain_ = 0, out_ = 0;
  int levels_ = 0;
  uint32_t width_ = 0, height_ = 0;
};

}  // namespace fly::raster
