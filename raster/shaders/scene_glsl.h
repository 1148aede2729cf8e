// GLSL 4.50 sources of the engine's passes, as C++ raw strings. The renderer prepends "#version 450 core" and
// the variant's #defines (raster/renderer.cpp, Renderer::sceneProgram):
//   FLY_LIGHT_MAP  vertex light maps: L = albedo · E / π (+ emission), for meshes that have one
//   FLY_PHONG      the modified Phong (lights, the sun, the directional ambient term), for the others
//   FLY_SUN        the sun as a directional light (sunlight mode)
//   FLY_TWO_SIDED  two-sided meshes: the vertex shader picks the front or back value by facing
//   FLY_GONIO      goniometric lights' tables
// Units: positions in metres, world frame (+Y up); E in lux; L in cd/m².
#pragma once

namespace fly::raster::shaders {

// Per vertex: luminance towards the eye (cd/m², linear Rec.709) for the front and the back face. The whole
// scene is one draw: what differs between meshes comes per vertex in aSurface (bits 0–29 the material's
// index, bit 30 two-sided, bit 31 has a light map; raster/renderer.cpp, surfaceBits).
inline constexpr const char* kSceneVertex = R"GLSL(
layout(location = 0) in vec3 aPositionM;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aCorner;
layout(location = 3) in vec3 aFrontLux;
layout(location = 4) in vec3 aBackLux;
layout(location = 5) in uint aSurface;

struct Material {
  vec4 diffuse;   // rgb albedo
  vec4 specular;  // rgb reflectance at normal incidence, w Blinn–Phong exponent
  vec4 emission;  // rgb cd/m²
};
layout(std430, binding = 0) readonly buffer Materials { Material materials[]; };

struct Light {
  vec4 positionType;    // xyz metres, w type (0 point, 1 spot, 2 directional, 3 goniometric)
  vec4 directionRange;  // xyz unit direction it points, w range (m; ≤ 0 = none)
  vec4 cAxisOffset;     // xyz goniometric C = 0° axis, w first table value
  vec4 intensity;       // rgb cd (directional: lux)
  vec4 cone;            // x cos inner, y cos outer
};
layout(std430, binding = 1) readonly buffer Lights { Light lights[]; };
#ifdef FLY_GONIO
layout(std430, binding = 2) readonly buffer Gonio { float gonioCd[]; };
#endif

uniform mat4 uClipFromWorld;
uniform vec3 uEyeM;          // perspective: the eye; orthographic: unused
uniform vec3 uViewDirWorld;  // orthographic: the viewing direction (unit)
uniform int uOrthographic;
uniform int uLightCount;
uniform vec3 uAmbientUpLux;
uniform vec3 uAmbientDownLux;
uniform vec3 uSunDirWorld;   // unit, towards the sun
uniform vec3 uSunNormalLux;  // illuminance on a surface facing the sun

out vec3 vLuminance;
flat out uint vTwoSided;

const float kPi = 3.14159265358979;
const float kCornerGain = FLY_CORNER_GAIN;

#ifdef FLY_GONIO
// Bilinear in γ and C over the table at `offset` (rdb/raster_rdb.h: kRasterGonioGammaSteps ×
// kRasterGonioCSteps, C-major), towards `dir` (unit, world) in the frame (axis, cAxis, axis × cAxis).
float flyGonioCd(int offset, vec3 axis, vec3 cAxis, vec3 dir) {
  const int G = FLY_GONIO_GAMMA_STEPS;
  const int C = FLY_GONIO_C_STEPS;
  float gamma = acos(clamp(dot(dir, axis), -1.0, 1.0)) / kPi * float(G - 1);
  float c = atan(dot(dir, cross(axis, cAxis)), dot(dir, cAxis)) / (2.0 * kPi);
  if (c < 0.0) c += 1.0;
  c *= float(C);
  int g0 = min(int(gamma), G - 2);
  float fg = clamp(gamma - float(g0), 0.0, 1.0);
  int c0 = min(int(c), C - 1);
  int c1 = (c0 + 1) % C;
  float fc = clamp(c - float(c0), 0.0, 1.0);
  float a = mix(gonioCd[offset + c0 * G + g0], gonioCd[offset + c0 * G + g0 + 1], fg);
  float b = mix(gonioCd[offset + c1 * G + g0], gonioCd[offset + c1 * G + g0 + 1], fg);
  return mix(a, b, fc);
}
#endif

#ifdef FLY_PHONG
// Direct illuminance on the surface (lux) and the Blinn–Phong lobe towards `toEye`.
void addLight(vec3 p, vec3 n, vec3 toEye, vec3 toLight, vec3 eLux, float exponent, inout vec3 diffuseLux,
              inout vec3 specularLux) {
  float cosSurface = dot(n, toLight);
  if (cosSurface <= 0.0) return;
  diffuseLux += eLux * cosSurface;
  vec3 h = normalize(toLight + toEye);
  specularLux += eLux * cosSurface * (exponent + 8.0) / (8.0 * kPi) * pow(max(dot(n, h), 0.0), exponent);
}

vec3 phong(Material m, vec3 p, vec3 n, vec3 toEye, float corner) {
  vec3 diffuseLux = vec3(0.0);
  vec3 specularLux = vec3(0.0);
  for (int i = 0; i < uLightCount; ++i) {
    Light l = lights[i];
    int type = int(l.positionType.w);
    if (type == 2) {
      addLight(p, n, toEye, -l.directionRange.xyz, l.intensity.rgb, m.specular.w, diffuseLux, specularLux);
      continue;
    }
    vec3 d = l.positionType.xyz - p;
    float dist2 = dot(d, d);
    if (dist2 <= 1e-12) continue;
    vec3 toLight = d * inversesqrt(dist2);
    float window = 1.0;
    if (l.directionRange.w > 0.0) {
      float r = sqrt(dist2) / l.directionRange.w;
      window = max(0.0, 1.0 - r * r * r * r);
      window *= window;
    }
    float cd = 1.0;
    if (type == 1) {
      float scale = 1.0 / max(0.001, l.cone.x - l.cone.y);
      float t = clamp((dot(-toLight, l.directionRange.xyz) - l.cone.y) * scale, 0.0, 1.0);
      cd = t * t;
    }
#ifdef FLY_GONIO
    if (type == 3) cd = flyGonioCd(int(l.cAxisOffset.w), l.directionRange.xyz, l.cAxisOffset.xyz, -toLight);
#endif
    addLight(p, n, toEye, toLight, l.intensity.rgb * (cd * window / dist2), m.specular.w, diffuseLux,
             specularLux);
  }
#ifdef FLY_SUN
  addLight(p, n, toEye, uSunDirWorld, uSunNormalLux, m.specular.w, diffuseLux, specularLux);
#endif
  // The directional ambient term (rdb/raster_rdb.h, DirectionalAmbient).
  vec3 ambientLux = (uAmbientUpLux * (1.0 + n.y) * 0.5 + uAmbientDownLux * (1.0 - n.y) * 0.5) *
                    (1.0 + kCornerGain * corner);
  return m.diffuse.rgb / kPi * (diffuseLux + ambientLux) + m.specular.rgb * specularLux;
}
#endif

void main() {
  gl_Position = uClipFromWorld * vec4(aPositionM, 1.0);
  vec3 toEye = uOrthographic != 0 ? -uViewDirWorld : normalize(uEyeM - aPositionM);
  vec3 n = normalize(aNormal);
  bool twoSided = (aSurface & 0x40000000u) != 0u;
  bool back = false;
#ifdef FLY_TWO_SIDED
  back = twoSided && dot(n, toEye) < 0.0;
#endif
  Material m = materials[aSurface & 0x3fffffffu];
  vec3 l = vec3(0.0);
  bool useLightMap = false;
#ifdef FLY_LIGHT_MAP
  useLightMap = (aSurface & 0x80000000u) != 0u;
  if (useLightMap) {
#ifdef FLY_TWO_SIDED
    l = m.diffuse.rgb * (back ? aBackLux : aFrontLux) / kPi;
#else
    l = m.diffuse.rgb * aFrontLux / kPi;
#endif
  }
#endif
#ifdef FLY_PHONG
  if (!useLightMap) l = phong(m, aPositionM, back ? -n : n, toEye, aCorner);
#endif
  vLuminance = l + m.emission.rgb;
  vTwoSided = twoSided ? 1u : 0u;
}
)GLSL";

