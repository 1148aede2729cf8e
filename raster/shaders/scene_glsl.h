// GLSL 4.50 sources of the engine's passes, as C++ raw strings. The renderer prepends "#version 450 core" and
// the variant's #defines (raster/renderer.cpp, Renderer::sceneProgram):
//   FLY_LIGHT_MAP  vertex light maps: L = albedo · E / π (+ emission), for meshes that have one
//   FLY_PHONG      the modified Phong (lights, the sun, the directional ambient term), for the others
//   FLY_SUN        the sun as a directional light (simple and sunlight modes)
//   FLY_TWO_SIDED  two-sided meshes: the vertex shader picks the front or back value by facing
//   FLY_GONIO      goniometric lights' tables
//   FLY_LIGHT_TEXTURE  light textures (with FLY_LIGHT_MAP): L = albedo · E_texel / π per fragment, bilinear, for
//                  meshes that have one
//   FLY_GLASS      glass: drawn in a second pass over a copy of the first, adding T(θ) times what lies
//                  behind it (rdb/raster_rdb.h, RasterMaterial::transmission)
//   FLY_FROSTED    frosted glass (with FLY_GLASS): T(θ) of its GGX transmission lobe by the split sum's table,
//                  times what lies behind it blurred by the lobe's width at its distance behind the pane (a mip
//                  level of the copy, chosen by the copy's depth)
//   FLY_SUN_DIRECT sunlight mode over light maps that keep the sun's direct part apart (with FLY_LIGHT_MAP):
//                  L = albedo · (E − E_sunDirect) / π + the sun's direct term (flySunTerm) for the current sun
//                  (FLY §3: baked indirect light, real-time sun)
//   FLY_IBL        sunlight mode's image-based light (raster/environment_light.h): the sky's irradiance in place
//                  of the directional ambient term, and its prefiltered radiance by the split sum for the
//                  specular part of every material, per fragment (flyEnvironmentSpecular), on light-mapped
//                  surfaces times the share of the environment's light their light map shows
//                  (flySpecularOcclusion)
//   FLY_CUBE_REFLECTION  curved reflectors (per fragment): a draw with uCubeReflector ≥ 0 adds the split sum of
//                  its own cube map (raster/cube_reflections.h) in every mode
//   FLY_REFLECTION_FOG  materials with reflection fog (per fragment): what a draw's material reflects (its planar
//                  image, cube map or image-based light) fades to uFogColor · E / π with the reflected distance
//   FLY_SUN_GLASS  scenes with clear glass and a sun (with FLY_SUN): the sun's direct term times the T of the
//                  glass between the surface and the sun, per fragment (raster/sun_glass.h; kSunGlassLookup,
//                  prepended to every stage). Per-vertex meshes pass the sun's term apart from the rest
//                  (vSunLuminance) for their fragment stage to multiply
// The surfaces that rdb::RasterRdb::shadedPerFragment names (textures, COLOR_0, alpha coverage) are drawn by
// kSurfaceVertex + kSurfaceFragment, which shade per fragment with the same terms, and these #defines too:
//   FLY_TEXTURES      base colour, emission and normal textures (RasterMaterial's texture slots)
//   FLY_NORMAL_MAP    normal maps (per-vertex tangents) for the Phong and sun terms
//   FLY_ANISOTROPY    anisotropic reflection lobes (per-vertex tangents; rdb::RasterMaterial::anisotropic) for
//                     the lamps', the sun's and the environment's specular terms
//   FLY_GLOSSINESS_TEXTURE  (with FLY_TEXTURES) glossiness textures: the GGX width per pixel
//                     (rdb::RasterMaterial::glossinessTexture) for the lamps', the sun's and the environment's
//                     specular terms
//   FLY_METALNESS_TEXTURE  (with FLY_TEXTURES) metalness textures: the mix with a metal of the base colour per
//                     pixel (rdb::RasterMaterial::metalnessTexture)
//   FLY_UV1           a second UV set
//   FLY_VERTEX_COLOR  COLOR_0 multiplies the base colour and the coverage
//   FLY_ALPHA_MASK    a cut-out: fragments with coverage below the material's cut-off are discarded
//   FLY_BLEND_PASS    a blended surface: writes (coverage · L, coverage) into the blend target, composited
//                     over the image by kBlendComposite
//   FLY_SSAO          simple mode's ambient occlusion: phong's ambient term times the pixel's AO
//                     (raster/ambient_occlusion.h; shaders/ambient_occlusion_glsl.h, prepended to every stage)
//   FLY_MEASURED      measured BRDFs (rdb::RasterMeasuredBrdf): a material with one shows its ball texture
//                     (raster/ball_texture.h) by reflection mapping (kMeasuredLookup)
//   FLY_DIFFUSE_BY_ANGLE  (with FLY_LIGHT_MAP) the light map's diffuse albedo times the diffuse share towards
//                     the eye (flyDiffuseTowards), for scenes where some material's share depends on the angle
//                     (rdb::RasterVariants::diffuseByAngle); without it the share is 1 and no position or
//                     normal is interpolated. The per-vertex program (kSceneVertex) takes it with light
//                     textures, which then take the share per fragment too
// Units: positions in metres, world frame (+Y up); E in lux; L in cd/m².
#pragma once

namespace fly::raster::shaders {

// Clear glass's transmittance T(θ) (base/clear_pane.h, ClearPane::at, in the same steps), prepended before
// kSceneCommon (whose flyGlassTransmittance calls it for clear glass) and to the sun's glass map
// (raster/sun_glass.h): t, r the transmission and reflection colours, f0 Schlick's F0 of the ior (< 0:
// uniform reflection, T = t (1 − r)), cosTheta the cosine of the angle to the pane's normal, either face.
// A slab of two Fresnel faces with absorption τ0 and internal reflections, T_pol = (1 − R)² τ / (1 − R² τ²),
// τ = τ0^(1 / cos θt) (the Fresnel equations; Tregenza and Sharples, "Daylighting algorithms", algorithm
// 2.34), scaled to the energy rule's T(0) = t (1 − r F0) and never above its t (1 − r F(θ)).
inline constexpr const char* kGlassPane = R"GLSL(
// One polarisation's slab transmittance, tr = 1 − R of one face, tau the internal transmittance.
vec3 flySlabPolarised(float tr, vec3 tau) {
  vec3 den = ((vec3(1.0) - tau) + tr * tau) * (vec3(1.0) + (1.0 - tr) * tau);
  return tr * tr * tau / max(den, vec3(1e-30));
}
// (T_s + T_p) / 2 at cos θ = c for index n and τ0 per channel.
vec3 flySlab(float c, float n, vec3 tau0) {
  float ct = sqrt(max(1.0 - (1.0 - c * c) / (n * n), 0.0));
  float k = 4.0 * n * c * ct;
  float s = c + n * ct;
  float p = n * c + ct;
  float trS = min(k / max(s * s, 1e-30), 1.0);
  float trP = min(k / max(p * p, 1e-30), 1.0);
  vec3 tau = pow(tau0, vec3(1.0 / max(ct, 1e-6)));
  return 0.5 * (flySlabPolarised(trS, tau) + flySlabPolarised(trP, tau));
}
vec3 flyPaneTransmittance(vec3 t, vec3 r, float f0, float cosTheta) {
  t = clamp(t, 0.0, 1.0);
  r = clamp(r, 0.0, 1.0);
  if (f0 < 0.0) return t * (vec3(1.0) - r);
  float r0 = min(f0, 0.99);
  float q = sqrt(r0);
  float n = (1.0 + q) / (1.0 - q);
  vec3 normalT = t * (vec3(1.0) - r * r0);
  // τ0 from S(0) = T_n: the positive root of T_n R0² τ0² + (1 − R0)² τ0 − T_n = 0, at most 1.
  float b = (1.0 - r0) * (1.0 - r0);
  vec3 tau0 = min(2.0 * normalT / (vec3(b) + sqrt(vec3(b * b) + 4.0 * normalT * normalT * r0 * r0)), vec3(1.0));
  vec3 s0 = flySlab(1.0, n, tau0);
  vec3 scale = mix(vec3(0.0), normalT / max(s0, vec3(1e-30)), greaterThan(s0, vec3(0.0)));
  float c = min(abs(cosTheta), 1.0);
  float x = 1.0 - c;
  float x2 = x * x;
  float schlick = r0 + (1.0 - r0) * x2 * x2 * x;
  return min(scale * flySlab(c, n, tau0), t * (vec3(1.0) - min(r * schlick, vec3(1.0))));
}
)GLSL";

