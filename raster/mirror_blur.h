// A glossy planar reflector's image blurred as its lobe spreads the light, keeping the light: the reflected
// light summed over a region is the sharp image's (a scatter, not a gather, so a near object's light spreads by
// its own distance behind the mirror whatever lies beside it). Each pixel of the mirrored pass's rectangle
// gets the radius over which the lobe spreads its light (from its depth: shaders/mirror_blur_glsl.h) and a
// level λ = log2(2r) of a pyramid whose texels are 2^k pixels wide; its light settles at levels ⌊λ⌋ and ⌊λ⌋ + 1
// (linearly by frac(λ)). Down the pyramid each texel is the mean of its 2 × 2 finer ones (what has not settled
// yet); up it each level adds the coarser one read bilinearly. Every step moves light and loses none, so the
// blurred image keeps the sharp one's light away from the rectangle's border (there each texel stands for its
// pixels inside the rectangle, and the bilinear reads clamp to it). Only the rectangle's texels are computed
// and read: what lies outside it in the textures is never used.
// An anisotropic lobe (wider along one axis of the surface) is blurred by the radius of its narrow axis, and
// every read of a coarser level (the up passes' and the reflector's) is the mean of a line of bilinear reads
// along the wide axis's direction on screen (mirrorBlurTaps): each keeps the light, and their spread adds to
// the blur's along that axis alone, by the same share at every level, so the blur's widths along and across
// the axis stand as the lobe's.
// The pass may be drawn at a lower resolution than the image (Renderer: 1/2 or 1/4 per axis where the
// lobe's spread is wide): the pyramid is the pass's, and the reflector reads its level 0 bilinearly, s times
// finer. Cost per reflector and frame: one depth copy and about 2 × 4/3 passes over the rectangle's pass
// pixels, in 2 · levels − 1 dispatches (the reflectors' dispatches of a level share their memory barriers);
// the reflector's fragment reads 4 texels of level 0 and 4 per tap of level 1 (shaders::kMirrorBlurUpsample).
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
  float alpha = 0.0f;     // GGX α of the reflection lobe (an anisotropic lobe's narrow α)
  float pxPerTan = 0.0f;  // in the pass's pixels: > 0 per unit of tan(angle from the view axis); < 0: −per metre
  // An anisotropic lobe: its wide axis's direction on screen (unit, in pixels) and its widths' ratio
  // α_wide / α_narrow (1: isotropic).
  vec2 wideAxis{1.0f, 0.0f};
  float aspect = 1.0f;
};

// The pixels of a reflector's mirrored pass: x, y, width, height (bottom-left origin, as glScissor).
struct MirrorRect {
  int x = 0, y = 0, width = 0, height = 0;
};

// The most reads along a lobe's wide axis (shaders::kMirrorBlurUpsample's FLY_MAX_MIRROR_TAPS): the widest
// anisotropy's (base/ggx.h: α_t / α_b = 10 at |U − V| = 1) are then 1.06 texels apart.
inline constexpr int kMaxMirrorTaps = 20;

// The pyramid's isotropic blur of a small emitter in the engine against the two-level model below (its variance
// at λ = 3, 4 and 5: 1.48, 1.57 and 1.52 times the model's; tests/raster/planar_reflection_test.cpp,
// AnisotropicGlossyMirrorBlursAlongItsWideAxis): it has a fainter, wider tail than the model, which the reads
// along the axis (whose added variance is the model's, within 8 %) are scaled to match.
inline constexpr float kMirrorBlurVarianceRatio = 1.5f;

// The offsets (in texels of the level read, along `wideAxis`) of the reads that stretch the blur of a lobe of
// widths' ratio `aspect` ≥ 1 along its wide axis. In the model, the pyramid's blur of light settled at level
// K has a variance of (4^K − 1) / 3 px² per axis (the down passes' 2 × 2 means (4^K − 1) / 12, the up passes'
// bilinear reads (4^K − 1) / 4), and reads of variance V texels² at every level 1 … K add 4 V (4^K − 1) / 3
// along the axis, so V = (aspect² − 1) / 4 (times kMirrorBlurVarianceRatio) makes the widths' ratio `aspect`
// at every level. n equally weighted reads spaced h ≤ 1 texel apart (so that their bilinear footprints join
// into a line): h² (n² − 1) / 12 = V. One read at 0 for an isotropic lobe.
std::vector<vec2> mirrorBlurTaps(const vec2& wideAxis, float aspect);

