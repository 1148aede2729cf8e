// GLSL 4.50 sources of the image-based light (raster/environment_light.h): the environment as a cube map,
// its GGX-prefiltered mip levels and diffuse irradiance, and the split-sum table. Units: radiance in cd/m²,
// irradiance in lux. Cube faces and texel directions follow the OpenGL specification's table (§8.13,
// "Cube Map Texture Selection"): face 0 … 5 = +X, −X, +Y, −Y, +Z, −Z.
#pragma once

namespace fly::raster::shaders {

// What the passes share: the direction of a cube texel, and GGX (Walter et al. 2007, eq. 33; Smith Λ,
// Heitz 2014, eq. 72, as base/ggx.h) with a low-discrepancy point set.
inline constexpr const char* kEnvironmentCommon = R"GLSL(
const float kPi = 3.14159265358979;

// The unit direction through (s, t) ∈ [−1, 1]² of cube face `face` (the inverse of the specification's
// selection: s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2).
vec3 flyCubeDirection(int face, vec2 st) {
  float s = st.x, t = st.y;
  vec3 d;
  if (face == 0) d = vec3(1.0, -t, -s);
  else if (face == 1) d = vec3(-1.0, -t, s);
  else if (face == 2) d = vec3(s, 1.0, t);
  else if (face == 3) d = vec3(s, -1.0, -t);
  else if (face == 4) d = vec3(s, -t, 1.0);
  else d = vec3(-s, -t, -1.0);
  return normalize(d);
}

// Texel (x, y) of an n × n face at (s, t) = its centre.
vec2 flyCubeTexelCentre(ivec2 texel, int n) { return (vec2(texel) + 0.5) / float(n) * 2.0 - 1.0; }

float flyGgxD(float cosH, float a2) {
  float d = cosH * cosH * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}
float flyGgxLambda(float cosTheta, float a2) {
  float c2 = cosTheta * cosTheta;
  if (c2 >= 1.0) return 0.0;
  return 0.5 * (sqrt(1.0 + a2 * (1.0 - c2) / max(c2, 1e-12)) - 1.0);
}
// Point k of n of the Hammersley set (van der Corput radical inverse in base 2).
vec2 flyHammersley(uint k, uint n) { return vec2((float(k) + 0.5) / float(n), float(bitfieldReverse(k)) * 2.3283064365386963e-10); }
// A normal of the GGX distribution D(h) cos θh around +z (Walter et al. 2007, eqs. 35–36): tan² θh = α² u/(1 − u).
vec3 flyGgxSampleNormal(vec2 u, float a2) {
  float cos2 = (1.0 - u.x) / (1.0 + (a2 - 1.0) * u.x);
  float cosH = sqrt(cos2), sinH = sqrt(max(0.0, 1.0 - cos2));
  float phi = 2.0 * kPi * u.y;
  return vec3(sinH * cos(phi), sinH * sin(phi), cosH);
}
// An orthonormal frame with z = n, as columns.
mat3 flyFrameAround(vec3 n) {
  vec3 t = normalize(cross(abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), n));
  return mat3(t, cross(n, t), n);
}
)GLSL";

// The cube's level 0 from the equirectangular image (rdb::RasterSky's layout: u = φ/2π with φ = atan2(z, x),
// v = θ/π from the zenith +Y), each texel the mean of 4 × 4 bilinear samples across it.
inline constexpr const char* kEnvironmentFromEquirect = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D uEquirect;
layout(binding = 0, rgba32f) uniform writeonly imageCube uCube;
uniform int uSize;
vec3 flyEquirect(vec3 d) {
  float phi = atan(d.z, d.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  float theta = acos(clamp(d.y, -1.0, 1.0));
  return textureLod(uEquirect, vec2(phi / (2.0 * kPi), theta / kPi), 0.0).rgb;
}
void main() {
  ivec3 id = ivec3(gl_GlobalInvocationID);
  if (id.x >= uSize || id.y >= uSize) return;
  vec3 sum = vec3(0.0);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      sum += flyEquirect(flyCubeDirection(id.z, (vec2(id.xy) + (vec2(i, j) + 0.5) / 4.0) / float(uSize) * 2.0 - 1.0));
  imageStore(uCube, id, vec4(sum / 16.0, 1.0));
}
)GLSL";