// What the scene's vertex and fragment stages share (prepended to both): the material and light tables, the
// view and lighting uniforms, and the modified Phong.
inline constexpr const char* kSceneCommon = R"GLSL(
struct Material {
  vec4 diffuse;       // rgb albedo, w 1 where the base colour texel tints the reflection (specular, reflection, F90)
  vec4 specular;      // rgb reflectance at normal incidence (the reflect input of the energy rule)
  vec4 emission;      // rgb cd/m², w the GGX α of transmission (frosted glass; 0: clear)
  vec4 transmission;  // rgb clear transmission colour (0: not glass), w Schlick's F0 (< 0: uniform reflection)
  vec4 reflection;    // rgb reflection colour, w the metalness texture's factor
  vec4 coverage;      // x opacity, y alpha cut-off, z normal scale, w alpha mode (0 opaque, 1 mask, 2 blend)
  vec4 environment;   // rgb the split sum's F90 (0: no environment reflection), w GGX α
  vec4 anisotropy;    // x U, y V (each [0, 1]), z rotation about the normal (rad), w 1: an anisotropic lobe
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
uniform float uDisplayWhiteCdM2;  // the exposure's white (cd/m²), for emission given as a display colour
// A material's emission, cd/m²: a display colour (stored as −(c + 1), rdb::RasterMaterial::emissionDisplay)
// times the exposure's white.
vec3 flyEmission(Material m) {
  return m.emission.r < 0.0 ? (-m.emission.rgb - 1.0) * uDisplayWhiteCdM2 : m.emission.rgb;
}
uniform vec3 uSunDirWorld;   // unit, towards the sun
uniform vec3 uSunNormalLux;  // illuminance on a surface facing the sun; 0 where it is in shadow (raster/sun_shadows.h)

const float kPi = 3.14159265358979;
const float kCornerGain = FLY_CORNER_GAIN;

// The reflect input of the SDB's energy rule for light at cos θ from the normal (sdb::Material::reflectionAt):
// R(θ) = F0 + (F90 − F0)(1 − cos θ)⁵, with F0 = m.specular (the reflection colour r times Schlick's F0 of the
// ior, or r for uniform reflection) and F90 = m.environment.rgb (r; 0 where nothing is reflected).
vec3 flyReflectAt(Material m, float cosTheta) {
  float x = 1.0 - clamp(cosTheta, 0.0, 1.0);
  float x2 = x * x;
  return m.specular.rgb + (m.environment.rgb - m.specular.rgb) * (x2 * x2 * x);
}
// The diffuse albedo's factor for light leaving towards cos θo: the baker's coupled diffuse (raytracer/bsdf.h)
// is f = k_d (1 − R(θi)) (1 − R(θo)) / ((1 − R̄) π), so under light from all sides alike (an environment, the
// ambient term, a light map's irradiance) it reflects k_d (1 − R(θo)) = albedo · (1 − R(θo)) / (1 − R(0)):
// the energy rule's diffuse share at θo, which falls to k_d (1 − r) at grazing angles.
// Where R(0) = 1 the diffuse share is 0 at every angle, and the factor is 1 (it leaves the light-map modes'
// rough-reflector stand-in of a perfect uniform reflector as it is).
vec3 flyDiffuseTowards(Material m, float cosO) {
  vec3 atNormal = vec3(1.0) - m.specular.rgb;
  vec3 factor = (vec3(1.0) - flyReflectAt(m, cosO)) / max(atNormal, vec3(1e-6));
  return mix(vec3(1.0), factor, greaterThan(atNormal, vec3(1e-6)));
}
// The same lobe's factor for light arriving from cos θi (with flyDiffuseTowards for the other direction):
// (1 − R(θi)) / (1 − R̄), R̄ = F0 + (F90 − F0) / 21 the cosine-weighted mean of R over the hemisphere.
vec3 flyDiffuseFrom(Material m, float cosI) {
  vec3 meanR = m.specular.rgb + (m.environment.rgb - m.specular.rgb) / 21.0;
  return (vec3(1.0) - flyReflectAt(m, cosI)) / max(vec3(1.0) - meanR, vec3(1e-6));
}

#ifdef FLY_ANISOTROPY
// The GGX widths (α_t, α_b) of a lobe of isotropic width α and anisotropy u, v ∈ [0, 1]: base/ggx.h's
// ggxAnisotropicAlphas (Burley 2012, §5.4: aspect = √(1 − 0.9 |u − v|), the wider axis α / aspect, the
// narrower α · aspect, so α_t α_b = α²).
vec2 flyAnisotropicAlphas(float alpha, float u, float v) {
  float d = clamp(u - v, -1.0, 1.0);
  float aspect = sqrt(1.0 - 0.9 * abs(d));
  return d >= 0.0 ? vec2(alpha / aspect, alpha * aspect) : vec2(alpha * aspect, alpha / aspect);
}
// The pixel's anisotropic lobe, set by kSurfaceFragment before it shades: unit world axes perpendicular to
// the shading normal, gLobeT of width gLobeAlphas.x and gLobeB of gLobeAlphas.y; gLobeAlphas.x ≤ 0: the
// material's isotropic lobe (m.environment.w).
vec3 gLobeT = vec3(1.0, 0.0, 0.0);
vec3 gLobeB = vec3(0.0, 1.0, 0.0);
vec2 gLobeAlphas = vec2(0.0);
#endif

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

#ifdef FLY_LIGHT_MAP
// What multiplies E / π in the light-map modes: the albedo, plus an opaque material's uniform reflection
// (a metal's) as if it were a rough reflector — under the baked irradiance, the limit of a rough conductor
// (raster/renderer.h). Glass keeps its reflection for T(θ).
vec3 flyLightMapReflectance(vec3 albedo, Material m) {
#ifdef FLY_IBL
  return albedo;  // the image-based light draws the reflection (flyEnvironmentSpecular)
#else
  bool glass = max(m.transmission.r, max(m.transmission.g, m.transmission.b)) > 0.0;
  return glass ? albedo : albedo + m.reflection.rgb;
#endif
}
#endif

#if defined(FLY_PHONG) || defined(FLY_MEASURED)
// The illuminance (lux) light l gives a surface at p facing it, and the unit direction towards it:
// directional lights as given, the others I(direction) · window / d² with KHR_lights_punctual's range window
// and spot falloff, or the goniometric table; 0 at the light's own position.
vec3 flyLightLux(Light l, vec3 p, out vec3 toLight) {
  int type = int(l.positionType.w);
  if (type == 2) {
    toLight = -l.directionRange.xyz;
    return l.intensity.rgb;
  }
  vec3 d = l.positionType.xyz - p;
  float dist2 = dot(d, d);
  toLight = vec3(0.0, 0.0, 1.0);
  if (dist2 <= 1e-12) return vec3(0.0);
  toLight = d * inversesqrt(dist2);
  float window = 1.0;
  if (l.directionRange.w > 0.0) {
    float r = sqrt(dist2) / l.directionRange.w;
    window = max(0.0, 1.0 - r * r * r * r);  // KHR_lights_punctual: clamp(1 − (d/range)⁴, 0, 1) / d²
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
  return l.intensity.rgb * (cd * window / dist2);
}
#endif

#if defined(FLY_PHONG) || defined(FLY_SUN_DIRECT)
// Smith's Λ for GGX at cos θ > 0, a2 = α² (base/ggx.h, Heitz 2014 eq. 72).
float flyLambda(float cosTheta, float a2) {
  float c2 = cosTheta * cosTheta;
  return c2 >= 1.0 ? 0.0 : 0.5 * (sqrt(1.0 + a2 * (1.0 - c2) / max(c2, 1e-12)) - 1.0);
}
#ifdef FLY_ANISOTROPY
// Smith's Λ of the anisotropic GGX lobe (gLobeT, gLobeB; widths ab) towards unit w, at cos θ = dot(w, n) > 0:
// the isotropic Λ with α projected on w's azimuth, α² tan²θ = (α_t² (w·t)² + α_b² (w·b)²) / cos²θ (Heitz
// 2014, eq. 86 and §5.3).
float flyLambdaAnisotropic(vec3 w, vec3 n, vec2 ab) {
  float c = dot(w, n);
  float wt = dot(w, gLobeT) * ab.x;
  float wb = dot(w, gLobeB) * ab.y;
  return c * c >= 1.0 ? 0.0 : 0.5 * (sqrt(1.0 + (wt * wt + wb * wb) / max(c * c, 1e-12)) - 1.0);
}
#endif
// Direct illuminance on the surface (lux), weighted for material m's diffuse lobe (flyDiffuseFrom), and the
// luminance (cd/m²) its reflection lobe sends towards `toEye`: the baker's glossy lobe (raytracer/bsdf.h),
// f = R(ωo·h) D(h) G2 / (4 cos θo cos θi) with GGX D of α = m.environment.w, Smith's height-correlated G2 and
// the energy rule's R (flyReflectAt), times E cos θi. α is at least 10⁻³ (the baker's bound of a delta lobe,
// which reflects no punctual light: here a highlight too small to see).
void addLight(Material m, vec3 p, vec3 n, vec3 toEye, vec3 toLight, vec3 eLux, inout vec3 diffuseLux,
              inout vec3 specularCdM2) {
  float cosSurface = dot(n, toLight);
  if (cosSurface <= 0.0) return;
  diffuseLux += eLux * cosSurface * flyDiffuseFrom(m, cosSurface);
  float cosO = dot(n, toEye);
  if (cosO <= 0.0) return;
  vec3 h = normalize(toLight + toEye);
  float alpha = max(m.environment.w, 1e-3);
  float a2 = alpha * alpha;
  float nh = max(dot(n, h), 0.0);
  float den = nh * nh * (a2 - 1.0) + 1.0;
  float d = a2 / (kPi * den * den);
  float g2 = 1.0 / (1.0 + flyLambda(cosO, a2) + flyLambda(cosSurface, a2));
#ifdef FLY_ANISOTROPY
  if (gLobeAlphas.x > 0.0) {
    // The anisotropic GGX D (Heitz 2014, eq. 85; Walter et al. 2007 eq. 33 stretched), 1 / (π α_t α_b
    // ((h·t / α_t)² + (h·b / α_b)² + (h·n)²)²), and the height-correlated G2 of its Λ.
    vec2 ab = max(gLobeAlphas, vec2(1e-3));
    vec3 hs = vec3(dot(h, gLobeT) / ab.x, dot(h, gLobeB) / ab.y, nh);
    float s2 = dot(hs, hs);
    d = 1.0 / (kPi * ab.x * ab.y * s2 * s2);
    g2 = 1.0 / (1.0 + flyLambdaAnisotropic(toEye, n, ab) + flyLambdaAnisotropic(toLight, n, ab));
  }
#endif
  specularCdM2 += eLux * flyReflectAt(m, dot(toEye, h)) * (d * g2 / (4.0 * cosO));
}
#endif

#ifdef FLY_PLANAR_REFLECTION
// The draw's planar reflector (RasterRdb::planarReflectors), −1 for none or in a mirrored pass, and whether its
// reflection image holds the sun's disc (sunlight mode draws the sky): then the image is the sun's mirror
// reflection, and the Phong lobe's sun highlight is left out so that it is not counted twice.
uniform int uReflector;
uniform int uSunInReflection;
#endif
// 1, or 0 where the draw's reflection image shows the sun (uSunInReflection).
float flySunHighlight() {
#ifdef FLY_PLANAR_REFLECTION
  return uReflector >= 0 && uSunInReflection != 0 ? 0.0 : 1.0;
#else
  return 1.0;
#endif
}

#if defined(FLY_FROSTED) && !defined(FLY_IBL) && !defined(FLY_CUBE_REFLECTION)
layout(binding = 14) uniform sampler2D uSplitSum;  // (A, B)(cos θo, √α), as below
#endif

#if defined(FLY_IBL) || defined(FLY_CUBE_REFLECTION)
// Image-based light (raster/environment_light.h): the environment's irradiance cube (lux) for the diffuse
// part of surfaces without a light map, and its GGX-prefiltered radiance cube with the split sum's table for
// the specular part of every material (Karis 2013: L_pre(r, α) · (F0 A + F90 B)). The environment is the
// sky's (FLY_IBL), or on a cube reflector's draw its own cube map (FLY_CUBE_REFLECTION, uCubeReflector ≥ 0).
layout(binding = 12) uniform samplerCube uIrradiance;
layout(binding = 13) uniform samplerCube uRadiance;  // level k: α_k = (k / (K − 1))²
layout(binding = 14) uniform sampler2D uSplitSum;    // (A, B)(cos θo, √α), texel centres at (i + ½) / N
uniform float uRadianceTopLevel;                     // K − 1
// 1: the irradiance replaces the Phong's directional ambient term (sunlight mode); 0: it does not (light-map
// mode, whose surfaces without a light map are shaded as in simple mode, and whose IBL is the room probe's).
uniform int uIrradianceAmbient;
vec3 flyIrradianceLux(vec3 n) { return textureLod(uIrradiance, n, 0.0).rgb; }
#ifdef FLY_CUBE_REFLECTION
uniform int uCubeReflector;  // the draw's RasterRdb::cubeReflectors index, −1 for none
#endif
#ifdef FLY_ROOM_PROBE
// The room probe (raster/room_probe.h) in place of the sky's radiance: its centre and box (world, m), and the
// point being shaded, which main() sets.
uniform vec3 uProbeCentreM;
uniform vec3 uProbeBoxMinM;
uniform vec3 uProbeBoxMaxM;
vec3 gProbePositionM = vec3(0.0);
// The probe's lookup direction for the mirror direction r at gProbePositionM: from its centre to where the
// ray p + t r leaves the box (parallax correction); r itself for a point outside the box, and on a cube
// reflector's draw, which reads its own maps.
vec3 flyProbeDirection(vec3 r) {
#ifdef FLY_CUBE_REFLECTION
  if (uCubeReflector >= 0) return r;
#endif
  vec3 p = gProbePositionM;
  if (any(lessThan(p, uProbeBoxMinM)) || any(greaterThan(p, uProbeBoxMaxM))) return r;
  vec3 side = mix(uProbeBoxMinM, uProbeBoxMaxM, step(vec3(0.0), r));
  vec3 t = abs(side - p) / max(abs(r), vec3(1e-6));
  vec3 d = p + min(t.x, min(t.y, t.z)) * r - uProbeCentreM;
  return dot(d, d) > 1e-12 ? d : r;
}
#else
vec3 flyProbeDirection(vec3 r) { return r; }
#endif
// The split sum's factor F0 A + F90 B of material m's GGX lobe towards the eye, and in `prefiltered` the
// prefiltered environment in the mirror direction (rgb: cd/m²; a: a cube reflector's fog weight, below).
vec3 flyEnvironmentLobe(Material m, vec3 n, vec3 toEye, out vec4 prefiltered) {
  float cosO = clamp(dot(n, toEye), 1e-4, 1.0);
  vec3 r = 2.0 * dot(n, toEye) * n - toEye;
  float alpha = clamp(m.environment.w, 0.0, 1.0);
  prefiltered = vec4(0.0);
  bool anisotropic = false;
#ifdef FLY_ANISOTROPY
  anisotropic = gLobeAlphas.x > 0.0;
  if (anisotropic) {
    // The anisotropic lobe as the isotropic lobe of its narrow width α_min spread along its wide axis w: the
    // GGX slope along an axis is Student's t with 2 degrees of freedom of scale α, and such spreads add
    // about as their scales do (as Cauchy spreads, exactly), so four half vectors n + s_k (α_max − α_min) w
    // at that distribution's quantiles 1/8, 3/8, 5/8, 7/8 (s_k = ±0.365, ±1.604; Q(p) = (2p − 1) /
    // √(2p(1 − p))), each reflecting the eye into a read of the level of α_min, averaged.
    float aMin = min(gLobeAlphas.x, gLobeAlphas.y);
    float spread = abs(gLobeAlphas.x - gLobeAlphas.y);
    vec3 wide = gLobeAlphas.x >= gLobeAlphas.y ? gLobeT : gLobeB;
    float level = sqrt(clamp(aMin, 0.0, 1.0)) * uRadianceTopLevel;
    for (int k = 0; k < 4; ++k) {
      float s = (k < 2 ? 0.365 : 1.604) * ((k & 1) == 0 ? 1.0 : -1.0) * spread;
      vec3 h = normalize(n + s * wide);
      prefiltered += textureLod(uRadiance, flyProbeDirection(2.0 * dot(h, toEye) * h - toEye), level);
    }
    prefiltered *= 0.25;
    // The table (the lobe's albedo) takes an effective isotropic α: the lobe's α = √(α_t α_b)
    // (flyAnisotropicAlphas) towards the α projected on the view's azimuth, α_o² = α_t² cos²φo + α_b² sin²φo
    // (what masks the eye's side of the lobe, Heitz 2014 §5.3), as the eye nears grazing:
    // α_eff = α (α_o / α)^(sin²θo). docs/materials-engine.md measures both against the anisotropic lobe.
    float sin2 = max(1.0 - cosO * cosO, 0.0);
    if (sin2 > 1e-8) {
      float ot = dot(toEye, gLobeT) * gLobeAlphas.x, ob = dot(toEye, gLobeB) * gLobeAlphas.y;
      float alphaO = sqrt((ot * ot + ob * ob) / sin2);
      alpha = clamp(alpha * pow(alphaO / max(alpha, 1e-6), sin2), 0.0, 1.0);
    }
  }
#endif
  // √α indexes both the table and the levels (√α_k = k / (K − 1)).
  float rough = sqrt(alpha);
  if (!anisotropic) prefiltered = textureLod(uRadiance, flyProbeDirection(r), rough * uRadianceTopLevel);
  vec2 ab = textureLod(uSplitSum, vec2(cosO, rough), 0.0).rg;
  return m.specular.rgb * ab.x + m.environment.rgb * ab.y;
}
// The environment's light reflected towards the eye by material m's GGX lobe (cd/m²).
vec3 flyEnvironmentSpecular(Material m, vec3 n, vec3 toEye) {
  if (m.environment.r + m.environment.g + m.environment.b <= 0.0) return vec3(0.0);
  vec4 prefiltered;
  vec3 lobe = flyEnvironmentLobe(m, n, toEye, prefiltered);
  return prefiltered.rgb * lobe;
}
#ifdef FLY_REFLECTION_FOG
// The same with reflection fog of luminance fogCdM2 (cd/m²): the sky lies at infinity (t = 1) and shows the
// fog alone; a cube reflector's maps hold L in rgb and t in a per texel (raster/cube_reflections.h), both
// prefiltered by the lobe, and the lobe sees mix(L̄, fogCdM2, t̄): exact for a mirror (level 0) and where L or
// t is uniform over the lobe, an approximation of the mean of mix(L, fog, t) elsewhere.
// The specular occlusion of a light-mapped surface (flySpecularOcclusion) dims what the environment shows,
// not the fog, whose E is the surface's own.
vec3 flyEnvironmentSpecularFogged(Material m, vec3 n, vec3 toEye, vec3 fogCdM2, bool cube, float occlusion) {
  if (m.environment.r + m.environment.g + m.environment.b <= 0.0) return vec3(0.0);
  vec4 prefiltered;
  vec3 lobe = flyEnvironmentLobe(m, n, toEye, prefiltered);
  return (cube ? mix(occlusion * prefiltered.rgb, fogCdM2, prefiltered.a) : fogCdM2) * lobe;
}
#endif
#endif

#ifdef FLY_GLASS
// The transmittance towards the eye of glass of transmission colour t seen at cos θ (either face): clear,
// the pane's T(θ) (kGlassPane, sdb::Material::clearTransmittanceAt); frosted
// (GGX α = m.emission.w > 0), the baker's thin-surface lobe (raytracer/bsdf.h), f = t (1 − R(ωo·h)) D G2 /
// (4 cos θo cos θi) about the straight-through direction, which passes ∫ f cos θi dωi = t ((A + B) −
// (F0 A + F90 B)) towards θo: the split sum's table at α (R's F0 and F90 as flyReflectAt's).
vec3 flyGlassTransmittance(Material m, vec3 t, float cosTheta) {
  float c = clamp(cosTheta, 0.0, 1.0);
#ifdef FLY_FROSTED
  if (m.emission.w > 0.0) {
    vec2 ab = textureLod(uSplitSum, vec2(c, sqrt(m.emission.w)), 0.0).rg;
    return t * max(vec3(ab.x + ab.y) - (m.specular.rgb * ab.x + m.environment.rgb * ab.y), vec3(0.0));
  }
#endif
  return flyPaneTransmittance(t, m.reflection.rgb, m.transmission.w, c);
}
#endif

#if defined(FLY_IBL) && defined(FLY_LIGHT_MAP)
// Specular occlusion of a light-mapped surface (docs/environment-light.md): the share of the environment's
// light that reaches it, Y(E_baked) / Y(E_env(n)) clamped to [0, 1] — E_baked the light map's irradiance
// without the sun's direct part (lux: the sky it sees and the interreflections), E_env(n) the unoccluded
// environment's on the bake's normal n. 1 under open sky, 0 where no light reaches (a closed room).
float flySpecularOcclusion(vec3 bakedLux, vec3 n) {
  const vec3 kY = vec3(0.2126, 0.7152, 0.0722);
  float open = dot(flyIrradianceLux(n), kY);
  return clamp(dot(bakedLux, kY) / max(open, 1e-20), 0.0, 1.0);
}
#endif

#ifdef FLY_SUN
// The sun's illuminance on a surface at p facing it (lux): per fragment with FLY_SUN_GLASS, times the T of the
// clear glass between p and the sun; per vertex the fragment stage applies that T to the sun's term, which the
// vertex stage passes apart (kSceneVertex).
vec3 flySunLux(vec3 p) {
#if defined(FLY_SUN_GLASS) && defined(FLY_PER_FRAGMENT)
  return uSunNormalLux * flySunGlass(p);
#else
  return uSunNormalLux;
#endif
}
#endif

#if defined(FLY_SUN) && (defined(FLY_SUN_DIRECT) || defined(FLY_SUN_GLASS))
// The sun's direct term of the modified Phong alone (cd/m²): what `phong` adds for the sun, for a light-mapped
// surface whose light map holds everything but it, and for the sun's term kept apart (FLY_SUN_GLASS).
vec3 flySunTerm(vec3 albedo, Material m, vec3 p, vec3 n, vec3 toEye) {
  vec3 diffuseLux = vec3(0.0);
  vec3 specularLux = vec3(0.0);
  addLight(m, p, n, toEye, uSunDirWorld, flySunLux(p), diffuseLux, specularLux);
  return albedo * flyDiffuseTowards(m, dot(n, toEye)) / kPi * diffuseLux + specularLux * flySunHighlight();
}
#endif

#ifdef FLY_PHONG

// Luminance (cd/m²) of a surface of Lambertian albedo `albedo` and material m's reflection lobe at p.
vec3 phong(vec3 albedo, Material m, vec3 p, vec3 n, vec3 toEye, float corner) {
  vec3 diffuseLux = vec3(0.0);
  vec3 specularLux = vec3(0.0);
  for (int i = 0; i < uLightCount; ++i) {
    vec3 toLight;
    vec3 eLux = flyLightLux(lights[i], p, toLight);
    if (eLux != vec3(0.0)) addLight(m, p, n, toEye, toLight, eLux, diffuseLux, specularLux);
  }
#if defined(FLY_SUN) && (!defined(FLY_SUN_GLASS) || defined(FLY_PER_FRAGMENT))
  vec3 sunSpecularLux = vec3(0.0);
  addLight(m, p, n, toEye, uSunDirWorld, flySunLux(p), diffuseLux, sunSpecularLux);
  specularLux += sunSpecularLux * flySunHighlight();
#endif
  // The directional ambient term (rdb/raster_rdb.h, DirectionalAmbient); in sunlight mode the environment's
  // irradiance in place of it (its specular part is added per fragment: flyEnvironmentSpecular).
#ifdef FLY_IBL
  vec3 ambientLux = uIrradianceAmbient != 0 ? flyIrradianceLux(n)
                                            : (uAmbientUpLux * (1.0 + n.y) * 0.5 + uAmbientDownLux * (1.0 - n.y) * 0.5) *
                                                  (1.0 + kCornerGain * corner);
#else
  vec3 ambientLux = (uAmbientUpLux * (1.0 + n.y) * 0.5 + uAmbientDownLux * (1.0 - n.y) * 0.5) *
                    (1.0 + kCornerGain * corner);
#endif
  vec3 diffuseOverPi = albedo * flyDiffuseTowards(m, dot(n, toEye)) / kPi;
#ifdef FLY_SSAO
  flyAmbientLuminance = diffuseOverPi * ambientLux;
#endif
  return diffuseOverPi * (diffuseLux + ambientLux) + specularLux;
}
#ifdef FLY_REFLECTION_FOG
// The irradiance (lux) at p on normal n that the modified Phong shades with: the lamps, the sun (0 in its
// shadow) and the ambient term (sunlight mode: the environment's irradiance). Reflection fog's E.
vec3 flyPhongIrradianceLux(vec3 p, vec3 n, float corner) {
  vec3 eLux = vec3(0.0);
  for (int i = 0; i < uLightCount; ++i) {
    vec3 toLight;
    vec3 lux = flyLightLux(lights[i], p, toLight);
    eLux += lux * max(dot(n, toLight), 0.0);
  }
#ifdef FLY_SUN
  eLux += flySunLux(p) * max(dot(n, uSunDirWorld), 0.0);
#endif
  vec3 ambientLux = (uAmbientUpLux * (1.0 + n.y) * 0.5 + uAmbientDownLux * (1.0 - n.y) * 0.5) * (1.0 + kCornerGain * corner);
#ifdef FLY_IBL
  if (uIrradianceAmbient != 0) ambientLux = flyIrradianceLux(n);
#endif
  eLux += ambientLux;
  return eLux;
}
#endif
#endif
)GLSL";

// Per vertex: luminance towards the eye (cd/m², linear Rec.709) for the front and the back face. What differs
// between meshes comes per vertex in aSurface (bits 0–29 the material's index, bit 30 two-sided, bit 31 has
// a light map; raster/renderer.cpp, surfaceBits), so a scene without per-fragment surfaces is one draw.
inline constexpr const char* kSceneVertex = R"GLSL(
layout(location = 0) in vec3 aPositionM;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aCorner;
layout(location = 3) in vec3 aFrontLux;
layout(location = 4) in vec3 aBackLux;
layout(location = 5) in uint aSurface;
#ifdef FLY_SUN_DIRECT
layout(location = 12) in vec3 aFrontSunLux;  // the sun-direct part of aFrontLux (rdb::RasterRdb)
layout(location = 13) in vec3 aBackSunLux;
#endif
#ifdef FLY_LIGHT_TEXTURE
layout(location = 6) in vec2 aLightMapUv;  // rdb/lightmap_uv.h's convention
// The slot of the mesh's front light texture (raster/renderer.cpp, uploadLightTextures); bit 31: the back's
// slot follows it; 0xffffffff: no light texture. With sun-direct texels, those of the front (and back)
// follow in the same order.
layout(location = 7) in uint aLightSlot;
out vec2 vLightMapUv;
flat out uint vLightSlot;      // aLightSlot of the triangle, 0xffffffff: none
flat out uint vBack;           // 1: the triangle's provoking vertex faces its back
flat out vec3 vAlbedoOverPi;   // sr⁻¹: the material's light-map reflectance over π (no angle in it)
#ifdef FLY_DIFFUSE_BY_ANGLE
// For the diffuse share towards the eye, per fragment (flyDiffuseTowards): a value per vertex taken flat
// would step along the triangles' shared edges where the angle changes across the surface.
out vec3 vShareNormal;  // the shading normal of the side seen
out vec3 vShareToEye;   // towards the eye (not unit: linear over the triangle)
flat out uint vShareMaterial;
#endif
#endif

out vec3 vLuminance;
#ifdef FLY_SSAO
out vec3 vAmbientLuminance;  // phong's ambient part of vLuminance (shaders/ambient_occlusion_glsl.h)
#endif
invariant gl_Position;  // the sun's shadow caps lie at exactly this depth (raster/sun_shadows.h)
#ifdef FLY_GLASS
out vec3 vTransmittance;  // T(θ) towards the eye
flat out uint vGlass;
#endif
#ifdef FLY_FROSTED
flat out float vAlphaT;  // frosted glass: its transmission lobe's GGX α (kSceneFragment blurs by it); < 0: clear
#endif
#ifdef FLY_SUN_GLASS
out vec3 vSunLuminance;  // the sun's direct term (cd/m²), not in vLuminance: the fragment applies the glass's T
out vec3 vPositionM;
#endif
#ifdef FLY_IBL
// For the environment's specular part, per fragment (flyEnvironmentSpecular): the shading normal (the back's
// on a two-sided mesh seen from behind), the direction to the eye (not unit) and the material.
out vec3 vIblNormal;
out vec3 vToEye;
flat out uint vMaterial;
out float vSpecularOcclusion;  // flySpecularOcclusion of a light-mapped mesh's vertex, 1 without a light map
#ifdef FLY_ROOM_PROBE
out vec3 vProbePositionM;
#endif
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
#ifdef FLY_IBL
  vIblNormal = back ? -n : n;
  vToEye = uOrthographic != 0 ? -uViewDirWorld : uEyeM - aPositionM;
  vMaterial = aSurface & 0x3fffffffu;
  vSpecularOcclusion = 1.0;
#ifdef FLY_ROOM_PROBE
  vProbePositionM = aPositionM;
#endif
#endif
#ifdef FLY_SUN_GLASS
  vSunLuminance = vec3(0.0);
  vPositionM = aPositionM;
#endif
#ifdef FLY_LIGHT_MAP
  useLightMap = (aSurface & 0x80000000u) != 0u;
  // The sun's direct term drawn in real time over a light map without it (FLY_SUN_DIRECT), else 0.
  vec3 sunTerm = vec3(0.0);
  if (useLightMap) {
#ifdef FLY_TWO_SIDED
    vec3 eLux = back ? aBackLux : aFrontLux;
#else
    vec3 eLux = aFrontLux;
#endif
#ifdef FLY_SUN_DIRECT
#ifdef FLY_TWO_SIDED
    eLux = max(eLux - (back ? aBackSunLux : aFrontSunLux), vec3(0.0));
#else
    eLux = max(eLux - aFrontSunLux, vec3(0.0));
#endif
#ifdef FLY_SUN
    sunTerm = flySunTerm(m.diffuse.rgb, m, aPositionM, back ? -n : n, toEye);
#endif
#endif
#ifdef FLY_IBL
#ifndef FLY_ROOM_PROBE
    vSpecularOcclusion = flySpecularOcclusion(eLux, back ? -n : n);  // the probe needs none (kSceneFragment)
#endif
#endif
#ifdef FLY_SUN_GLASS
    vSunLuminance = sunTerm;
    sunTerm = vec3(0.0);
#endif
    l = flyLightMapReflectance(m.diffuse.rgb, m) * flyDiffuseTowards(m, dot(back ? -n : n, toEye)) * eLux / kPi +
        sunTerm;
  }
#endif
#ifdef FLY_LIGHT_TEXTURE
  // The fragment shader adds albedo · E_texel / π in place of the vertex value.
  vLightMapUv = aLightMapUv;
  vAlbedoOverPi = flyLightMapReflectance(m.diffuse.rgb, m) / kPi;
#ifdef FLY_DIFFUSE_BY_ANGLE
  vShareNormal = back ? -n : n;
  vShareToEye = uOrthographic != 0 ? -uViewDirWorld : uEyeM - aPositionM;
  vShareMaterial = aSurface & 0x3fffffffu;
#endif
  vLightSlot = 0xffffffffu;
  vBack = 0u;
  if (useLightMap && aLightSlot != 0xffffffffu) {
    vLightSlot = aLightSlot;
    vBack = back ? 1u : 0u;
    l = sunTerm;
  }
#endif
#ifdef FLY_PHONG
  if (!useLightMap) {
    l = phong(m.diffuse.rgb, m, aPositionM, back ? -n : n, toEye, aCorner);
#ifdef FLY_SUN_GLASS
    vSunLuminance = flySunTerm(m.diffuse.rgb, m, aPositionM, back ? -n : n, toEye);
#endif
  }
#endif
  vLuminance = l + flyEmission(m);
#ifdef FLY_SSAO
  vAmbientLuminance = flyAmbientLuminance;
#endif
#ifdef FLY_GLASS
  // The transmittance at the angle the pane is seen (flyGlassTransmittance).
  vGlass = 0u;
  vTransmittance = vec3(0.0);
#ifdef FLY_FROSTED
  vAlphaT = -1.0;
#endif
  if (max(m.transmission.r, max(m.transmission.g, m.transmission.b)) > 0.0) {
    vTransmittance = flyGlassTransmittance(m, m.transmission.rgb, abs(dot(n, toEye)));
    vGlass = 1u;
#ifdef FLY_FROSTED
    if (m.emission.w > 0.0) vAlphaT = m.emission.w;
#endif
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

// The light textures' lookup, prepended to both fragment stages (raster/renderer.cpp, sceneProgram) with
// FLY_LIGHT_TEXTURE.
inline constexpr const char* kLightTextureLookup = R"GLSL(
#ifdef FLY_LIGHT_TEXTURE
// A slot's place in the array texture: rect = x, y, width, height (texels of the layer); layer = its index,
// 1 / layer width, 1 / layer height.
struct LightRect {
  vec4 rect;
  vec4 layer;
};
layout(std430, binding = 3) readonly buffer LightRects { LightRect lightRects[]; };
layout(binding = 2) uniform sampler2DArray uLightTextures;  // irradiance, lux
// The irradiance (lux) a mesh's light texture shows at light-map UV `uv` on the face `back` or not: its
// slots begin at `slots` (aLightSlot: bit 31, the back follows the front); with FLY_SUN_DIRECT the sun-direct
// texels' slots follow in the same order, and the result is E − E_sunDirect. Bilinear, clamped to the edge of
// each slot's own texels (its neighbours in the layer are never read).
vec3 flySlotTexel(uint slot, vec2 uv) {
  LightRect r = lightRects[slot];
  vec2 t = clamp(uv * r.rect.zw, vec2(0.5), r.rect.zw - vec2(0.5));
  return texture(uLightTextures, vec3((r.rect.xy + t) * r.layer.yz, r.layer.x)).rgb;
}
vec3 flyLightTexel(uint slots, bool back, vec2 uv) {
  bool hasBack = (slots & 0x80000000u) != 0u;
  uint front = slots & 0x7fffffffu;
  uint side = (back && hasBack) ? 1u : 0u;
  vec3 e = flySlotTexel(front + side, uv);
#ifdef FLY_SUN_DIRECT
  e = max(e - flySlotTexel(front + (hasBack ? 2u : 1u) + side, uv), vec3(0.0));
#endif
  return e;
}
#endif
)GLSL";

// A lamp near a measured material's objects evaluated at a point by the BRDF itself (raster/ball_texture.h,
// BallSettings::nearLightRadii), for the surface pass (flyNearLights) and kNearLampsCompute; after
// kSceneCommon and shaders::kMeasuredBrdf, with FLY_MEASURED.
inline constexpr const char* kNearLamp = R"GLSL(
// A surface frame with z = n (any tangent: the BRDFs are isotropic), as rows: local = localFromWorld · world.
mat3 flyLocalFromWorld(vec3 n) {
  vec3 t = normalize(cross(abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), n));
  return transpose(mat3(t, cross(n, t), n));
}
// Luminance (cd/m²) towards wo (local) of lamp lights[light] at p through brdfs[brdf]; adds the luminance of
// its irradiance on the surface (lux) to eLux.
vec3 flyNearLamp(int light, int brdf, vec3 p, mat3 localFromWorld, vec3 wo, inout float eLux) {
  vec3 toLight;
  vec3 e = flyLightLux(lights[light], p, toLight);
  vec3 wi = localFromWorld * toLight;
  if (wi.z <= 0.0) return vec3(0.0);
  eLux += dot(e, vec3(0.2126, 0.7152, 0.0722)) * wi.z;
  return flyMeasuredBrdf(brdf, wi, wo) * wi.z * e;
}
// A unit vector as two 16-bit signed normalised numbers on the octahedron (Meyer et al. 2010; error < 10⁻⁴ rad).
uint flyOctEncode(vec3 n) {
  vec2 o = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
  if (n.z < 0.0) o = (1.0 - abs(o.yx)) * vec2(o.x >= 0.0 ? 1.0 : -1.0, o.y >= 0.0 ? 1.0 : -1.0);
  return packSnorm2x16(o);
}
vec3 flyOctDecode(uint word) {
  vec2 o = unpackSnorm2x16(word);
  vec3 n = vec3(o, 1.0 - abs(o.x) - abs(o.y));
  if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return normalize(n);
}
)GLSL";

