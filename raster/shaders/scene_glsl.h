// GLSL 4.50 sources of the engine's passes, as C++ raw strings. The renderer prepends "#version 450 core" and
// the variant's #defines (raster/renderer.cpp, Renderer::sceneProgram):
//   FLY_LIGHT_MAP  vertex light maps: L = albedo · E / π (+ emission), for meshes that have one
//   FLY_PHONG      the modified Phong (lights, the sun, the directional ambient term), for the others
//   FLY_SUN        the sun as a directional light (simple and sunlight modes)
//   FLY_TWO_SIDED  two-sided meshes: the vertex shader picks the front or back value by facing
//   FLY_GONIO      goniometric lights' tables
//   FLY_LIGHT_TEXTURE  light textures (with FLY_LIGHT_MAP): L = albedo · E_texel / π per fragment, bilinear, for
//                  meshes that have one
//   FLY_GLASS      clear glass: drawn in a second pass over a copy of the first, adding T(θ) times what lies
//                  behind it (rdb/raster_rdb.h, RasterMaterial::transmission)
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
#ifdef FLY_LIGHT_TEXTURE
layout(location = 6) in vec2 aLightMapUv;  // rdb/lightmap_uv.h's convention
// The slot of the mesh's front light texture (raster/renderer.cpp, uploadLightTextures); bit 31: the back's
// slot follows it; 0xffffffff: no light texture.
layout(location = 7) in uint aLightSlot;
out vec2 vLightMapUv;
flat out uint vLightSlot;      // the slot of the side this vertex faces, 0xffffffff: none
flat out vec3 vAlbedoOverPi;   // sr⁻¹
#endif

struct Material {
  vec4 diffuse;       // rgb albedo
  vec4 specular;      // rgb reflectance at normal incidence, w Blinn–Phong exponent
  vec4 emission;      // rgb cd/m²
  vec4 transmission;  // rgb clear transmission colour (0: not glass), w Schlick's F0 (< 0: uniform reflection)
  vec4 reflection;    // rgb reflection colour
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
#ifdef FLY_GLASS
out vec3 vTransmittance;  // T(θ) towards the eye
flat out uint vGlass;
#endif

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
#ifdef FLY_LIGHT_TEXTURE
  // The fragment shader adds albedo · E_texel / π in place of the vertex value.
  vLightMapUv = aLightMapUv;
  vAlbedoOverPi = m.diffuse.rgb / kPi;
  vLightSlot = 0xffffffffu;
  if (useLightMap && aLightSlot != 0xffffffffu) {
    vLightSlot = (aLightSlot & 0x7fffffffu) + ((back && (aLightSlot & 0x80000000u) != 0u) ? 1u : 0u);
    l = vec3(0.0);
  }
#endif
#ifdef FLY_PHONG
  if (!useLightMap) l = phong(m, aPositionM, back ? -n : n, toEye, aCorner);
#endif
  vLuminance = l + m.emission.rgb;
  vTwoSided = twoSided ? 1u : 0u;
#ifdef FLY_GLASS
  // The energy rule's transmittance at the angle the pane is seen (sdb::Material::effectiveAt): T(θ) =
  // t · (1 − clamp(r · F(θ))), F Schlick's, from either face.
  vGlass = 0u;
  vTransmittance = vec3(0.0);
  if (max(m.transmission.r, max(m.transmission.g, m.transmission.b)) > 0.0) {
    float f = 1.0;
    if (m.transmission.w >= 0.0) {
      float x = 1.0 - clamp(abs(dot(n, toEye)), 0.0, 1.0);
      float x2 = x * x;
      f = m.transmission.w + (1.0 - m.transmission.w) * x2 * x2 * x;
    }
    vTransmittance = m.transmission.rgb * (vec3(1.0) - clamp(m.reflection.rgb * f, 0.0, 1.0));
    vGlass = 1u;
  }
#endif
}
)GLSL";

// The luminance image's encoding, prepended to the passes that write or read it (raster/renderer.cpp): an
// RG32UI target, 8 bytes a pixel where RGBA32F takes 16 (the H100 writes pixels through its raster back end
// at a fixed rate in bytes: docs/benchmarks.md, fly-bench-raster). Linear RGB in cd/m² as three 19-bit
// mantissas with a shared 7-bit exponent: GL's RGB9E5 (EXT_texture_shared_exponent) widened to 64 bits.
// Range: a pixel's largest channel from 2⁻⁶⁴ ≈ 5.4·10⁻²⁰ to 9·10¹⁸ cd/m² (the sun's disc is ~1.6·10⁹); below
// that the pixel reads 0, above it is clamped. Accuracy: each channel within 2⁻¹⁹ ≈ 1.9·10⁻⁶ of the pixel's
// largest channel (round to nearest); 0 stays 0. Layout: x = r | g << 19 (g's low 13 bits), y = g >> 13 |
// b << 6 | (exponent + 64) << 25; decoded channel = mantissa · 2^(exponent − 19). Decoded on the CPU by
// Renderer::luminanceRgb (raster/renderer.cpp, decodeLuminance) the same way.
inline constexpr const char* kLuminanceEncoding = R"GLSL(
uvec2 flyEncodeLuminance(vec3 l) {
  vec3 c = min(max(l, vec3(0.0)), vec3(9.0e18));
  float m = max(c.r, max(c.g, c.b));
  if (!(m >= 5.421010862e-20)) return uvec2(0u);  // 2⁻⁶⁴; also NaN
  // m < 2^e ≤ 2m, e ∈ [−63, 63]; 2^(19 − e) built from its bits (exact, unlike exp2 on some GPUs).
  int e = int(floatBitsToUint(m) >> 23) - 126;
  float scale = uintBitsToFloat(uint(146 - e) << 23);
  uvec3 q = uvec3(c * scale + 0.5);
  if (max(q.r, max(q.g, q.b)) > 0x7ffffu) {  // m rounded up to 2^19: one more bit of exponent
    ++e;
    q = uvec3(c * (0.5 * scale) + 0.5);
  }
  return uvec2(q.r | (q.g << 19), (q.g >> 13) | (q.b << 6) | (uint(e + 64) << 25));
}
vec3 flyDecodeLuminance(uvec2 p) {
  uvec3 q = uvec3(p.x & 0x7ffffu, (p.x >> 19) | ((p.y & 0x3fu) << 13), (p.y >> 6) & 0x7ffffu);
  return vec3(q) * uintBitsToFloat(((p.y >> 25) + 44u) << 23);  // 2^(exponent + 64 − 83)
}
)GLSL";

