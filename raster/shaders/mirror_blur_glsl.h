// GLSL 4.50 sources of a glossy planar reflector's blur (raster/mirror_blur.h), as C++ raw strings; the engine
// prepends "#version 450 core" (and shaders::kLuminanceEncoding to the first pass).
#pragma once

namespace fly::raster::shaders {

// Level `level + 1` of a settled pyramid read bilinearly at pixel `p` of level `level` (a 2× finer grid: the
// coarse texels at ±1/4 and ±3/4 of a coarse texel, weights 3/4 and 1/4 per axis), its texels clamped to
// `coarseRegion` (lo.xy, hi.xy exclusive): the texels outside it hold nothing defined. Each coarse texel gives
// its 2 × 2 finer pixels' worth in all (per axis 3/4 + 3/4 + 1/4 + 1/4 = 2, the clamped edge texel 1 + 3/4 +
// 1/4), so the upsampling keeps the light (Σ L times pixel area).
inline constexpr const char* kMirrorBlurUpsample = R"GLSL(
vec3 flyMirrorUpsample(sampler2D pyramid, ivec2 p, int level, ivec4 coarseRegion) {
  vec2 u = (vec2(p) + 0.5) * 0.5 - 0.5;
  ivec2 i0 = ivec2(floor(u));
  vec2 f = u - vec2(i0);
  ivec2 a = clamp(i0, coarseRegion.xy, coarseRegion.zw - 1), b = clamp(i0 + 1, coarseRegion.xy, coarseRegion.zw - 1);
  int l = level + 1;
  return mix(mix(texelFetch(pyramid, a, l).rgb, texelFetch(pyramid, ivec2(b.x, a.y), l).rgb, f.x),
             mix(texelFetch(pyramid, ivec2(a.x, b.y), l).rgb, texelFetch(pyramid, b, l).rgb, f.x), f.y);
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

// Level uLevel ≥ 1 of the settled pyramid plus the level below it upsampled (kMirrorBlurUpsample), from the
// coarsest up: each level then holds the light settled there and at every coarser level, each spread by its
// own level's texels. Level 0 is summed where the reflector reads it (shaders::kSurfaceFragment).
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
  vec3 l = imageLoad(uSettled, p).rgb + flyMirrorUpsample(uPyramid, p, uLevel, uCoarseRegion);
  imageStore(uSettled, p, vec4(l, 1.0));
}
)GLSL";

}  // namespace fly::raster::shaders