// What lies behind a pane, for the glass pass of both scene programs (kSceneFragment, kSurfaceFragment): the
// first pass's image, and for frosted glass that image blurred by the pane's lobe.
inline constexpr const char* kGlassBehind = R"GLSL(
layout(binding = 4) uniform usampler2D uBehind;  // the first pass's image (kLuminanceEncoding)
#ifdef FLY_FROSTED
layout(binding = 3) uniform sampler2D uBehindBlurred;  // uBehind decoded, with a box-filtered mip chain
layout(binding = 1) uniform sampler2D uBehindDepth;    // the first pass's window depth
uniform mat4 uWorldFromClip;
// xyz the eye (world, m); w > 0: pixels per unit of tan(angle from the view axis) at the image's centre
// (perspective), w < 0: −pixels per metre (orthographic).
uniform vec4 uBlurView;
vec3 flyUnproject(vec2 fragCoord, float windowZ, vec2 sizePx) {
  vec4 p = uWorldFromClip * vec4(fragCoord / sizePx * 2.0 - 1.0, windowZ * 2.0 - 1.0, 1.0);
  return p.xyz / p.w;
}
// The mip level of the image behind that blurs it as a frosted pane of GGX α does. A thin-surface GGX lobe
// sends half its light within tan θh < α of the straight-through direction's half vector (its CDF in tan²θh
// is t² / (α² + t²)), i.e. within about 2α rad of the ray: a point at distance D behind the pane along the
// ray, seen from the eye at distance E, is spread over a radius of 2α · D / E in tan units (2α · D metres
// orthographically) — the lobe's full angular width for the sky (D / E → 1), sharp where the scene touches
// the pane. A box-filtered level k averages 2^k pixels: k = log2(2 · radius in pixels).
float flyBlurLod(float alphaT) {
  vec2 sizePx = vec2(textureSize(uBehindBlurred, 0));
  float behindZ = texelFetch(uBehindDepth, ivec2(gl_FragCoord.xy), 0).r;
  float radiusPx = 1e9;  // nothing behind (the sky): the lobe's full width, or the coarsest level
  if (uBlurView.w > 0.0) radiusPx = 2.0 * alphaT * uBlurView.w;
  if (behindZ < 1.0) {
    vec3 pane = flyUnproject(gl_FragCoord.xy, gl_FragCoord.z, sizePx);
    vec3 behind = flyUnproject(gl_FragCoord.xy, behindZ, sizePx);
    float d = distance(behind, pane);
    radiusPx = uBlurView.w > 0.0 ? 2.0 * alphaT * uBlurView.w * clamp(d / max(distance(behind, uBlurView.xyz), 1e-6), 0.0, 1.0)
                                 : -2.0 * alphaT * d * uBlurView.w;
  }
  return log2(max(2.0 * radiusPx, 1.0));
}
#endif
// The luminance behind the pane at this pixel (cd/m²), blurred for a transmission lobe of GGX α > 0.
vec3 flyBehind(float alphaT) {
#ifdef FLY_FROSTED
  if (alphaT > 0.0) {
    return textureLod(uBehindBlurred, gl_FragCoord.xy / vec2(textureSize(uBehindBlurred, 0)), flyBlurLod(alphaT)).rgb;
  }
#endif
  return flyDecodeLuminance(texelFetch(uBehind, ivec2(gl_FragCoord.xy), 0).xy);
}
)GLSL";