// The back of a one-sided surface has no light value: it shows black (it still hides what is behind it).
inline constexpr const char* kSceneFragment = R"GLSL(
in vec3 vLuminance;
flat in uint vTwoSided;
layout(location = 0) out vec4 oLuminance;
void main() {
  oLuminance = vec4((gl_FrontFacing || vTwoSided != 0u) ? vLuminance : vec3(0.0), 1.0);
}
)GLSL";

// The full-screen passes are compute shaders, one invocation per pixel: on GPUs whose graphics pipeline runs on
// a few of their processors (the H100's), they run on all of them and stay off the raster back end.

// The background: every pixel the scene left empty (depth still 1, the cleared value) gets black, or with
// FLY_SKY the sky dome (rdb/raster_sky.h: equirectangular over world directions, row 0 at the zenith) and the
// sun's disc in that pixel's direction. So the colour target needs no clear.
inline constexpr const char* kBackgroundCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D uDepth;
layout(binding = 0, rgba32f) uniform writeonly image2D uLuminance;
#ifdef FLY_SKY
layout(binding = 1) uniform sampler2D uSky;
uniform mat3 uWorldFromCamera;  // rotation
uniform vec2 uTanHalfFov;       // perspective: tan of the half angles in x and y; orthographic: 0
uniform vec3 uSunDirWorld;
uniform vec3 uSunRadianceCdM2;
uniform float uSunCosHalfAngle;  // > 1 when there is no sun
const float kPi = 3.14159265358979;
#endif
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(uLuminance);
  if (p.x >= size.x || p.y >= size.y || texelFetch(uDepth, p, 0).r < 1.0) return;
  vec3 l = vec3(0.0);