// One level of the source's mip chain from the one above it: each texel the solid-angle-weighted mean of its
// 2 × 2 children (a texel at a face's centre spans up to 5.2 times the solid angle of one at its corner, which
// a plain box filter would weight alike, biasing coarse levels against whatever lies at the faces' centres).
inline constexpr const char* kEnvironmentDownsample = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform readonly imageCube uFine;
layout(binding = 1, rgba32f) uniform writeonly imageCube uCoarse;
uniform int uSize;  // the coarse level's face size
float flyCornerArea(float x, float y) { return atan(x * y, sqrt(x * x + y * y + 1.0)); }
void main() {
  ivec3 id = ivec3(gl_GlobalInvocationID);
  if (id.x >= uSize || id.y >= uSize) return;
  float step = 1.0 / float(uSize);  // a child's side in s, t
  vec4 sum = vec4(0.0);  // alpha too: a cube reflector's fog weight (raster/cube_reflections.h)
  float weight = 0.0;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      ivec2 child = 2 * id.xy + ivec2(i, j);
      float s0 = -1.0 + float(child.x) * step, t0 = -1.0 + float(child.y) * step;
      float s1 = s0 + step, t1 = t0 + step;
      float sr = flyCornerArea(s0, t0) - flyCornerArea(s0, t1) - flyCornerArea(s1, t0) + flyCornerArea(s1, t1);
      sum += imageLoad(uFine, ivec3(child, id.z)) * sr;
      weight += sr;
    }
  }
  imageStore(uCoarse, id, sum / weight);
}
)GLSL";

// Mip level k of the prefiltered cube (split sum, Karis 2013, with n = v = r): the mean of L over GGX
// directions of α = uAlpha, weighted by cos θl, L_pre(r) = Σ L(l_k) (n·l_k) / Σ (n·l_k), l = reflect(−r, h),
// h ~ D(h) cos θh. Each sample reads the source cube at the mip level whose texel's solid angle matches the
// sample's (filtered importance sampling, Křivánek & Colbert 2008): lod = ½ log2(Ω_sample / Ω_texel), without
// the customary + 1, whose wider blur moves a bright region's light towards the horizon (measured: 5 % low
// against 3 % on a 100 : 1 cap of 15°; tests/raster/environment_light_test.cpp).
inline constexpr const char* kEnvironmentPrefilter = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform samplerCube uSource;  // level 0 and its box-filtered mip chain
layout(binding = 0, rgba32f) uniform writeonly imageCube uOut;
uniform int uSize;          // this level's face size
uniform int uSourceSize;    // the source's level-0 face size
uniform float uAlpha;       // GGX α of this level
uniform int uSamples;
void main() {
  ivec3 id = ivec3(gl_GlobalInvocationID);
  if (id.x >= uSize || id.y >= uSize) return;
  vec3 r = flyCubeDirection(id.z, flyCubeTexelCentre(id.xy, uSize));
  float a2 = max(uAlpha * uAlpha, 1e-8);
  mat3 frame = flyFrameAround(r);
  float texelSr = 4.0 * kPi / (6.0 * float(uSourceSize * uSourceSize));
  vec4 sum = vec4(0.0);  // alpha too: a cube reflector's fog weight (raster/cube_reflections.h)
  float weight = 0.0;
  for (int k = 0; k < uSamples; ++k) {
    vec3 h = flyGgxSampleNormal(flyHammersley(uint(k), uint(uSamples)), a2);
    vec3 l = vec3(2.0 * h.z * h.xy, 2.0 * h.z * h.z - 1.0);  // reflect(−v, h) with v = +z
    if (l.z <= 0.0) continue;
    float pdf = flyGgxD(h.z, a2) / 4.0;  // D cos θh / (4 v·h), v·h = cos θh
    float lod = max(0.5 * log2(1.0 / (float(uSamples) * pdf * texelSr)), 0.0);
    sum += textureLod(uSource, frame * l, lod) * l.z;
    weight += l.z;
  }
  imageStore(uOut, id, sum / max(weight, 1e-20));
}
)GLSL";

