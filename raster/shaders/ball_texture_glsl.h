// GLSL 4.50 sources of the ball textures (raster/ball_texture.h; FLY §4): the measured BRDFs of
// rdb::RasterMeasuredBrdf evaluated per texel — the MERL table by the same trilinear interpolation as
// sdb::MeasuredBrdf::evalPerSr, the car-paint model by the same formulas as sdb::CarPaintBrdf::evalPerSr — and
// the compute pass that writes a ball. Units: illuminance in lux, radiance in cd/m², BRDF in 1/sr.
#pragma once

namespace fly::raster::shaders {

// The BRDF evaluation, for kBallCompute and for the scene pass's lamps evaluated per pixel (shaders/
// scene_glsl.h, FLY_MEASURED). Its block and table come at binding FLY_BRDF_BINDING and texture unit
// FLY_BRDF_TABLE_UNIT; kPi comes from the source it is prepended to.
inline constexpr const char* kMeasuredBrdf = R"GLSL(
// rdb::RasterMeasuredBrdf as a std430 block (raster/ball_texture.cpp, GpuBallBrdf).
struct BallBrdf {
  vec4 kind;               // x 0 table, 1 car paint; y the table's first θh slice in uBrdfTables; z coat η; w coat α
  vec4 base;               // rgb the pigment's albedo, w the coat's internal diffuse reflectance F̄int
  vec4 lobes[3];           // rgb the flakes' F0 (0: no lobe), w GGX α
  vec4 albedo[FLY_ALBEDO_STEPS];  // rgb ρ(θo) at cos θo = (k + 0.5) / FLY_ALBEDO_STEPS
};
layout(std430, binding = FLY_BRDF_BINDING) readonly buffer BallBrdfs { BallBrdf brdfs[]; };
// The MERL tables one after the other along z: texel (φd, θd, first slice + θh), rgb 1/sr, a 1 where measured.
layout(binding = FLY_BRDF_TABLE_UNIT) uniform sampler3D uBrdfTables;

// sdb::MeasuredBrdf::evalPerSr: trilinear in (√(θh/(π/2)), θd, φd) over the corners that were measured.
vec3 flyTableBrdf(int firstSlice, vec3 wi, vec3 wo) {
  if (!(wi.z > 0.0) || !(wo.z > 0.0)) return vec3(0.0);
  vec3 h = normalize(wi + wo);
  float sinH = length(h.xy);
  float thetaH = atan(sinH, h.z);
  // Rusinkiewicz's rotation taking h to the normal, as a frame: ωi's coordinates in it are the difference
  // vector (sdb::halfDiffAngles).
  vec3 hx = vec3(1.0, 0.0, 0.0), hy = vec3(0.0, 1.0, 0.0);
  if (sinH > 1e-9) {
    vec2 cs = h.xy / sinH;
    hx = vec3(h.z * cs.x, h.z * cs.y, -sinH);
    hy = vec3(-cs.y, cs.x, 0.0);
  }
  vec3 diff = vec3(dot(wi, hx), dot(wi, hy), dot(wi, h));
  float sinD = length(diff.xy);
  float thetaD = atan(sinD, diff.z);
  float phiD = sinD > 1e-12 ? mod(atan(diff.y, diff.x), kPi) : 0.0;
  float x = clamp(sqrt(max(0.0, thetaH / (0.5 * kPi))) * 90.0, 0.0, 89.0);
  float y = clamp(thetaD / (0.5 * kPi) * 90.0, 0.0, 89.0);
  float z = clamp(phiD / kPi * 180.0, 0.0, 180.0);
  int h0 = min(int(x), 88), d0 = min(int(y), 88), p0 = min(int(z), 179);
  int p1 = (p0 + 1) % 180;
  vec3 f = vec3(x - float(h0), y - float(d0), z - float(p0));
  vec3 sum = vec3(0.0);
  float weightSum = 0.0;
  for (int c = 0; c < 8; ++c) {
    int hi = h0 + (c & 1), di = d0 + ((c >> 1) & 1), pi = (c & 4) != 0 ? p1 : p0;
    float w = ((c & 1) != 0 ? f.x : 1.0 - f.x) * ((c & 2) != 0 ? f.y : 1.0 - f.y) * ((c & 4) != 0 ? f.z : 1.0 - f.z);
    vec4 s = texelFetch(uBrdfTables, ivec3(pi, di, firstSlice + hi), 0);
    if (w > 0.0 && s.a > 0.5) {
      sum += w * s.rgb;
      weightSum += w;
    }
  }
  return weightSum > 0.0 ? sum / weightSum : texelFetch(uBrdfTables, ivec3(p0, d0, firstSlice + h0), 0).rgb;
}

// Walter et al. 2007, eq. 33 (GGX D) and eq. 34 (Smith G1), as sdb/car_paint_brdf.cpp.
float flyGgxD(float cosThetaH, float alpha) {
  float a2 = alpha * alpha;
  float d = cosThetaH * cosThetaH * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}
float flySmithG1(float cosTheta, float alpha) {
  float c2 = cosTheta * cosTheta;
  float tan2 = max(0.0, 1.0 - c2) / max(c2, 1e-12);
  return 2.0 / (1.0 + sqrt(1.0 + alpha * alpha * tan2));
}
float flyGgxLobe(vec3 wi, vec3 wo, float alpha, out float cosThetaD) {
  vec3 h = normalize(wi + wo);
  cosThetaD = clamp(dot(wi, h), 0.0, 1.0);
  return flyGgxD(h.z, alpha) * flySmithG1(wi.z, alpha) * flySmithG1(wo.z, alpha) / (4.0 * wi.z * wo.z);
}
float flyDielectricFresnel(float cosTheta, float eta) {
  float c = clamp(cosTheta, 0.0, 1.0);
  float sin2t = (1.0 - c * c) / (eta * eta);
  if (sin2t >= 1.0) return 1.0;
  float ct = sqrt(1.0 - sin2t);
  float rs = (c - eta * ct) / (c + eta * ct);
  float rp = (eta * c - ct) / (eta * c + ct);
  return 0.5 * (rs * rs + rp * rp);
}
vec3 flyRefractedInside(vec3 w, float eta) {
  vec2 t = w.xy / eta;
  return vec3(t, sqrt(max(0.0, 1.0 - dot(t, t))));
}

// sdb::CarPaintBrdf::evalPerSr: the coat's GGX reflection plus the base (diffuse and flake lobes) through it.
// Reads the block's members where it needs them (a copy of the whole block, albedo table and all, per
// evaluation would be wasted work).
vec3 flyCarPaintBrdf(int index, vec3 wi, vec3 wo) {
  if (!(wi.z > 0.0) || !(wo.z > 0.0)) return vec3(0.0);
  vec4 coat = brdfs[index].kind;
  float eta = coat.z;
  vec3 f = vec3(0.0);
  float through = 1.0;
  vec3 wiBase = wi, woBase = wo;
  if (eta > 1.0) {
    float cosThetaD;
    float lobe = flyGgxLobe(wi, wo, coat.w, cosThetaD);
    f += vec3(flyDielectricFresnel(cosThetaD, eta) * lobe);
    through = (1.0 - flyDielectricFresnel(wi.z, eta)) * (1.0 - flyDielectricFresnel(wo.z, eta)) / (eta * eta);
    wiBase = flyRefractedInside(wi, eta);
    woBase = flyRefractedInside(wo, eta);
  }
  vec4 pigment = brdfs[index].base;
  vec3 base = pigment.rgb / (kPi * (vec3(1.0) - pigment.rgb * pigment.w));
  for (int k = 0; k < 3; ++k) {
    vec4 flakes = brdfs[index].lobes[k];
    vec3 f0 = flakes.rgb;
    if (f0 == vec3(0.0)) continue;
    float cosThetaD;
    float lobe = flyGgxLobe(wiBase, woBase, flakes.w, cosThetaD);
    float x = 1.0 - cosThetaD;
    float x2 = x * x;
    base += (f0 + (vec3(1.0) - f0) * (x2 * x2 * x)) * lobe;
  }
  return f + through * base;
}

// The BRDF (1/sr) of brdfs[index] for unit directions in the surface's frame (z = normal).
vec3 flyMeasuredBrdf(int index, vec3 wi, vec3 wo) {
  vec4 kind = brdfs[index].kind;
  return kind.x < 0.5 ? flyTableBrdf(int(kind.y), wi, wo) : flyCarPaintBrdf(index, wi, wo);
}

// ρ(θo), linear between the table's samples.
vec3 flyAlbedo(int index, float cosThetaOut) {
  float x = clamp(cosThetaOut * float(FLY_ALBEDO_STEPS) - 0.5, 0.0, float(FLY_ALBEDO_STEPS - 1));
  int k = min(int(x), FLY_ALBEDO_STEPS - 2);
  return mix(brdfs[index].albedo[k].rgb, brdfs[index].albedo[k + 1].rgb, x - float(k));
}
)GLSL";

