// GLSL 4.50 sources of a glossy planar reflector's blur (raster/mirror_blur.h), as C++ raw strings; the engine
// prepends "#version 450 core" (and shaders::kLuminanceEncoding to the first pass).
#pragma once

namespace fly::raster::shaders {

// Reads of a settled pyramid (texels at integer positions u, a texel's centre at u = its index), its texels
// clamped to `region` (lo.xy, hi.xy exclusive): the texels outside it hold nothing defined.
// flyMirrorBilinear: level `level` read bilinearly at u. Read at the centres of an s-times finer grid
// (u = (p + 0.5) / s − 0.5, s a power of two), each texel gives its s × s finer pixels' worth in all (the tent's
// samples at spacing 1/s sum to s per axis, at any offset; a clamped edge texel takes what lies beyond it), so
// the read keeps the light (Σ L times pixel area); at s = 1 it is the texel itself.
// flyMirrorTaps: the mean of uMirrorTapCount such reads at u + uMirrorTaps[i] (offsets in that level's
// texels along the lobe's wide axis on screen: raster/mirror_blur.h, mirrorBlurTaps), each of which keeps the
// light: one read at u for an isotropic lobe, a line of reads that stretches the blur for an anisotropic one.
inline constexpr const char* kMirrorBlurUpsample = R"GLSL(
#define FLY_MAX_MIRROR_TAPS 20
uniform int uMirrorTapCount;
uniform vec2 uMirrorTaps[FLY_MAX_MIRROR_TAPS];
vec3 flyMirrorBilinear(sampler2D pyramid, vec2 u, int level, ivec4 region) {
  u = clamp(u, vec2(region.xy), vec2(region.zw - 1));
  ivec2 a = ivec2(floor(u));
  vec2 f = u - vec2(a);
  ivec2 b = min(a + 1, region.zw - 1);
  return mix(mix(texelFetch(pyramid, a, level).rgb, texelFetch(pyramid, ivec2(b.x, a.y), level).rgb, f.x),
             mix(texelFetch(pyramid, ivec2(a.x, b.y), level).rgb, texelFetch(pyramid, b, level).rgb, f.x), f.y);
}
vec3 flyMirrorTaps(sampler2D pyramid, vec2 u, int level, ivec4 region) {
  vec3 l = vec3(0.0);
  for (int i = 0; i < uMirrorTapCount; ++i) l += flyMirrorBilinear(pyramid, u + uMirrorTaps[i], level, region);
  return l / float(max(uMirrorTapCount, 1));
}
)GLSL";

// Level 0: each pixel of the mirrored pass's rectangle (uRect: x, y, width, height) decoded, and its light
// split by how far the glossy lobe spreads it. A GGX lobe of α reflects half its light within about 2α rad of
// the mirror direction: a point at distance D behind the mirror along the reflected ray, the mirror at E from
// the eye, is spread over a radius r = 2α · D / (E + D) in tan units (uPxPerTan > 0 pixels per unit), 2α · D
// metres orthographically (uPxPerTan < 0: −pixels per metre); the sky (depth 1) over the full 2α (a quarter of
// the image orthographically). The point's level λ = log2(2r) is the one whose texels are as wide as its
// spread: the fraction 1 − frac(λ) of its light settles at level ⌊λ⌋, the rest one level coarser. Level 0
// keeps max(1 − λ, 0) (uSettled) and passes the rest down with λ (uPass: rgb, a = λ).
// With the mirrored eye e' (uEye.w = 1) the ray e' → q crosses the mirror at the fraction t = E / (E + D) of
// its length, so D / (E + D) = 1 − t from the heights of e' and q over the mirror's plane (uPlane: n, −d).
inline constexpr const char* kMirrorBlurSplit = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(rg32ui, binding = 0) uniform readonly uimage2D uImage;  // kLuminanceEncoding
layout(binding = 0) uniform sampler2D uDepth;                  // the mirrored pass's window depth
layout(rgba32f, binding = 1) uniform writeonly image2D uSettled;
layout(rgba32f, binding = 2) uniform writeonly image2D uPass;
uniform ivec4 uRect;
uniform mat4 uWorldFromClip;  // the mirrored pass's
uniform vec4 uPlane;
uniform vec4 uEye;  // xyz: the mirrored eye (w = 1, perspective) or the view direction (w = 0, orthographic)
uniform float uAlpha;
uniform float uPxPerTan;
uniform vec2 uTargetPx;
float flySpreadPx(ivec2 p) {
  float widest = uPxPerTan > 0.0 ? 2.0 * uAlpha * uPxPerTan : 0.25 * uTargetPx.y;
  float z = texelFetch(uDepth, p, 0).r;
  if (z >= 1.0) return widest;
  vec4 q = uWorldFromClip * vec4((vec2(p) + 0.5) / uTargetPx * 2.0 - 1.0, z * 2.0 - 1.0, 1.0);
  float hq = max(dot(uPlane.xyz, q.xyz / q.w) + uPlane.w, 0.0);  // metres in front of the mirror
  if (uEye.w > 0.0) {
    float he = dot(uPlane.xyz, uEye.xyz) + uPlane.w;  // the mirrored eye: behind the mirror, < 0
    return widest * clamp(1.0 - he / min(he - hq, -1e-12), 0.0, 1.0);
  }
  return min(-2.0 * uAlpha * uPxPerTan * hq / max(abs(dot(uPlane.xyz, uEye.xyz)), 1e-6), widest);
}
void main() {
  if (any(greaterThanEqual(gl_GlobalInvocationID.xy, uvec2(uRect.zw)))) return;
  ivec2 p = uRect.xy + ivec2(gl_GlobalInvocationID.xy);
  vec3 l = flyDecodeLuminance(imageLoad(uImage, p).xy);
  float level = log2(max(2.0 * flySpreadPx(p), 1.0));
  float settles = clamp(1.0 - level, 0.0, 1.0);
  imageStore(uSettled, p, vec4(settles * l, 1.0));
  imageStore(uPass, p, vec4((1.0 - settles) * l, level));
}
)GLSL";

