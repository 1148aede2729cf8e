// GLSL 4.50 sources of the bloom passes (raster/bloom.h), as C++ raw strings; the engine prepends
// "#version 450 core" and shaders::kLuminanceEncoding.
#pragma once

namespace fly::raster::shaders {

// Linear RGB (cd/m²) above the threshold: L · max(Y − T, 0) / Y with Y the Rec. 709 luminance and T =
// uThresholdCdM2, so a pixel's colour is kept and only its part above T glows.
inline constexpr const char* kBloomBright = R"GLSL(
uniform float uThresholdCdM2;
vec3 flyBright(vec3 l) {
  float y = dot(l, vec3(0.2126, 0.7152, 0.0722));
  return y > uThresholdCdM2 ? l * ((y - uThresholdCdM2) / y) : vec3(0.0);
}
)GLSL";

// One level down: each pixel the finer level filtered by (1 3 3 1) / 8 per axis over the 4 × 4 finer pixels
// about its centre (a pixel past the finer level's edge counts as 0). Centred on the coarse pixel, so a point
// keeps its place at every level (a 2 × 2 box would move it by up to half a coarse pixel), and each finer pixel
// gives half its value per axis in all, so every level keeps the energy (Σ L times pixel area) of the one above.
// The first level reads the luminance image's bright part (FLY_BLOOM_FIRST), the others the level above.
inline constexpr const char* kBloomDownCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform writeonly image2D uDown;
#ifdef FLY_BLOOM_FIRST
layout(rg32ui, binding = 1) uniform readonly uimage2D uLuminance;  // kLuminanceEncoding
#else
layout(rgba32f, binding = 1) uniform readonly image2D uFiner;
#endif
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(px, imageSize(uDown)))) return;
#ifdef FLY_BLOOM_FIRST
  ivec2 finerSize = imageSize(uLuminance);
#else
  ivec2 finerSize = imageSize(uFiner);
#endif
  const float kWeight[4] = float[4](0.125, 0.375, 0.375, 0.125);
  vec3 sum = vec3(0.0);
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      ivec2 q = 2 * px + ivec2(i, j) - 1;
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, finerSize))) continue;
#ifdef FLY_BLOOM_FIRST
      vec3 v = flyBright(flyDecodeLuminance(imageLoad(uLuminance, q).xy));
#else
      vec3 v = imageLoad(uFiner, q).rgb;
#endif
      sum += kWeight[i] * kWeight[j] * v;
    }
  }
  imageStore(uDown, px, vec4(sum, 0.0));
}
)GLSL";

// A coarser level's value at a finer pixel: a 3×3 tent (1 2 1 / 16 per axis) of bilinear reads one coarse
// texel apart about the finer pixel's centre (Jimenez, "Next Generation Post Processing in Call of Duty:
// Advanced Warfare", SIGGRAPH 2014): a smooth upsampling whose weights sum to 1, so it keeps the mean.
inline constexpr const char* kBloomUpsample = R"GLSL(
layout(binding = 0) uniform sampler2D uCoarse;
uniform int uCoarseLevel;
vec3 flyUpsample(ivec2 finePx) {
  vec2 size = vec2(textureSize(uCoarse, uCoarseLevel));
  vec2 centre = (vec2(finePx) + 0.5) * 0.5 / size;
  vec2 d = 1.0 / size;
  vec3 s = vec3(0.0);
  for (int j = -1; j <= 1; ++j) {
    for (int i = -1; i <= 1; ++i) {
      float w = float((2 - abs(i)) * (2 - abs(j))) / 16.0;
      s += w * textureLod(uCoarse, centre + vec2(i, j) * d, float(uCoarseLevel)).rgb;
    }
  }
  return s;
}
)GLSL";

// One level up: u_k = d_k + U(u_{k+1}) in place (the coarsest level is its own u).
inline constexpr const char* kBloomUpCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform image2D uLevel;
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(px, imageSize(uLevel)))) return;
  imageStore(uLevel, px, vec4(imageLoad(uLevel, px).rgb + flyUpsample(px), 0.0));
}
)GLSL";

// The image with its glare: L − k B(L) + k U(u_0) / N, N the levels. U(u_0) / N is the mean over the levels of
// B blurred at each level's scale, which keeps B's energy: the glare moves the fraction k of the light above the
// threshold into a wide kernel around it and adds or removes nothing (up to what the kernel spreads past the
// image's edges).
inline constexpr const char* kBloomCompositeCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(rg32ui, binding = 1) uniform readonly uimage2D uLuminance;
layout(rg32ui, binding = 2) uniform writeonly uimage2D uOut;
uniform float uStrength;
uniform float uLevelCount;
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(px, imageSize(uOut)))) return;
  vec3 l = flyDecodeLuminance(imageLoad(uLuminance, px).xy);
  vec3 glare = flyUpsample(px) / uLevelCount;
  imageStore(uOut, px, uvec4(flyEncodeLuminance(max(l - uStrength * flyBright(l), vec3(0.0)) + uStrength * glare), 0u, 0u));
}
)GLSL";

}  // namespace fly::raster::shaders