// The back of a one-sided surface never reaches these stages: the renderer culls it (glTF's doubleSided:
// false), so what lies behind it shows.
inline constexpr const char* kSceneFragment = R"GLSL(
in vec3 vLuminance;
#ifdef FLY_SSAO
in vec3 vAmbientLuminance;
#endif
#ifdef FLY_SUN_GLASS
in vec3 vSunLuminance;
in vec3 vPositionM;
#endif
layout(location = 0) out uvec2 oLuminance;  // kLuminanceEncoding
#ifdef FLY_GLASS
in vec3 vTransmittance;
flat in uint vGlass;
uniform int uGlassPass;  // 0: all but the glass; 1: the glass alone
#endif
#ifdef FLY_FROSTED
flat in float vAlphaT;
#endif
#ifdef FLY_LIGHT_TEXTURE
in vec2 vLightMapUv;
flat in uint vLightSlot;
flat in uint vBack;
flat in vec3 vAlbedoOverPi;
#ifdef FLY_DIFFUSE_BY_ANGLE
in vec3 vShareNormal;
in vec3 vShareToEye;
flat in uint vShareMaterial;
#endif
#endif
#ifdef FLY_IBL
in vec3 vIblNormal;
in vec3 vToEye;
flat in uint vMaterial;
in float vSpecularOcclusion;
#ifdef FLY_ROOM_PROBE
in vec3 vProbePositionM;
#endif
#endif
void main() {
#ifdef FLY_GLASS
  if ((vGlass != 0u) != (uGlassPass != 0)) discard;
#endif
  vec3 l = vLuminance;
#ifdef FLY_IBL
  float specularOcclusion = vSpecularOcclusion;
#endif
#ifdef FLY_ROOM_PROBE
  gProbePositionM = vProbePositionM;
#endif
#ifdef FLY_LIGHT_TEXTURE
  if (vLightSlot != 0xffffffffu) {
    vec3 eTexelLux = flyLightTexel(vLightSlot, vBack != 0u, vLightMapUv);
    vec3 albedoOverPi = vAlbedoOverPi;
#ifdef FLY_DIFFUSE_BY_ANGLE
    albedoOverPi *= flyDiffuseTowards(materials[vShareMaterial], dot(normalize(vShareNormal), normalize(vShareToEye)));
#endif
    l += albedoOverPi * eTexelLux;
#if defined(FLY_IBL) && !defined(FLY_ROOM_PROBE)
    specularOcclusion = flySpecularOcclusion(eTexelLux, normalize(vIblNormal));
#endif
  }
#endif
#ifdef FLY_IBL
#ifdef FLY_ROOM_PROBE
  specularOcclusion = 1.0;  // the probe shows what occludes the sky
#endif
  l += specularOcclusion * flyEnvironmentSpecular(materials[vMaterial], normalize(vIblNormal), normalize(vToEye));
#endif
#ifdef FLY_SSAO
  l -= (1.0 - flyAmbientOcclusion()) * vAmbientLuminance;
#endif
#ifdef FLY_SUN_GLASS
  // A pane's own sun term (its reflection) is not behind it (raster/sun_glass.h). The renderer compiles
  // FLY_SUN_GLASS only for scenes with clear glass, so FLY_GLASS (vGlass) is defined with it.
  l += vGlass != 0u ? vSunLuminance : vSunLuminance * flySunGlass(vPositionM);
#endif

#ifdef FLY_GLASS
  // Either face of a pane passes light.
  if (vGlass != 0u) {
#ifdef FLY_FROSTED
    l += vTransmittance * flyBehind(vAlphaT);
#else
    l += vTransmittance * flyBehind(0.0);
#endif
  }
#endif
  oLuminance = flyEncodeLuminance(l);
}
)GLSL";