// Level uLevel ≥ 1 (its texels uRegion, the finer level's uFinerRegion: lo.xy, hi.xy exclusive): each texel
// the mean of its 2 × 2 finer texels of uPass that lie in the finer region (the mean over what exists: at the
// rectangle's border a texel stands for its pixels inside it). Of each finer texel's light of level λ the
// fraction min(uLevel + 1 − λ, 1) settles here (all of it at the coarsest level, uCoarsest) and the rest
// passes on with λ; the passing light's λ is the light-weighted mean of its texels'. Each texel's light goes
// to exactly one of the two, so the pyramid keeps the light.
inline constexpr const char* kMirrorBlurDown = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 1) uniform writeonly image2D uSettled;
layout(rgba32f, binding = 2) uniform writeonly image2D uPass;
layout(rgba32f, binding = 3) uniform readonly image2D uFinerPass;
uniform ivec4 uRegion;
uniform ivec4 uFinerRegion;
uniform float uLevel;
uniform bool uCoarsest;
void main() {
  ivec2 p = uRegion.xy + ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, uRegion.zw))) return;
  vec3 settled = vec3(0.0), passing = vec3(0.0);
  float levelSum = 0.0, weight = 0.0, n = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 c = 2 * p + ivec2(k & 1, k >> 1);
    if (any(lessThan(c, uFinerRegion.xy)) || any(greaterThanEqual(c, uFinerRegion.zw))) continue;
    vec4 f = imageLoad(uFinerPass, c);
    float settles = uCoarsest ? 1.0 : clamp(uLevel + 1.0 - f.a, 0.0, 1.0);
    settled += settles * f.rgb;
    vec3 rest = (1.0 - settles) * f.rgb;
    passing += rest;
    float w = rest.r + rest.g + rest.b;
    levelSum += w * f.a;
    weight += w;
    n += 1.0;
  }
  n = max(n, 1.0);
  imageStore(uSettled, p, vec4(settled / n, 1.0));
  imageStore(uPass, p, vec4(passing / n, weight > 0.0 ? levelSum / weight : uLevel + 1.0));
}
)GLSL";

// Level uLevel ≥ 1 of the settled pyramid plus the level above it read 2× finer (kMirrorBlurUpsample's
// flyMirrorTaps), from the coarsest down: each level then holds the light settled there and at every coarser
// level, each spread by its own level's texels (and stretched along the lobe's wide axis by the taps). Level 0
// and level 1 are summed where the reflector reads them (shaders::kSurfaceFragment).
inline constexpr const char* kMirrorBlurUp = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 1) uniform image2D uSettled;  // level uLevel
layout(binding = 1) uniform sampler2D uPyramid;         // the same texture, read at level uLevel + 1
uniform ivec4 uRegion;
uniform ivec4 uCoarseRegion;
uniform int uLevel;
void main() {
  ivec2 p = uRegion.xy + ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, uRegion.zw))) return;
  vec3 l = imageLoad(uSettled, p).rgb + flyMirrorTaps(uPyramid, (vec2(p) + 0.5) * 0.5 - 0.5, uLevel + 1, uCoarseRegion);
  imageStore(uSettled, p, vec4(l, 1.0));
}
)GLSL";

}  // namespace fly::raster::shaders
