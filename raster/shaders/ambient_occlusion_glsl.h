// GLSL 4.50 sources of the screen-space ambient occlusion passes (raster/ambient_occlusion.h), as C++ raw
// strings; the engine prepends "#version 450 core".
#pragma once

namespace fly::raster::shaders {

// The depth pre-pass: the opaque scene's window depth, nothing else (the scene's vertex array: aPositionM at
// location 0).
inline constexpr const char* kAoDepthVertex = R"GLSL(
layout(location = 0) in vec3 aPositionM;
uniform mat4 uClipFromWorld;
void main() { gl_Position = uClipFromWorld * vec4(aPositionM, 1.0); }
)GLSL";

inline constexpr const char* kAoDepthFragment = R"GLSL(
void main() {}
)GLSL";

// A pixel's camera-space point (metres; the camera looks down −Z) from the depth texture, shared by both
// compute passes. Window depth 1 (nothing drawn) is kept just below 1 so an infinite far plane stays finite.
inline constexpr const char* kAoCameraPoint = R"GLSL(
layout(binding = 0) uniform sampler2D uDepth;  // window depth in [0, 1], read per pixel
uniform mat4 uCameraFromClip;
uniform ivec2 uSizePx;
vec3 flyCameraPoint(vec2 windowPx, float depth) {
  vec4 clip = vec4(windowPx / vec2(uSizePx) * 2.0 - 1.0, min(depth, 0.99999988) * 2.0 - 1.0, 1.0);
  vec4 c = uCameraFromClip * clip;
  return c.xyz / c.w;
}
vec3 flyPixelPoint(ivec2 px) {
  px = clamp(px, ivec2(0), uSizePx - 1);
  return flyCameraPoint(vec2(px) + 0.5, texelFetch(uDepth, px, 0).r);
}
)GLSL";

// The occlusion estimate per pixel: a normal-oriented hemisphere (Crytek's SSAO, Mittring 2007, with the
// hemisphere of Bavoil & Sainz's normal-oriented variant): kAoSamples points p + ε n + t_i R d_i, the d_i
// cosine-distributed about the normal n (reconstructed from the depth of the neighbours, flyPlanarStep),
// t_i in [0.1, 1]. A point lies in an occluder where the depth buffer, read bilinearly (flyBilinearDepth) at
// its projection (window depth is affine over a plane, so a plane reads exactly), is nearer than it; an
// occluder farther than R in depth from p counts less (smoothstep(0, 1, R / Δz), the range check). AO = 1 −
// the occluded fraction: the cosine-weighted fraction of the hemisphere left open within R, so a point on an
// open plane reads 1 and a point on the edge line of a 90° inner corner ½ (the wall takes half of the
// cosine-weighted hemisphere by symmetry). The sample pattern turns by 2π k/16 with the pixel's index k in a 4×4
// Bayer tile, which kAoBlurCompute averages away.
inline constexpr const char* kAoCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(r16f, binding = 0) uniform writeonly image2D uRawAo;
uniform mat4 uClipFromCamera;
uniform float uRadiusM;
uniform int uOrthographic;
const int kAoSamples = 16;
const float kTwoPi = 6.28318530718;
// The camera-space step to the neighbour along `axis` on the side that continues the pixel's own plane:
// window depth is affine over a plane, so the side whose next two pixels extrapolate the pixel's depth best
// (the smaller second difference) lies on its surface, not across a crease or a silhouette. A side whose two
// pixels are not both inside the image is never taken: its clamped reads repeat the pixel itself, a zero step
// and so an undefined normal at the image's border.
float flyDepthAt(ivec2 px) { return texelFetch(uDepth, clamp(px, ivec2(0), uSizePx - 1), 0).r; }
// Window depth at a window point, bilinear between the four nearest pixels in full float precision: the
// texture unit's own filter weighs with a few bits of sub-texel position (8 on NVIDIA), which on a floor seen
// at a grazing angle reads a plane several ‰ of its depth step off, enough to occlude the plane with itself.
float flyBilinearDepth(vec2 windowPx) {
  vec2 f = windowPx - 0.5;
  ivec2 i = ivec2(floor(f));
  vec2 w = f - vec2(i);
  return mix(mix(flyDepthAt(i), flyDepthAt(i + ivec2(1, 0)), w.x),
             mix(flyDepthAt(i + ivec2(0, 1)), flyDepthAt(i + ivec2(1, 1)), w.x), w.y);
}
vec3 flyPlanarStep(ivec2 px, float depth, ivec2 axis) {
  bool plusInside = all(lessThan(px + 2 * axis, uSizePx));
  bool minusInside = all(greaterThanEqual(px - 2 * axis, ivec2(0)));
  float plus = abs(2.0 * flyDepthAt(px + axis) - flyDepthAt(px + 2 * axis) - depth);
  float minus = abs(2.0 * flyDepthAt(px - axis) - flyDepthAt(px - 2 * axis) - depth);
  vec3 p = flyPixelPoint(px);
  bool takePlus = plusInside && (!minusInside || plus <= minus);
  return takePlus ? flyPixelPoint(px + axis) - p : p - flyPixelPoint(px - axis);
}
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(px, uSizePx))) return;
  float depth = texelFetch(uDepth, px, 0).r;
  if (depth >= 1.0) {
    imageStore(uRawAo, px, vec4(1.0));
    return;
  }
  vec3 p = flyPixelPoint(px);
  vec3 normal = cross(flyPlanarStep(px, depth, ivec2(1, 0)), flyPlanarStep(px, depth, ivec2(0, 1)));
  if (!(dot(normal, normal) > 0.0)) {  // an image under 3 pixels across: no plane to read, left open
    imageStore(uRawAo, px, vec4(1.0));
    return;
  }
  vec3 n = normalize(normal);
  vec3 toEye = uOrthographic != 0 ? vec3(0.0, 0.0, 1.0) : -p;
  if (dot(n, toEye) < 0.0) n = -n;
  vec3 t = normalize(cross(abs(n.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), n));
  vec3 b = cross(n, t);
  const int kBayer[16] = int[16](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);
  float turn = kTwoPi * float(kBayer[(px.y & 3) * 4 + (px.x & 3)]) / 16.0;
  vec3 origin = p + n * (0.02 * uRadiusM);
  float occluded = 0.0;
  for (int i = 0; i < kAoSamples; ++i) {
    float u = (float(i) + 0.5) / float(kAoSamples);
    float sinTheta = sqrt(u), cosTheta = sqrt(1.0 - u);  // cosine-weighted: pdf = cos θ / π
    float phi = kTwoPi * fract(float(i) * 0.618034) + turn;
    vec3 d = (t * cos(phi) + b * sin(phi)) * sinTheta + n * cosTheta;
    vec3 s = origin + d * (uRadiusM * mix(0.1, 1.0, fract((float(i) + 0.5) * 0.381966)));
    vec4 c = uClipFromCamera * vec4(s, 1.0);
    vec2 windowPx = (c.xy / c.w * 0.5 + 0.5) * vec2(uSizePx);
    if (any(lessThan(windowPx, vec2(0.0))) || any(greaterThan(windowPx, vec2(uSizePx)))) continue;
    float sceneDepth = flyBilinearDepth(windowPx);
    if (sceneDepth >= 1.0) continue;
    float sceneZ = flyCameraPoint(windowPx, sceneDepth).z;
    if (sceneZ > s.z + 1.0e-4 * abs(s.z)) {
      occluded += smoothstep(0.0, 1.0, uRadiusM / max(abs(p.z - sceneZ), 1.0e-6));
    }
  }
  imageStore(uRawAo, px, vec4(1.0 - occluded / float(kAoSamples)));
}
)GLSL";