// The per-fragment surfaces' vertex stage: what kSurfaceFragment interpolates. The light-map values of both
// faces pass through, so the fragment picks its face by gl_FrontFacing.
inline constexpr const char* kSurfaceVertex = R"GLSL(
layout(location = 0) in vec3 aPositionM;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aCorner;
layout(location = 3) in vec3 aFrontLux;
layout(location = 4) in vec3 aBackLux;
layout(location = 5) in uint aSurface;
#ifdef FLY_LIGHT_TEXTURE
layout(location = 6) in vec2 aLightMapUv;
layout(location = 7) in uint aLightSlot;
out vec2 vLightMapUv;
flat out uint vLightSlot;
#endif
#ifdef FLY_SUN_DIRECT
layout(location = 12) in vec3 aFrontSunLux;
layout(location = 13) in vec3 aBackSunLux;
out vec3 vFrontSunLux;
#ifdef FLY_TWO_SIDED
out vec3 vBackSunLux;
#endif
#endif
#ifdef FLY_TEXTURES
layout(location = 8) in vec2 aUv0;
out vec2 vUv0;
#ifdef FLY_UV1
layout(location = 9) in vec2 aUv1;
out vec2 vUv1;
#endif
#endif
#ifdef FLY_VERTEX_COLOR
layout(location = 10) in vec4 aColor;  // COLOR_0, linear RGBA
out vec4 vColor;
#endif
#if defined(FLY_NORMAL_MAP) || defined(FLY_ANISOTROPY)
layout(location = 11) in vec4 aTangent;  // world, w: bitangent = w · cross(normal, tangent)
out vec4 vTangent;
#endif
// Only what the variant reads is interpolated (the fewer varyings, the cheaper each pixel).
#if defined(FLY_PHONG) || defined(FLY_SUN_DIRECT) || defined(FLY_MEASURED) || defined(FLY_PLANAR_REFLECTION) || \
    defined(FLY_IBL) || defined(FLY_CUBE_REFLECTION) || defined(FLY_DIFFUSE_BY_ANGLE)
out vec3 vPositionM;
out vec3 vNormal;
#endif
#ifdef FLY_PHONG
out float vCorner;
#endif
#ifdef FLY_LIGHT_MAP
out vec3 vFrontLux;
#ifdef FLY_TWO_SIDED
out vec3 vBackLux;
#endif
#endif
// The surface flags (two-sided, has a light map) where they can differ between meshes of the variant.
#if defined(FLY_TWO_SIDED) || (defined(FLY_PHONG) && defined(FLY_LIGHT_MAP))
#define FLY_SURFACE_FLAGS
flat out uint vSurface;
#endif
invariant gl_Position;  // the sun's shadow caps lie at exactly this depth (raster/sun_shadows.h)

void main() {
  gl_Position = uClipFromWorld * vec4(aPositionM, 1.0);
#if defined(FLY_PHONG) || defined(FLY_SUN_DIRECT) || defined(FLY_MEASURED) || defined(FLY_PLANAR_REFLECTION) || \
    defined(FLY_IBL) || defined(FLY_CUBE_REFLECTION) || defined(FLY_DIFFUSE_BY_ANGLE)
  vPositionM = aPositionM;
  vNormal = aNormal;
#endif
#ifdef FLY_PHONG
  vCorner = aCorner;
#endif
#ifdef FLY_SUN_DIRECT
  vFrontSunLux = aFrontSunLux;
#ifdef FLY_TWO_SIDED
  vBackSunLux = aBackSunLux;
#endif
#endif
#ifdef FLY_LIGHT_MAP
  vFrontLux = aFrontLux;
#ifdef FLY_TWO_SIDED
  vBackLux = aBackLux;
#endif
#endif
#ifdef FLY_SURFACE_FLAGS
  vSurface = aSurface;
#endif
#ifdef FLY_LIGHT_TEXTURE
  vLightMapUv = aLightMapUv;
  vLightSlot = aLightSlot;
#endif
#ifdef FLY_TEXTURES
  vUv0 = aUv0;
#ifdef FLY_UV1
  vUv1 = aUv1;
#endif
#endif
#ifdef FLY_VERTEX_COLOR
  vColor = aColor;
#endif
#if defined(FLY_NORMAL_MAP) || defined(FLY_ANISOTROPY)
  vTangent = aTangent;
#endif
}
)GLSL";