class MirrorBlur {
 public:
  explicit MirrorBlur(SunShadows::Compile compile);
  ~MirrorBlur();
  MirrorBlur(const MirrorBlur&) = delete;
  MirrorBlur& operator=(const MirrorBlur&) = delete;

  // Reflector `k`'s image (RG32UI, shaders::kLuminanceEncoding) in `rect` of its widthPx × heightPx pass split
  // by its pixels' spread into the pyramid's level 0 (right after its pass: the image and `depth`, the pass's
  // depth renderbuffer of DEPTH24_STENCIL8 at least that size, are read here). finish() then blurs every
  // reflector split since the last finish(), level by level: the reflectors' dispatches of one level run
  // between the same two memory barriers.
  void split(uint32_t k, unsigned image, unsigned depth, const MirrorRect& rect, uint32_t widthPx,
             uint32_t heightPx, const MirrorLobe& lobe);
  void finish();
  // Reflector k's settled pyramid (RGBA32F, cd/m²): level 0 read by flyMirrorBilinear within fineRegion(k)
  // plus level 1 read by flyMirrorTaps (with taps(k)) within coarseRegion(k) is the blurred image.
  unsigned pyramid(uint32_t k) const { return reflectors_.at(k).pyramid; }
  const int* fineRegion(uint32_t k) const { return reflectors_.at(k).fineRegion; }
  // Level 1's texels for that read (lo.xy, hi.xy exclusive); empty where the pyramid has one level.
  const int* coarseRegion(uint32_t k) const { return reflectors_.at(k).coarseRegion; }
  // The offsets of level 1's reads (flyMirrorTaps' uMirrorTaps), as the up passes used them.
  const std::vector<vec2>& taps(uint32_t k) const { return reflectors_.at(k).taps; }

 private:
  struct Reflector {
    unsigned pyramid = 0, passing = 0;  // the settled light, and the light still to be spread (a = its λ)
    uint32_t width = 0, height = 0, passingWidth = 0, passingHeight = 0;
    int levels = 0, passingLevels = 0;  // the textures' levels
    int fineRegion[4] = {0, 0, 0, 0};
    int coarseRegion[4] = {0, 0, 0, 0};
    std::vector<vec2> taps;
    MirrorRect rect;     // the last split's
    int blurLevels = 0;  // the levels it needs
    bool pending = false;  // split, not yet blurred
  };
  // `texture` made (or remade) to hold `levels` levels of a widthPx × heightPx pass: each level k at least
  // ⌈size / 2^k⌉ texels (level 0 rounded up to a multiple of 2^(levels − 1)).
  static void ensure(unsigned& texture, uint32_t& width, uint32_t& height, int& levels, uint32_t widthPx,
                     uint32_t heightPx, int wantLevels, bool depthStencil);
  SunShadows::Compile compile_;
  unsigned split_ = 0, down_ = 0, up_ = 0;
  // Uniform locations: split (rect, worldFromClip, plane, eye, alpha, pxPerTan, targetPx), down (region,
  // finerRegion, level, coarsest), up (region, coarseRegion, level).
  int splitRect_ = -1, splitWorldFromClip_ = -1, splitPlane_ = -1, splitEye_ = -1, splitAlpha_ = -1,
      splitPxPerTan_ = -1, splitTargetPx_ = -1;
  int downRegion_ = -1, downFinerRegion_ = -1, downLevel_ = -1, downCoarsest_ = -1;
  int upRegion_ = -1, upCoarseRegion_ = -1, upLevel_ = -1, upTapCount_ = -1, upTaps_ = -1;
  // Shared by the reflectors: used only while one is split.
  unsigned depth_ = 0;
  uint32_t depthWidth_ = 0, depthHeight_ = 0;
  int depthLevels_ = 0;
  std::vector<Reflector> reflectors_;
};

}  // namespace fly::raster