// The back of a one-sided surface has no light value: it shows black (it still hides what is behind it, unless
// it is clear glass, whose both faces pass light).
inline constexpr const char* kSceneFragment = R"GLSL(
in vec3 vLuminance;
flat in uint vTwoSided;
layout(location = 0) out uvec2 oLuminance;  // kLuminanceEncoding
#ifdef FLY_GLASS
in vec3 vTransmittance;
flat in uint vGlass;
uniform int uGlassPass;                         // 0: all but the glass; 1: the glass alone
layout(binding = 4) uniform usampler2D uBehind;  // the first pass's image (kLuminanceEncoding)
#endif
#ifdef FLY_LIGHT_TEXTURE
in vec2 vLightMapUv;
flat in uint vLightSlot;
flat in vec3 vAlbedoOverPi;
// A slot's place in the array texture: rect = x, y, width, height (texels of the layer); layer = its index,
// 1 / layer width, 1 / layer height.
struct LightRect {
  vec4 rect;
  vec4 layer;
};
layout(std430, binding = 3) readonly buffer LightRects { LightRect lightRects[]; };
layout(binding = 2) uniform sampler2DArray uLightTextures;  // irradiance, lux
#endif
void main() {
#ifdef FLY_GLASS
  if ((vGlass != 0u) != (uGlassPass != 0)) discard;
#endif
  vec3 l = vLuminance;
#ifdef FLY_LIGHT_TEXTURE
  if (vLightSlot != 0xffffffffu) {
    LightRect r = lightRects[vLightSlot];
    // Bilinear, clamped to the edge of the slot's own texels (its neighbours in the layer are never read).
    vec2 t = clamp(vLightMapUv * r.rect.zw, vec2(0.5), r.rect.zw - vec2(0.5));
    l += vAlbedoOverPi * texture(uLightTextures, vec3((r.rect.xy + t) * r.layer.yz, r.layer.x)).rgb;
  }
#endif
  l = (gl_FrontFacing || vTwoSided != 0u) ? l : vec3(0.0);
#ifdef FLY_GLASS
  // Either face of a pane passes light.
  if (vGlass != 0u) l += vTransmittance * flyDecodeLuminance(texelFetch(uBehind, ivec2(gl_FragCoord.xy), 0).xy);
#endif
  oLuminance = flyEncodeLuminance(l);
}
)GLSL";

// The full-screen passes are compute shaders, one invocation per pixel: on GPUs whose graphics pipeline runs
// on a few of their processors (the H100's), they run on all of them and stay off the raster back end.

// The background in every pixel, before the scene is drawn over it (so the colour target needs no clear):
// black, or with FLY_SKY the sky dome (rdb/raster_sky.h: equirectangular over world directions, row 0 at the
// zenith) and the sun's disc in that pixel's direction.
inline constexpr const char* kBackgroundCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32ui) uniform writeonly uimage2D uLuminance;  // kLuminanceEncoding
#ifdef FLY_SKY
layout(binding = 0) uniform sampler2D uSky;
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
  if (p.x >= size.x || p.y >= size.y) return;
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
  imageStore(uLuminance, p, uvec4(flyEncodeLuminance(l), 0u, 0u));
}
)GLSL";

// Luminance (cd/m²) → display value → sRGB, with base/tone_map.h's GLSL (flyToneMap, flyEncodeSrgb).
inline constexpr const char* kToneMapCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 1, rg32ui) uniform readonly uimage2D uLuminance;  // kLuminanceEncoding
layout(binding = 0, rgba8) uniform writeonly image2D uDisplay;
uniform int uOperator;
uniform float uExposureScale;
uniform float uWhitePoint;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(uDisplay);
  if (p.x >= size.x || p.y >= size.y) return;
  vec3 l = flyDecodeLuminance(imageLoad(uLuminance, p).xy);
  imageStore(uDisplay, p, vec4(flyEncodeSrgb(flyToneMap(l, uOperator, uExposureScale, uWhitePoint)), 1.0));
}
)GLSL";

}  // namespace fly::raster::shaders