// Per fragment: the base colour (factor × texel × COLOR_0; its alpha, times the opacity, the coverage), the
// normal (normal map), then the same terms as kSceneVertex's: albedo · E / π from the light map (the
// interpolated vertex values of the face seen, or the light texture's texel), or the modified Phong; plus
// the emission (factor × texel). One draw per material (its textures bound to units 5–7), or per mesh for
// blended ones. Textures are sRGB-decoded by the GPU where they hold colour (rdb::RasterTexture::srgb).
inline constexpr const char* kSurfaceFragment = R"GLSL(
#if defined(FLY_PHONG) || defined(FLY_SUN_DIRECT) || defined(FLY_MEASURED) || defined(FLY_PLANAR_REFLECTION) || \
    defined(FLY_IBL) || defined(FLY_CUBE_REFLECTION) || defined(FLY_DIFFUSE_BY_ANGLE)
in vec3 vPositionM;
in vec3 vNormal;
#endif
#ifdef FLY_PHONG
in float vCorner;
#endif
#ifdef FLY_SUN_DIRECT
in vec3 vFrontSunLux;
#ifdef FLY_TWO_SIDED
in vec3 vBackSunLux;
#endif
#endif
#ifdef FLY_LIGHT_MAP
in vec3 vFrontLux;
#ifdef FLY_TWO_SIDED
in vec3 vBackLux;
#endif
#endif
#if defined(FLY_TWO_SIDED) || (defined(FLY_PHONG) && defined(FLY_LIGHT_MAP))
#define FLY_SURFACE_FLAGS
flat in uint vSurface;  // its flags (bits 30, 31: kSceneVertex)
#endif
// The draw's material (one per draw): a uniform index, so the GPU loads its block once for all fragments.
uniform uint uMaterial;
#ifdef FLY_LIGHT_TEXTURE
in vec2 vLightMapUv;
flat in uint vLightSlot;
#endif
#ifdef FLY_TEXTURES
in vec2 vUv0;
#ifdef FLY_UV1
in vec2 vUv1;
#endif
layout(binding = 5) uniform sampler2D uBaseColorTexture;
layout(binding = 6) uniform sampler2D uEmissionTexture;
layout(binding = 7) uniform sampler2D uNormalTexture;
#ifdef FLY_ANISOTROPY
layout(binding = 16) uniform sampler2D uAnisotropyTexture;          // red U, green V
layout(binding = 17) uniform sampler2D uAnisotropyRotationTexture;  // red × 2π: rotation (rad)
#endif
#ifdef FLY_GLOSSINESS_TEXTURE
layout(binding = 18) uniform sampler2D uGlossinessTexture;  // red × the material's glossiness
#endif
#ifdef FLY_GLASS
layout(binding = 19) uniform sampler2D uTransmissionTexture;  // red × the glass's transmission
#endif
#ifdef FLY_METALNESS_TEXTURE
layout(binding = 20) uniform sampler2D uMetalnessTexture;  // red × the material's metalness factor
#endif
// The draw's material's texture slots: bit 0 base colour, 1 emission, 2 normal map, 3 anisotropy, 4 its
// rotation, 5 glossiness, 6 transmission, 7 metalness; and per slot its affine
// UV map (rdb::RasterTextureRef): uv' = (dot(row0.xy, uv) + row0.z, dot(row1.xy, uv) + row1.z), row0.w the
// UV set (0 or 1). Uniforms (one material per draw), so that every invocation of a 2 × 2 quad — helper
// invocations outside the triangle too — computes the UVs whose differences pick the mip level, and the
// samples are taken in uniform control flow, before any discard.
uniform uint uTextureSlots;
uniform vec4 uUvRows[16];  // per slot row0, row1, in the bits' order
#endif
#ifdef FLY_VERTEX_COLOR
in vec4 vColor;
#endif
#if defined(FLY_NORMAL_MAP) || defined(FLY_ANISOTROPY)
in vec4 vTangent;
#endif
#ifdef FLY_PLANAR_REFLECTION
// The draw's reflector's image (kLuminanceEncoding, the size of the target) and R(θ)'s colour and F0
// (RasterMaterial::mirrorReflection, mirrorF0; F0 < 0: uniform).
layout(binding = 11) uniform usampler2D uReflection;
uniform vec3 uMirrorReflection;
uniform float uMirrorF0;
// A glossy reflector (uMirrorGlossy) shows its image blurred as its lobe spreads the light (raster/mirror_blur.h):
// its settled pyramid's level 0 read bilinearly within uMirrorFine plus level 1 read along the lobe's wide
// axis (flyMirrorTaps) within uMirrorCoarse (lo.xy, hi.xy exclusive; empty: a pyramid of one level). Its
// mirrored pass may be drawn uMirrorScale times coarser than the image per axis (1, 2 or 4): its pixel (x, y)
// covers the image's pixels s·x … s·x + s − 1, and the pyramid is the pass's.
uniform bool uMirrorGlossy;
uniform float uMirrorScale;
layout(binding = 3) uniform sampler2D uReflectionBlurred;
uniform ivec4 uMirrorFine;
uniform ivec4 uMirrorCoarse;
vec3 flyMirrorImage() {
  if (!uMirrorGlossy) return flyDecodeLuminance(texelFetch(uReflection, ivec2(gl_FragCoord.xy), 0).xy);
  vec3 l = flyMirrorBilinear(uReflectionBlurred, gl_FragCoord.xy / uMirrorScale - 0.5, 0, uMirrorFine);
  if (uMirrorCoarse.z > uMirrorCoarse.x)
    l += flyMirrorTaps(uReflectionBlurred, gl_FragCoord.xy / (2.0 * uMirrorScale) - 0.5, 1, uMirrorCoarse);
  return l;
}
#endif
#ifdef FLY_REFLECTION_FOG
// The draw's material's reflection fog (rdb::RasterMaterial): distance (m; ≤ 0: none) and colour.
uniform float uFogDistanceM;
uniform vec3 uFogColor;
#ifdef FLY_PLANAR_REFLECTION
// A fogged planar reflector's mirrored pass: its depth (valid in the mirror's screen rectangle, which holds
// the mirror's fragments) and worldFromClip, which say how far behind the mirror what a pixel shows lies.
layout(binding = 1) uniform sampler2D uReflectionDepth;
uniform mat4 uMirrorWorldFromClip;
// The distance (m) from p on the mirror to what the mirrored pass shows at fragCoord; 10³⁰ for nothing (the
// sky). (A fogged reflector's pass is drawn at the image's resolution.)
float flyMirrorDistance(vec2 fragCoord, vec3 p, vec2 sizePx) {
  float z = texelFetch(uReflectionDepth, ivec2(clamp(fragCoord, vec2(0.0), sizePx - 1.0)), 0).r;
  if (z >= 1.0) return 1e30;
  vec4 q = uMirrorWorldFromClip * vec4(fragCoord / sizePx * 2.0 - 1.0, z * 2.0 - 1.0, 1.0);
  return distance(q.xyz / q.w, p);
}
#endif
#endif
#ifdef FLY_BLEND_PASS
layout(location = 0) out vec4 oBlend;  // (coverage · L, coverage): "over", back to front
#else
layout(location = 0) out uvec2 oLuminance;  // kLuminanceEncoding
#endif

#ifdef FLY_MEASURED
// The draw's material's ball (raster/ball_texture.h): layer uBallLayer the lights and the environment,
// uBallLayer + 1 the sun; −1 for a material without a measured BRDF. uBallFromWorld: the ball's frame, whose
// +Z points from the material's objects to the eye (raster/ball_texture.h).
layout(binding = 9) uniform sampler2DArray uBalls;
uniform int uBallLayer;
uniform mat3 uBallFromWorld;
// The lamps near the draw's material's objects (raster/ball_texture.h, BallSettings::nearLightRadii): indices
// into lights[], evaluated per pixel with the pixel's own direction and distance; the ball holds the rest.
uniform int uNearLights[FLY_MAX_NEAR_LIGHTS];
uniform int uNearLightCount;

#ifdef FLY_NEAR_DEFERRED
// The opaque draws leave the near lamps to kNearLampsCompute, which evaluates them once per pixel on every
// processor of the GPU (a fragment shader's quads evaluate pixels up to 4 times over on small triangles, and
// on the H100 the fragment stage runs on a few of its processors): per pixel what that pass needs
// (flyNearRecord), 0 in .y where there is nothing to add.
layout(location = 1) out uvec4 oNear;       // oct normal, BRDF index + 1 | light-map bit << 8, depth, B
layout(location = 2) out uvec4 oNearLight;  // C, the additive part outside the light-map ratio, 0
uvec4 gNear = uvec4(0u);
vec3 gNearOutside = vec3(0.0);  // the light-map mode's additive part (the ball's sun), emission added in main
float gNearBakedLux = 0.0;
#endif

// The near lamps' luminance (cd/m²) at p with normal n seen from toEye (world), by the BRDF itself
// (shaders/ball_texture_glsl.h, kMeasuredBrdf); adds the luminance of their irradiance to eLux. With
// FLY_NEAR_DEFERRED, 0: the pixel's data is recorded for kNearLampsCompute instead (light-map mode: the
// denominator eBall + ε, the baked luminance, the additive part; flyMeasuredLightMap).
vec3 flyNearLights(vec3 p, vec3 n, vec3 toEye, inout float eLux) {
  vec3 l = vec3(0.0);
  if (uNearLightCount == 0) return l;
#ifdef FLY_NEAR_DEFERRED
  gNear = uvec4(flyOctEncode(n), uint(uBallLayer / 2 + 1), floatBitsToUint(gl_FragCoord.z), 0u);
#else
  mat3 localFromWorld = flyLocalFromWorld(n);
  vec3 wo = localFromWorld * toEye;
  for (int k = 0; k < uNearLightCount; ++k) l += flyNearLamp(uNearLights[k], uBallLayer / 2, p, localFromWorld, wo, eLux);
#endif
  return l;
}

// Sphere mapping with the view direction per pixel: the reflection r of the direction to the eye about the
// normal (ball frame) is what the ball shows at the normal halfway between r and the ball's +Z.
vec2 flyBallUv(vec3 n, vec3 toEye) {
  vec3 nView = uBallFromWorld * n;
  vec3 vView = uBallFromWorld * toEye;
  vec3 r = 2.0 * dot(nView, vView) * nView - vView;
  vec3 h = r + vec3(0.0, 0.0, 1.0);
  float len = length(h);
  vec2 xy = len > 1e-6 ? h.xy / len : vec2(1.0, 0.0);
  return xy * 0.5 + 0.5;
}

// The ball's sun at ball coordinates uv where the sun reaches the pixel (uSunNormalLux is 0 in the shadow
// pass), times the glass's T on the way (FLY_SUN_GLASS).
vec3 flyBallSun(vec2 uv) {
  vec3 sunFactor = vec3(max(uSunNormalLux.r, max(uSunNormalLux.g, uSunNormalLux.b)) > 0.0 ? 1.0 : 0.0);
#if defined(FLY_SUN) && defined(FLY_SUN_GLASS)
  sunFactor *= flySunGlass(vPositionM);
#endif
  return sunFactor * texture(uBalls, vec3(uv, float(uBallLayer + 1))).rgb;
}