// One ball: texel (i, j) of an N × N image is the point (x, y) = ((i + ½)/N · 2 − 1, (j + ½)/N · 2 − 1) of a
// unit ball seen along −Z of the view frame (orthographic), its normal n = (x, y, √(1 − x² − y²)) and the
// direction to the eye ωo = +Z. Texels outside the disc take the normal at radius 1 − 1/N (what bilinear
// filtering near the rim reads). Two passes of this source:
//   FLY_BALL_ENV  the environment term into an image of its own (M × M, M ≤ N; layer = the BRDF's index):
//                 ∫ f(ωi, ωo) cos θi L(ωi) dωi ≈ ρ(θo) · Σ w f L / Σ w f over a midpoint grid of the half
//                 vector (θh = u² · π/2, φh), ωi = 2(ωo·h)h − ωo, w = cos θi · 4 (ωo·h) · sin θh · u: the
//                 BRDF-weighted mean of L times the exact albedo, so a coarse grid errs only where L varies
//                 within the lobe; a = its irradiance's luminance, for the two hemispheres exactly from their
//                 view factors, for the sky π · Σ w' L / Σ w' (w' without f)
//   otherwise     the ball: layer z = 0 the lights, Σ f(ωi, ωo) cos θi E_i (each light a distant one: ωi
//                 towards it, E_i its illuminance in lux), plus the environment image (bilinear at the texel's
//                 (x, y)); layer z = 1 the sun alone. a = the luminance of the irradiance (lux) of the layer's
//                 light on the texel's normal.
inline constexpr const char* kBallCompute = R"GLSL(
#ifdef FLY_BALL_ENV
// A work group: 4 texels (y), each summed by 16 invocations (x) over every 16th half vector, then reduced.
layout(local_size_x = 16, local_size_y = 4) in;
#else
layout(local_size_x = 8, local_size_y = 8) in;
#endif
layout(binding = 0, rgba32f) uniform writeonly image2DArray uOut;
uniform int uBrdf;        // index into brdfs
uniform int uSize;        // the output image's N (or M)
uniform int uFirstLayer;  // where the output goes in uOut

float flyLuminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The normal and surface frame of texel `texel` of an size × size ball.
mat3 flyBallFrame(ivec2 texel, int size) {
  vec2 xy = (vec2(texel) + 0.5) / float(size) * 2.0 - 1.0;
  float rimRadius = 1.0 - 1.0 / float(size);
  float r2 = dot(xy, xy);
  if (r2 > rimRadius * rimRadius) {
    xy *= rimRadius * inversesqrt(r2);
    r2 = rimRadius * rimRadius;
  }
  vec3 n = vec3(xy, sqrt(max(0.0, 1.0 - r2)));
  // Any tangent: the BRDFs are isotropic.
  vec3 t = normalize(cross(abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), n));
  return mat3(t, cross(n, t), n);
}

#ifdef FLY_BALL_ENV
layout(binding = 1) uniform sampler2D uSky;  // rdb::RasterSky's equirectangular image, world directions
uniform int uEnvironment;    // 1 two hemispheres (uUpCdM2 above, uDownCdM2 below), 2 the sky image
uniform vec3 uUpView;        // world +Y in the view frame
uniform vec3 uUpCdM2;
uniform vec3 uDownCdM2;
uniform mat3 uWorldFromView;
uniform int uEnvSteps;       // grid steps per axis

vec3 flyEnvironment(vec3 dView) {
  if (uEnvironment == 1) return dot(dView, uUpView) > 0.0 ? uUpCdM2 : uDownCdM2;
  vec3 d = uWorldFromView * dView;
  float phi = atan(d.z, d.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  float theta = acos(clamp(d.y, -1.0, 1.0));
  return textureLod(uSky, vec2(phi / (2.0 * kPi), theta / kPi), 0.0).rgb;
}

// The 16 partial sums of each of the group's 4 texels: Σ w f L, Σ w f (rgb), Σ w L, Σ w (a).
shared vec3 sSumFL[4][16];
shared vec3 sSumF[4][16];
shared vec2 sSumLW[4][16];

// One texel per (work group x, work group y · 4 + local y): the texel count along a side is small (64² by
// default), so each texel's 16² grid cells are spread over 16 invocations, which keeps the GPU's processors
// busy where one invocation per texel would leave most of them idle.
void main() {
  ivec2 texel = ivec2(gl_WorkGroupID.x, gl_WorkGroupID.y * 4u + gl_LocalInvocationID.y);
  uint slot = gl_LocalInvocationID.y, part = gl_LocalInvocationID.x;
  bool inside = texel.x < uSize && texel.y < uSize;
  mat3 viewFromLocal = flyBallFrame(min(texel, ivec2(uSize - 1)), uSize);
  vec3 n = viewFromLocal[2];
  vec3 wo = vec3(viewFromLocal[0].z, viewFromLocal[1].z, n.z);  // +Z in the surface frame
  vec3 sumFL = vec3(0.0), sumF = vec3(0.0);
  float sumL = 0.0, sumW = 0.0;
  for (int cell = int(part); inside && cell < uEnvSteps * uEnvSteps; cell += 16) {
    int a = cell / uEnvSteps, c = cell - a * uEnvSteps;
    float u = (float(a) + 0.5) / float(uEnvSteps);
    float thetaH = u * u * 0.5 * kPi;
    float sinH = sin(thetaH), cosH = cos(thetaH);
    float phi = 2.0 * kPi * (float(c) + 0.5) / float(uEnvSteps);
    vec3 h = vec3(sinH * cos(phi), sinH * sin(phi), cosH);
    float woDotH = dot(wo, h);
    if (woDotH <= 0.0) continue;
    vec3 wi = 2.0 * woDotH * h - wo;
    if (wi.z <= 0.0) continue;
    float w = wi.z * 4.0 * woDotH * sinH * u;
    vec3 radiance = flyEnvironment(viewFromLocal * wi);
    vec3 f = flyMeasuredBrdf(uBrdf, wi, wo);
    sumFL += w * f * radiance;
    sumF += w * f;
    sumL += w * flyLuminance(radiance);
    sumW += w;
  }
  sSumFL[slot][part] = sumFL;
  sSumF[slot][part] = sumF;
  sSumLW[slot][part] = vec2(sumL, sumW);
  barrier();
  if (part != 0u || !inside) return;
  for (uint k = 1u; k < 16u; ++k) {
    sumFL += sSumFL[slot][k];
    sumF += sSumF[slot][k];
    sumL += sSumLW[slot][k].x;
    sumW += sSumLW[slot][k].y;
  }
  vec3 albedo = flyAlbedo(uBrdf, wo.z);
  vec3 l = vec3(sumF.r > 0.0 ? albedo.r * sumFL.r / sumF.r : 0.0, sumF.g > 0.0 ? albedo.g * sumFL.g / sumF.g : 0.0,
                sumF.b > 0.0 ? albedo.b * sumFL.b / sumF.b : 0.0);
  float eLux = 0.0;
  if (uEnvironment == 1) {
    // Two uniform hemispheres: the view factors (1 ± cos θ)/2 of a plane tilted θ from the up direction.
    float c = dot(n, uUpView);
    eLux = kPi * flyLuminance(uUpCdM2 * (0.5 + 0.5 * c) + uDownCdM2 * (0.5 - 0.5 * c));
  } else if (sumW > 0.0) {
    eLux = kPi * sumL / sumW;
  }
  imageStore(uOut, ivec3(texel, uFirstLayer), vec4(l, eLux));
}
#else
struct BallLight {
  vec4 toLightView;  // xyz unit, towards the light, view frame
  vec4 lux;          // rgb illuminance on a surface facing it
};
layout(std430, binding = 1) readonly buffer BallLights { BallLight ballLights[]; };
layout(binding = 2) uniform sampler2DArray uEnvironmentImage;  // the FLY_BALL_ENV pass's output
uniform int uHasEnvironment;
uniform int uFirstLight;
uniform int uLightCount;
uniform vec3 uSunView;  // unit, towards the sun, view frame
uniform vec3 uSunLux;   // 0: no sun

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (texel.x >= uSize || texel.y >= uSize) return;
  int layer = int(gl_GlobalInvocationID.z);
  mat3 viewFromLocal = flyBallFrame(texel, uSize);
  mat3 localFromView = transpose(viewFromLocal);
  vec3 wo = localFromView * vec3(0.0, 0.0, 1.0);
  vec3 l = vec3(0.0);
  float eLux = 0.0;
  if (layer == 1) {
    vec3 wi = localFromView * uSunView;
    l = flyMeasuredBrdf(uBrdf, wi, wo) * max(wi.z, 0.0) * uSunLux;
    eLux = flyLuminance(uSunLux) * max(wi.z, 0.0);
  } else {
    for (int k = uFirstLight; k < uFirstLight + uLightCount; ++k) {
      vec3 wi = localFromView * ballLights[k].toLightView.xyz;
      l += flyMeasuredBrdf(uBrdf, wi, wo) * max(wi.z, 0.0) * ballLights[k].lux.rgb;
      eLux += flyLuminance(ballLights[k].lux.rgb) * max(wi.z, 0.0);
    }
    if (uHasEnvironment != 0) {
      vec4 env = textureLod(uEnvironmentImage, vec3((vec2(texel) + 0.5) / float(uSize), float(uBrdf)), 0.0);
      l += env.rgb;
      eLux += env.a;
    }
  }
  imageStore(uOut, ivec3(texel, uFirstLayer + layer), vec4(l, eLux));
}
#endif
)GLSL";

}  // namespace fly::raster::shaders