// The bilateral blur: the mean over the 4×4 pixels [x − 2, x + 1] × [y − 2, y + 1] (each of the pattern's 16
// turns once) of those whose depth lies within R/2 of the pixel's, so occlusion does not bleed across depth
// edges.
inline constexpr const char* kAoBlurCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(r16f, binding = 0) uniform writeonly image2D uAo;
layout(binding = 1) uniform sampler2D uRawAo;
uniform float uRadiusM;
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(px, uSizePx))) return;
  float z = flyPixelPoint(px).z;
  float sum = 0.0, weight = 0.0;
  for (int j = -2; j <= 1; ++j) {
    for (int i = -2; i <= 1; ++i) {
      ivec2 q = px + ivec2(i, j);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, uSizePx))) continue;
      if (abs(flyPixelPoint(q).z - z) > 0.5 * uRadiusM) continue;
      sum += texelFetch(uRawAo, q, 0).r;
      weight += 1.0;
    }
  }
  imageStore(uAo, px, vec4(sum / weight));
}
)GLSL";

// Prepended to the scene's stages with FLY_SSAO (raster/renderer.cpp, Renderer::sceneProgram): phong() keeps
// its ambient luminance, albedo · E_ambient / π, in flyAmbientLuminance, which the fragment stage scales by the
// pixel's AO (flyAmbientOcclusion): the ambient term alone is occluded, never the lamps' or the sun's light.
inline constexpr const char* kAoAmbientCommon = R"GLSL(
#ifdef FLY_SSAO
vec3 flyAmbientLuminance = vec3(0.0);
#endif
)GLSL";

inline constexpr const char* kAoAmbientLookup = R"GLSL(
#ifdef FLY_SSAO
layout(binding = 15) uniform sampler2D uAmbientOcclusion;
float flyAmbientOcclusion() { return texelFetch(uAmbientOcclusion, ivec2(gl_FragCoord.xy), 0).r; }
#endif
)GLSL";

}  // namespace fly::raster::shaders
