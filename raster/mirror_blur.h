// A glossy planar reflector's image blurred as its lobe spreads the light, keeping the light: the reflected
// light summed over a region is the sharp image's (a scatter, not a gather, so a near object's light spreads by
// its own distance behind the mirror whatever lies beside it). Each pixel of the mirrored pass's rectangle
// gets the radius over which the lobe spreads its light (from its depth: shaders/mirror_blur_glsl.h) and a
// level λ = log2(2r) of a pyramid whose texels are 2^k pixels wide; its light settles at levels ⌊λ⌋ and ⌊λ⌋ + 1
// (linearly by frac(λ)). Down the pyramid each texel is the mean of its 2 × 2 finer ones (what has not settled
// yet); up it each level adds the coarser one read bilinearly. Every step moves light and loses none, so the
// blurred image keeps the sharp one's light away from the rectangle's border (there each texel stands for its
// pixels inside the rectangle, and the bilinear reads clamp to it). Only the rectangle's texels are computed
// and read: what lies outside it in the textures is never used. Cost per reflector and frame: one depth copy
// and about 2 × 4/3 passes over the rectangle's pixels, in 2 · levels dispatches; the reflector's fragment
// reads 5 texels (level 0 and level 1 bilinearly, shaders::kMirrorBlurUpsample).
// Needs a current context for its whole life.
#pragma once

#include <cstdint>
#include <vector>

#include "base/math.h"
#include "raster/sun_shadows.h"

namespace fly::raster {

// What decides how far a glossy reflector's lobe spreads the light of its image's pixels.
struct MirrorLobe {
  mat4 worldFromClip{1.0f};  // the mirrored pass's (with its oblique near plane)
  vec4 planeWorld{0.0f};     // the mirror: n, −d (n · p − d = 0, n towards the viewer)
  // Perspective: xyz the mirrored eye (world, m), w = 1; orthographic: xyz the view direction, w = 0.
  vec4 eye{0.0f};
  float alpha = 0.0f;     // GGX α of the reflection lobe
  float pxPerTan = 0.0f;  // > 0: pixels per unit of tan(angle from the view axis); < 0: −pixels per metre
};

// The pixels of a reflector's mirrored pass: x, y, width, height (bottom-left origin, as glScissor).
struct MirrorRect {
  int x = 0, y = 0, width = 0, height = 0;
};

class MirrorBlur {
 public:
  explicit MirrorBlur(SunShadows::Compile compile);
  ~MirrorBlur();
  MirrorBlur(const MirrorBlur&) = delete;
  MirrorBlur& operator=(const MirrorBlur&) = delete;

  // Blurs reflector `k`'s image (RG32UI, shaders::kLuminanceEncoding) in `rect` of a widthPx × heightPx
  // target; `depth` is the mirrored pass's depth renderbuffer (DEPTH24_STENCIL8) of the same size.
  void blur(uint32_t k, unsigned image, unsigned depth, const MirrorRect& rect, uint32_t widthPx, uint32_t heightPx,
            const MirrorLobe& lobe);
  // Reflector k's settled pyramid (RGBA32F, cd/m²): level 0 plus level 1 read by kMirrorBlurUpsample with
  // coarseRegion(k) is the blurred image at a pixel of its rectangle.
  unsigned pyramid(uint32_t k) const { return reflectors_.at(k).pyramid; }
  // Level 1's texels for that read (lo.xy, hi.xy exclusive); empty where the pyramid has one level.
  const int* coarseRegion(uint32_t k) const { return reflectors_.at(k).coarseRegion; }

 private:
  struct Reflector {
    unsigned pyramid = 0;
    int coarseRegion[4] = {0, 0, 0, 0};
  };
  void resize(uint32_t widthPx, uint32_t heightPx);
  SunShadows::Compile compile_;
  unsigned split_ = 0, down_ = 0, up_ = 0;
  unsigned passing_ = 0, depth_ = 0;  // shared by the reflectors: used only while one is blurred
  std::vector<Reflector> reflectors_;
  int levels_ = 0;
  uint32_t width_ = 0, height_ = 0;
};

}  // namespace fly::raster