// Luminance (cd/m²) under the current lights: the ball's lights and environment, the near lamps per pixel,
// and the ball's sun.
vec3 flyMeasuredLit(vec3 n, vec3 toEye) {
  vec2 uv = flyBallUv(n, toEye);
  float unused = 0.0;
  return texture(uBalls, vec3(uv, float(uBallLayer))).rgb + flyNearLights(vPositionM, n, toEye, unused) +
         flyBallSun(uv);
}

#ifdef FLY_LIGHT_MAP
// Luminance under baked light of irradiance eLux (lux): an irradiance light map does not say where its light
// came from, which a measured BRDF needs, so the ball's directional distribution is kept and scaled to the
// baked level: L = Y(E_baked) · (ball + ε · albedo/π) / (Y(E_ball) + ε), with E_ball the irradiance the ball's
// own light gives the pixel's normal (the balls' a, read at the normal's own texel, plus the near lamps').
// Shadows and interreflections scale the highlight; where the ball's light gives nothing (E_ball ≪ ε) it is a
// diffuse albedo · E / π. ε = 10⁻³ · Y(E_baked) + 10⁻⁶ lux. Over light maps that keep the sun apart (FLY_SUN_DIRECT)
// the ratio is of the other light, and the ball's sun is added as in flyMeasuredLit.
vec3 flyMeasuredLightMap(vec3 eLux, vec3 albedo, vec3 n, vec3 toEye) {
  vec2 uv = flyBallUv(n, toEye);
  vec3 nView = uBallFromWorld * n;
  vec2 nUv = (nView.z > 0.0 ? nView.xy : normalize(nView.xy + vec2(1e-12, 0.0))) * 0.5 + 0.5;
  float eBaked = dot(eLux, vec3(0.2126, 0.7152, 0.0722));
  float eps = 1e-3 * eBaked + 1e-6;
  float eBall = texture(uBalls, vec3(nUv, float(uBallLayer))).a;
  vec3 lights = texture(uBalls, vec3(uv, float(uBallLayer))).rgb + flyNearLights(vPositionM, n, toEye, eBall);
#if defined(FLY_SUN_DIRECT) && defined(FLY_SUN)
  vec3 outside = flyBallSun(uv);
#else
  lights += texture(uBalls, vec3(uv, float(uBallLayer + 1))).rgb;
  eBall += texture(uBalls, vec3(nUv, float(uBallLayer + 1))).a;
  vec3 outside = vec3(0.0);
#endif
#ifdef FLY_NEAR_DEFERRED
  if (gNear.y != 0u) {
    gNear.y |= 0x100u;
    gNear.w = floatBitsToUint(eBall + eps);
    gNearBakedLux = eBaked;
    gNearOutside = outside;
  }
#endif
  return eBaked * (lights + eps * albedo / kPi) / (eBall + eps) + outside;
}
#endif
#endif

#ifdef FLY_TEXTURES
vec2 flyTextureUv(vec4 row0, vec4 row1) {
#ifdef FLY_UV1
  vec2 uv = row0.w > 0.5 ? vUv1 : vUv0;
#else
  vec2 uv = vUv0;
#endif
  return vec2(dot(row0.xy, uv) + row0.z, dot(row1.xy, uv) + row1.z);
}
#endif

void main() {
  Material m = materials[uMaterial];
#ifdef FLY_ROOM_PROBE
  gProbePositionM = vPositionM;
#endif
#ifdef FLY_TWO_SIDED
  bool twoSided = (vSurface & 0x40000000u) != 0u;
#else
  bool twoSided = false;  // no mesh of the scene is
#endif
  vec4 base = vec4(m.diffuse.rgb, m.coverage.x);
  vec3 emission = flyEmission(m);
#ifdef FLY_TEXTURES
  vec3 normalTexel = vec3(0.5, 0.5, 1.0);
  if ((uTextureSlots & 1u) != 0u) {
    vec4 texel = texture(uBaseColorTexture, flyTextureUv(uUvRows[0], uUvRows[1]));
    base *= texel;
    if (m.diffuse.w > 0.5) {  // a metal's reflection of its base colour texture (RasterMaterial::reflectionTinted)
      m.specular.rgb *= texel.rgb;
      m.reflection.rgb *= texel.rgb;
      m.environment.rgb *= texel.rgb;
    }
  }
  if ((uTextureSlots & 2u) != 0u) emission *= texture(uEmissionTexture, flyTextureUv(uUvRows[2], uUvRows[3])).rgb;
#ifdef FLY_NORMAL_MAP
  if ((uTextureSlots & 4u) != 0u) normalTexel = texture(uNormalTexture, flyTextureUv(uUvRows[4], uUvRows[5])).xyz;
#endif
#endif
#ifdef FLY_ANISOTROPY
  vec3 anisotropy = m.anisotropy.xyz;  // U, V, rotation (rad); the textures replace them
#ifdef FLY_TEXTURES
  if ((uTextureSlots & 8u) != 0u)
    anisotropy.xy = texture(uAnisotropyTexture, flyTextureUv(uUvRows[6], uUvRows[7])).rg;
  if ((uTextureSlots & 16u) != 0u)
    anisotropy.z = 2.0 * kPi * texture(uAnisotropyRotationTexture, flyTextureUv(uUvRows[8], uUvRows[9])).r;
#endif
#endif
#ifdef FLY_GLOSSINESS_TEXTURE
  // The lobe's width at the pixel (rdb::RasterMaterial::glossinessTexture): α = (glossiness · red)², which
  // every specular term and the anisotropic widths below take from m.environment.w.
  if ((uTextureSlots & 32u) != 0u) {
    float red = texture(uGlossinessTexture, flyTextureUv(uUvRows[10], uUvRows[11])).r;
    m.environment.w *= red * red;
  }
#endif
#ifdef FLY_GLASS
  // The glass's transmission colour at the pixel; with a transmission texture the diffuse input loses the
  // texel's transmission share (rdb::RasterMaterial::transmissionTexture).
  vec3 glassT = m.transmission.rgb;
#ifdef FLY_TEXTURES
  if ((uTextureSlots & 64u) != 0u) {
    glassT *= texture(uTransmissionTexture, flyTextureUv(uUvRows[12], uUvRows[13])).r;
    if ((uTextureSlots & 128u) == 0u) base.rgb *= vec3(1.0) - clamp(glassT, 0.0, 1.0);
  }
#endif
#endif
#ifdef FLY_VERTEX_COLOR
  base *= vColor;
#endif
#ifdef FLY_METALNESS_TEXTURE
  // Metalness k at the pixel (rdb::RasterMaterial::metalnessTexture): the material mixed with a uniform
  // reflector of the base colour c (base.rgb: the diffuse colour × texel × COLOR_0). R0, R90 and the
  // reflection colour → mix(·, c, k), transmission × (1 − k), and the energy rule at normal incidence gives
  // the albedo (1 − R0)(1 − t)(1 − k) c.
  if ((uTextureSlots & 128u) != 0u) {
    float red = texture(uMetalnessTexture, flyTextureUv(uUvRows[14], uUvRows[15])).r;
    float k = clamp(m.reflection.w * red, 0.0, 1.0);
    vec3 c = clamp(base.rgb, 0.0, 1.0);
    m.specular.rgb = mix(m.specular.rgb, c, k);
    m.environment.rgb = mix(m.environment.rgb, c, k);
    m.reflection.rgb = mix(m.reflection.rgb, c, k);
    vec3 t = vec3(0.0);
#ifdef FLY_GLASS
    glassT *= 1.0 - k;
    t = clamp(glassT, 0.0, 1.0);
#endif
    base.rgb = c * (1.0 - k) * (vec3(1.0) - m.specular.rgb) * (vec3(1.0) - t);
  }
#endif
#ifdef FLY_ALPHA_MASK
  if (base.a < m.coverage.y) discard;
#endif
  bool back = !gl_FrontFacing;
  vec3 l = vec3(0.0);
#if defined(FLY_PHONG) || defined(FLY_SUN_DIRECT) || defined(FLY_MEASURED) || defined(FLY_PLANAR_REFLECTION) || \
    defined(FLY_IBL) || defined(FLY_CUBE_REFLECTION) || defined(FLY_DIFFUSE_BY_ANGLE)
  // The shading normal (bent by the normal map) and the direction to the eye, for the Phong and sun terms and
  // the diffuse share towards the eye (flyDiffuseTowards).
  vec3 toEye = uOrthographic != 0 ? -uViewDirWorld : normalize(uEyeM - vPositionM);
  vec3 n = normalize(vNormal);
#ifdef FLY_NORMAL_MAP
  if ((uTextureSlots & 4u) != 0u) {
    // glTF's tangent space: x along the tangent, y along w · cross(n, t), z along n.
    vec3 t = vTangent.xyz - n * dot(n, vTangent.xyz);
    float tl = dot(t, t);
    if (tl > 1e-12) {
      t *= inversesqrt(tl);
      vec3 b = (vTangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
      vec3 s = normalTexel * 2.0 - 1.0;
      s.xy *= m.coverage.z;
      vec3 bent = t * s.x + b * s.y + n * s.z;
      if (dot(bent, bent) > 1e-12) n = normalize(bent);
    }
  }
#endif
  if (back && twoSided) n = -n;
#ifdef FLY_ANISOTROPY
  if (m.anisotropy.w > 0.0) {
    // The lobe's axes: the tangent made perpendicular to the shading normal, turned by the rotation about it
    // towards the bitangent w · n × t of the front face (glTF's tangent frame; the baker's, raytracer/
    // surface_point.h: the brushing stays where it is on a two-sided surface's back), and n × t
    // (rdb::RasterMaterial::anisotropic).
    vec3 t = vTangent.xyz - n * dot(n, vTangent.xyz);
    float tl = dot(t, t);
    if (tl > 1e-12) {
      t *= inversesqrt(tl);
      float c = cos(anisotropy.z), s = sin(anisotropy.z);
      float w = (vTangent.w < 0.0 ? -1.0 : 1.0) * (back && twoSided ? -1.0 : 1.0);
      gLobeT = c * t + s * w * cross(n, t);
      gLobeB = cross(n, gLobeT);
      gLobeAlphas = flyAnisotropicAlphas(m.environment.w, anisotropy.x, anisotropy.y);
    }
  }
#endif
#endif
  bool useLightMap = false;
#if defined(FLY_IBL) || defined(FLY_CUBE_REFLECTION)
  float specularOcclusion = 1.0;  // flySpecularOcclusion on a light-mapped surface under the sky's light
#endif
#ifdef FLY_REFLECTION_FOG
  // Reflection fog's E: what the mode has at the pixel (the light map's irradiance, or the Phong's lamps, sun
  // and ambient term).
  vec3 fogIrradianceLux = vec3(0.0);
#endif
#ifdef FLY_LIGHT_MAP
#ifdef FLY_PHONG
  useLightMap = (vSurface & 0x80000000u) != 0u;
#else
  useLightMap = true;  // every mesh has a light map (the renderer leaves FLY_PHONG out only then)
#endif
  if (useLightMap) {
#ifdef FLY_TWO_SIDED
    vec3 eLux = (back && twoSided) ? vBackLux : vFrontLux;
#else
    vec3 eLux = vFrontLux;
#endif
#ifdef FLY_SUN_DIRECT
    // The light map without the sun's direct part; the sun's direct term for the current sun instead.
#ifdef FLY_TWO_SIDED
    eLux = max(eLux - ((back && twoSided) ? vBackSunLux : vFrontSunLux), vec3(0.0));
#else
    eLux = max(eLux - vFrontSunLux, vec3(0.0));
#endif
#endif
#ifdef FLY_LIGHT_TEXTURE
    if (vLightSlot != 0xffffffffu) eLux = flyLightTexel(vLightSlot, back, vLightMapUv);
#endif
#ifdef FLY_IBL
    // On the normal the light map was baked for (the interpolated one, not the normal map's).
#ifndef FLY_ROOM_PROBE
    specularOcclusion = flySpecularOcclusion(eLux, (back && twoSided) ? -normalize(vNormal) : normalize(vNormal));
#endif
#ifdef FLY_CUBE_REFLECTION
    if (uCubeReflector >= 0) specularOcclusion = 1.0;  // its cube map shows what it sees
#endif

#endif
    vec3 reflectance = flyLightMapReflectance(base.rgb, m);
#ifdef FLY_PLANAR_REFLECTION
    if (uReflector >= 0) reflectance = base.rgb;  // the reflection image shows what the mirror reflects
#endif
#ifdef FLY_CUBE_REFLECTION
    if (uCubeReflector >= 0) reflectance = base.rgb;  // its cube map shows what it reflects
#endif
#ifdef FLY_DIFFUSE_BY_ANGLE
    l = reflectance * flyDiffuseTowards(m, dot(n, toEye)) * eLux / kPi;
#else
    l = reflectance * eLux / kPi;  // every material's diffuse share is the same at every angle
#endif
#if defined(FLY_SUN_DIRECT) && defined(FLY_SUN)
    l += flySunTerm(base.rgb, m, vPositionM, n, toEye);
#endif
#ifdef FLY_REFLECTION_FOG
    fogIrradianceLux = eLux;
#if defined(FLY_SUN_DIRECT) && defined(FLY_SUN)
    fogIrradianceLux += flySunLux(vPositionM) * max(dot(n, uSunDirWorld), 0.0);
#endif
#endif
#ifdef FLY_MEASURED
    if (uBallLayer >= 0) l = flyMeasuredLightMap(eLux, base.rgb, n, toEye);
#endif
  }
#endif
#ifdef FLY_PHONG
  if (!useLightMap) {
#ifdef FLY_MEASURED
    if (uBallLayer >= 0) {
      l = flyMeasuredLit(n, toEye);
    } else {
      l = phong(base.rgb, m, vPositionM, n, toEye, vCorner);
    }
#else
    l = phong(base.rgb, m, vPositionM, n, toEye, vCorner);
#endif
#ifdef FLY_SSAO
    l -= (1.0 - flyAmbientOcclusion()) * flyAmbientLuminance;
#endif
#ifdef FLY_REFLECTION_FOG
    fogIrradianceLux = flyPhongIrradianceLux(vPositionM, n, vCorner);
#endif
  }
#endif
#ifdef FLY_REFLECTION_FOG
  // L_fog = fogColor · E / π: the luminance of a Lambertian surface of albedo fogColor at the pixel.
  vec3 fogCdM2 = uFogColor * fogIrradianceLux / kPi;
#endif
#if defined(FLY_IBL) || defined(FLY_CUBE_REFLECTION)
  // The environment's specular part (without FLY_IBL, only a cube reflector's); a planar reflector's image and
  // a measured BRDF's ball show their own.
  bool environmentReflects = !back || twoSided;
#ifndef FLY_IBL
  environmentReflects = environmentReflects && uCubeReflector >= 0;
#endif
#ifdef FLY_PLANAR_REFLECTION
  environmentReflects = environmentReflects && uReflector < 0;
#endif
#ifdef FLY_MEASURED
  environmentReflects = environmentReflects && uBallLayer < 0;
#endif
#ifdef FLY_REFLECTION_FOG
  bool cubeMaps = false;
#ifdef FLY_CUBE_REFLECTION
  cubeMaps = uCubeReflector >= 0;
#endif
  if (environmentReflects) {
    l += uFogDistanceM > 0.0 ? flyEnvironmentSpecularFogged(m, n, toEye, fogCdM2, cubeMaps, specularOcclusion)
                             : specularOcclusion * flyEnvironmentSpecular(m, n, toEye);
  }
#else
  if (environmentReflects) l += specularOcclusion * flyEnvironmentSpecular(m, n, toEye);
#endif
#endif
#ifdef FLY_PLANAR_REFLECTION
  // What the mirror reflects: the mirrored pass's image at this pixel (renderer.cpp, render), blurred by a
  // glossy mirror's lobe, times R(θ).
  if (uReflector >= 0 && !back) {
    float x = 1.0 - clamp(dot(n, toEye), 0.0, 1.0);
    float fresnel = uMirrorF0 < 0.0 ? 1.0 : uMirrorF0 + (1.0 - uMirrorF0) * x * x * x * x * x;
    vec3 image = flyMirrorImage();
#ifdef FLY_REFLECTION_FOG
    // Fades to the fog by the distance from this point to what its image shows (the sky: t = 1).
    if (uFogDistanceM > 0.0) {
      float d = flyMirrorDistance(gl_FragCoord.xy, vPositionM, vec2(textureSize(uReflectionDepth, 0)));
      image = mix(image, fogCdM2, min(d / uFogDistanceM, 1.0));
    }
#endif
    l += uMirrorReflection * fresnel * image;
  }
#endif
  l += emission;
#ifdef FLY_GLASS
  // Either face of a pane passes what lies behind it, times T(θ) at the angle it is seen.
  vec3 glassToEye = uOrthographic != 0 ? -uViewDirWorld : normalize(uEyeM - vPositionM);
  l += flyGlassTransmittance(m, glassT, abs(dot(normalize(vNormal), glassToEye))) * flyBehind(m.emission.w);
#endif
#ifdef FLY_BLEND_PASS
  float a = clamp(base.a, 0.0, 1.0);
  oBlend = vec4(l * a, a);
#else
  oLuminance = flyEncodeLuminance(l);
#endif
#ifdef FLY_NEAR_DEFERRED
  oNear = (!back || twoSided) ? gNear : uvec4(0u);
  oNearLight = uvec4(floatBitsToUint(gNearBakedLux), flyEncodeLuminance(gNearOutside + emission), 0u);
#endif
}
)GLSL";