#ifdef FLY_SKY
  vec2 ndc = (vec2(p) + 0.5) / vec2(size) * 2.0 - 1.0;  // the pixel's centre
  vec3 d = normalize(uWorldFromCamera * vec3(ndc * uTanHalfFov, -1.0));
  float phi = atan(d.z, d.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  float theta = acos(clamp(d.y, -1.0, 1.0));
  l = textureLod(uSky, vec2(phi / (2.0 * kPi), theta / kPi), 0.0).rgb;
  if (dot(d, uSunDirWorld) >= uSunCosHalfAngle) l += uSunRadianceCdM2;
#endif
  imageStore(uLuminance, p, vec4(l, 1.0));
}
)GLSL";

// Luminance (cd/m²) → display value → sRGB, with base/tone_map.h's GLSL (flyToneMap, flyEncodeSrgb).
inline constexpr const char* kToneMapCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D uLuminance;
layout(binding = 0, rgba8) uniform writeonly image2D uDisplay;
uniform int uOperator;
uniform float uExposureScale;
uniform float uWhitePoint;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(uDisplay);
  if (p.x >= size.x || p.y >= size.y) return;
  vec3 l = texelFetch(uLuminance, p, 0).rgb;
  imageStore(uDisplay, p, vec4(flyEncodeSrgb(flyToneMap(l, uOperator, uExposureScale, uWhitePoint)), 1.0));
}
)GLSL";

}  // namespace fly::raster::shaders