// Diffuse irradiance E(n) = ∫ L(ω) max(0, n·ω) dω (lux) per texel of the irradiance cube, by quadrature over
// every texel of one level of the source cube with its exact solid angle (the difference of
// A(x, y) = atan2(x y, √(x² + y² + 1)) over its corners).
inline constexpr const char* kEnvironmentIrradiance = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform samplerCube uSource;
layout(binding = 0, rgba32f) uniform writeonly imageCube uOut;
uniform int uSize;        // the irradiance cube's face size
uniform int uQuadSize;    // the face size of the source level summed over
uniform float uQuadLod;   // that level
float flyCornerArea(float x, float y) { return atan(x * y, sqrt(x * x + y * y + 1.0)); }
void main() {
  ivec3 id = ivec3(gl_GlobalInvocationID);
  if (id.x >= uSize || id.y >= uSize) return;
  vec3 n = flyCubeDirection(id.z, flyCubeTexelCentre(id.xy, uSize));
  vec3 e = vec3(0.0);
  float step = 2.0 / float(uQuadSize);
  for (int face = 0; face < 6; ++face) {
    for (int y = 0; y < uQuadSize; ++y) {
      float t0 = -1.0 + float(y) * step, t1 = t0 + step;
      for (int x = 0; x < uQuadSize; ++x) {
        float s0 = -1.0 + float(x) * step, s1 = s0 + step;
        vec3 w = flyCubeDirection(face, vec2(s0 + s1, t0 + t1) * 0.5);
        float c = dot(n, w);
        if (c <= 0.0) continue;
        float sr = flyCornerArea(s0, t0) - flyCornerArea(s0, t1) - flyCornerArea(s1, t0) + flyCornerArea(s1, t1);
        e += textureLod(uSource, w, uQuadLod).rgb * c * sr;
      }
    }
  }
  imageStore(uOut, id, vec4(e, 1.0));
}
)GLSL";

// The split sum's second factor (Karis 2013) for fly's GGX — Smith's height-correlated masking-shadowing
// G2 = 1/(1 + Λ(ωo) + Λ(ωi)), as the baker's glossy lobe (raytracer/bsdf.cpp) — and Schlick's Fresnel:
// ∫ f cos θi dωi = F0 · A + B with A = ∫ (1 − Fc) f₁ cos, B = ∫ Fc f₁ cos, f₁ the lobe with F = 1 and
// Fc = (1 − ωo·h)⁵. Texel (i, j) of an N × N table: cos θo = (i + ½)/N, √α = (j + ½)/N. By importance
// sampling h ~ D(h) cos θh over a Hammersley set: f₁ cos θi / pdf = G2 (ωo·h) / (cos θo cos θh).
inline constexpr const char* kEnvironmentSplitSum = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32f) uniform writeonly image2D uOut;
uniform int uSize;
uniform int uSamples;
void main() {
  ivec2 id = ivec2(gl_GlobalInvocationID.xy);
  if (id.x >= uSize || id.y >= uSize) return;
  float cosO = (float(id.x) + 0.5) / float(uSize);
  float rough = (float(id.y) + 0.5) / float(uSize);
  float a2 = rough * rough * rough * rough;
  vec3 wo = vec3(sqrt(max(0.0, 1.0 - cosO * cosO)), 0.0, cosO);
  float lambdaO = flyGgxLambda(cosO, a2);
  vec2 ab = vec2(0.0);
  for (int k = 0; k < uSamples; ++k) {
    vec3 h = flyGgxSampleNormal(flyHammersley(uint(k), uint(uSamples)), a2);
    float oh = dot(wo, h);
    if (oh <= 0.0) continue;
    vec3 wi = 2.0 * oh * h - wo;
    if (wi.z <= 0.0) continue;
    float g2 = 1.0 / (1.0 + lambdaO + flyGgxLambda(wi.z, a2));
    float value = g2 * oh / (cosO * h.z);
    float x = 1.0 - oh;
    float fc = x * x * x * x * x;
    ab += vec2((1.0 - fc) * value, fc * value);
  }
  imageStore(uOut, id, vec4(ab / float(uSamples), 0.0, 0.0));
}
)GLSL";

}  // namespace fly::raster::shaders