// The near lamps of the measured materials' opaque pixels (FLY_NEAR_DEFERRED; raster/ball_texture.h,
// BallSettings::nearLightRadii), once per pixel after the opaque draws: the point from the pixel's depth, the
// lamps by the BRDF itself (kNearLamp), added to the image — L + N in the modes without light maps; in the
// light-map modes flyMeasuredLightMap's ratio with the lamps' part added, (M · B + C · N) / (B + E_N) + S,
// where M = L − S is the ratio's value without them, B its denominator, C the baked luminance, S the additive
// part (the ball's sun, emission) and E_N the lamps' irradiance (luminance, lux). Each pixel's record is reset
// to 0 once read, so the next frame starts from an empty one.
inline constexpr const char* kNearLampsCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32ui) uniform uimage2D uLuminance;  // kLuminanceEncoding
layout(binding = 1, rgba32ui) uniform uimage2D uNear;
layout(binding = 2, rgba32ui) uniform readonly uimage2D uNearLight;
// Per measured BRDF k: nearLists[k · (FLY_MAX_NEAR_LIGHTS + 1)] lamps, then their indices into lights[].
layout(std430, binding = 5) readonly buffer NearLists { int nearLists[]; };
uniform mat4 uWorldFromClip;
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(uLuminance);
  if (px.x >= size.x || px.y >= size.y) return;
  uvec4 g = imageLoad(uNear, px);
  if (g.y == 0u) return;
  imageStore(uNear, px, uvec4(0u));
  int brdf = int(g.y & 0xffu) - 1;
  vec4 clip = vec4((vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0, uintBitsToFloat(g.z) * 2.0 - 1.0, 1.0);
  vec4 world = uWorldFromClip * clip;
  vec3 p = world.xyz / world.w;
  vec3 n = flyOctDecode(g.x);
  vec3 toEye = uOrthographic != 0 ? -uViewDirWorld : normalize(uEyeM - p);
  mat3 localFromWorld = flyLocalFromWorld(n);
  vec3 wo = localFromWorld * toEye;
  int first = brdf * (FLY_MAX_NEAR_LIGHTS + 1);
  vec3 lamps = vec3(0.0);
  float eLamps = 0.0;
  for (int k = 0; k < nearLists[first]; ++k) lamps += flyNearLamp(nearLists[first + 1 + k], brdf, p, localFromWorld, wo, eLamps);
  vec3 l = flyDecodeLuminance(imageLoad(uLuminance, px).xy);
  if ((g.y & 0x100u) == 0u) {
    l += lamps;
  } else {
    uvec4 h = imageLoad(uNearLight, px);
    vec3 outside = flyDecodeLuminance(h.yz);
    float b = uintBitsToFloat(g.w);
    l = (max(l - outside, vec3(0.0)) * b + uintBitsToFloat(h.x) * lamps) / (b + eLamps) + outside;
  }
  imageStore(uLuminance, px, uvec4(flyEncodeLuminance(l), 0u, 0u));
}
)GLSL";

// Blended surfaces over the image: the blend target holds, per pixel, C = Σ over the surfaces back to front of
// "over" (C ← a · L + (1 − a) · C) and T = Π (1 − a), so what the pixel shows is C + T · (the image behind).
inline constexpr const char* kBlendComposite = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32ui) uniform uimage2D uLuminance;  // kLuminanceEncoding
layout(binding = 1, rgba32f) uniform readonly image2D uBlend;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(uLuminance);
  if (p.x >= size.x || p.y >= size.y) return;
  vec4 b = imageLoad(uBlend, p);
  if (b.a >= 1.0) return;  // no blended surface in this pixel
  vec3 behind = flyDecodeLuminance(imageLoad(uLuminance, p).xy);
  imageStore(uLuminance, p, uvec4(flyEncodeLuminance(b.rgb + b.a * behind), 0u, 0u));
}
)GLSL";

// What lies behind frosted glass decoded (kLuminanceEncoding) into a float image whose mip chain the panes
// read blurred (raster/renderer.h, FLY_FROSTED).
inline constexpr const char* kBehindDecode = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32ui) uniform readonly uimage2D uBehind;
layout(binding = 1, rgba32f) uniform writeonly image2D uOut;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(uOut);
  if (p.x >= size.x || p.y >= size.y) return;
  imageStore(uOut, p, vec4(flyDecodeLuminance(imageLoad(uBehind, p).xy), 1.0));
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
uniform ivec4 uRegion;  // the pixels to fill: x, y, width, height
uniform vec2 uPassPx;   // the pass's size (a mirrored pass may use a corner of the image)
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
  if (any(greaterThanEqual(ivec2(gl_GlobalInvocationID.xy), uRegion.zw))) return;
  ivec2 p = uRegion.xy + ivec2(gl_GlobalInvocationID.xy);
  vec3 l = vec3(0.0);
#ifdef FLY_SKY
  vec2 ndc = (vec2(p) + 0.5) / uPassPx * 2.0 - 1.0;  // the pixel's centre
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
