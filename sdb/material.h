// The physical "realistic material" (HOOPS Luminate's realistic material): Lambertian diffuse,
// reflection and transmission colours with an energy rule that keeps their sum ≤ 1, Fresnel or uniform
// reflection, glossy and anisotropic lobes, absorption inside transmissive media, reflection fog, a bump map,
// emission in cd/m², and optionally a measured (MERL table) or fitted (car paint) BRDF.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "base/color.h"
#include "sdb/car_paint_brdf.h"
#include "sdb/measured_brdf.h"
#include "sdb/texture.h"

namespace fly::sdb {

// How the reflection amount varies with the angle of incidence (the realistic material, "Reflection").
enum class ReflectionModel {
  kFresnel,  // Schlick's approximation, F0 from `ior`, multiplied by the reflection colour
  kUniform,  // the reflection colour at every angle
};

// How the OpenGL engine shows what a surface reflects (FLY §5: chosen by shape and material).
enum class EngineReflection {
  kAuto,     // where the material is mirror-like (isMirrorLike): a planar reflection on a flat mesh, a cube map
             // on a curved one
  kPlanar,   // a planar reflection wherever the mesh is flat, whatever the reflectance (polished floors, water)
  kCubemap,  // a cube map rendered from each mesh's centre, flat or curved, whatever the reflectance
  kNone,     // none: the reflection lobe's highlights of the lights only
};

// The three reflectances after the energy rule; each channel in [0,1] and d + r + t ≤ 1 per channel.
struct EffectiveComponents {
  Rgb diffuse{0.0f};
  Rgb reflection{0.0f};
  Rgb transmission{0.0f};
};

// The realistic material's energy rule, applied per channel after clamping each input to [0,1]:
//   reflect' = reflect;  transmission' = (1 − reflect')·transmission;  diffuse' = (1 − reflect' − transmission')·diffuse.
// Textured materials apply it per texel with the same function.
EffectiveComponents applyEnergyRule(const Rgb& diffuse, const Rgb& reflection, const Rgb& transmission);

// How a surface's coverage (its alpha) is used (glTF 2.0 §3.9.4 "Alpha Coverage").
enum class AlphaMode {
  kOpaque,  // fully covered everywhere; alpha is ignored
  kMask,    // a cut-out: covered where coverage ≥ alphaCutoff, absent (light and rays pass) elsewhere
  kBlend,   // partial coverage: a fraction 1 − coverage of the light passes straight through, unbent
};

// Fresnel reflectance at normal incidence from the index of refraction (against air): F0 = ((n − 1)/(n + 1))².
float fresnelF0(float ior);
// Schlick's approximation (Schlick 1994, eq. 24): F(θ) = F0 + (1 − F0)(1 − cos θ)⁵, cos θ clamped to [0,1].
float schlickFresnel(float cosTheta, float f0);

// GGX α below which a lobe is a delta (a mirror, clear transmission): at α = 10⁻³ (glossiness 0.032) the lobe
// is 0.06° wide, far narrower than the sun (0.53°), and its density overflows float precision (pbrt-v4's
// TrowbridgeReitzDistribution::EffectivelySmooth uses the same bound). Both engines use it (raytracer/bsdf.h
// keeps a copy, checked equal by its test).
inline constexpr float kSmoothAlpha = 1e-3f;

struct Material {
  std::string name;

  // Which preset it came from ("" = none, e.g. converted from glTF). See material_presets.h.
  std::string preset;

  // Diffuse (Lambertian) reflectance, linear Rec.709, each channel in [0,1]. Default 0.8 (a light grey paint).
  Rgb diffuseColor{0.8f};
  TextureRef diffuseTexture;  // sRGB-encoded; multiplies diffuseColor

  // Coverage (glTF alpha), [0,1]: opacity × the alpha channel of diffuseTexture (when it has one) × the
  // mesh's COLOR_0 alpha, used as alphaMode says. Default 1 with kOpaque.
  AlphaMode alphaMode = AlphaMode::kOpaque;
  float opacity = 1.0f;      // glTF baseColorFactor alpha
  float alphaCutoff = 0.5f;  // kMask threshold, [0,1] (glTF alphaCutoff, default 0.5)

  // Reflection colour, linear, [0,1]; takes precedence over transmission and diffuse in the energy rule.
  Rgb reflectionColor{0.0f};
  TextureRef reflectionTexture;  // multiplies reflectionColor; linear unless reflectionTextureSrgb
  // reflectionTexture holds sRGB-encoded colour (a glTF metal's base colour texture) rather than linear values.
  bool reflectionTextureSrgb = false;
  ReflectionModel reflectionModel = ReflectionModel::kFresnel;

  // Index of refraction, [1, 4]. Default 1.5 (glass, most plastics and paints; glTF's default). Sets the Fresnel
  // F0 = ((ior − 1)/(ior + 1))² and bends transmitted rays.
  float ior = 1.5f;

  // Reflection glossiness, [0,1]: 0 = a perfect mirror, 1 = the widest lobe. Equal to glTF's perceptual
  // roughness; the microfacet (GGX) width is α = glossiness². Default 0.5.
  float reflectionGlossiness = 0.5f;
  EngineReflection engineReflection = EngineReflection::kAuto;  // the scene file's "engineReflection"
  TextureRef reflectionGlossinessTexture;  // linear, red channel; multiplies reflectionGlossiness

  // Anisotropy in U and V (tangent and bitangent directions), each in [0,1]: the larger, the wider the
  // reflection along that direction (the realistic material). Equal values (the default 0,0) = isotropic.
  float anisotropyU = 0.0f;
  float anisotropyV = 0.0f;
  float anisotropyRotationRad = 0.0f;        // rotation of the anisotropy basis about the normal, radians
  TextureRef anisotropyTexture;              // linear; red = U, green = V (per pixel, replaces the values)
  TextureRef anisotropyRotationTexture;      // linear; red × 2π = rotation in radians (replaces the value)

  // Transmission colour, linear, [0,1]: fraction of light passing through (after the energy rule).
  Rgb transmissionColor{0.0f};
  TextureRef transmissionTexture;  // linear; multiplies transmissionColor
  // Transmission glossiness, [0,1]: 0 = clear (sharp refraction), 1 = the widest cone (frosted). Default 0.
  float transmissionGlossiness = 0.0f;

  // Metalness per texel (glTF's metallicRoughnessTexture, blue channel): with metalnessTexture, each point is
  // the mix, by m = metalnessFactor × the texture's first channel (linear), of this material (weight 1 − m) and
  // a metal whose uniform reflection is the base colour c = diffuseColor × diffuseTexture × COLOR_0 (weight m).
  // Both reflections are Schlick-shaped, R(θ) = R0 + (R90 − R0)(1 − cos θ)⁵, so the mix is one too:
  // R0 = (1 − m) R0' + m c, R90 = (1 − m) R90' + m c (R0' = reflectionColor × F0(ior), R90' = reflectionColor
  // for Fresnel reflection; both reflectionColor for uniform), with diffuse (1 − m) × diffuse and transmission
  // (1 − m) × transmission, and then the energy rule. Without metalnessTexture, metalnessFactor is unused.
  TextureRef metalnessTexture;
  float metalnessFactor = 1.0f;  // [0,1]

  // Absorption inside a transmissive medium (Beer–Lambert, as glTF KHR_materials_volume): white light that has
  // travelled `scatteringDistanceM` metres inside has the colour `scatteringColor`. Distance in metres, (0, ∞];
  // ∞ (default) = no absorption. Colour linear, (0,1].
  Rgb scatteringColor{1.0f};
  float scatteringDistanceM = std::numeric_limits<float>::infinity();

  // Reflection fog: reflected objects fade to `reflectionFogColor` (linear radiance factor, [0,1]) as their
  // distance approaches `reflectionFogDistanceM` metres, (0, ∞]; ∞ (default) = no fog.
  float reflectionFogDistanceM = std::numeric_limits<float>::infinity();
  Rgb reflectionFogColor{0.0f};

  // Bump map: a tangent-space normal map (glTF normalTexture convention, linear) and its strength, [0, ∞),
  // default 1 (the map as authored).
  TextureRef bumpTexture;
  float bumpScale = 1.0f;

  // Both faces are shaded and, for emitters, emit (glTF doubleSided). Every surface blocks light from both
  // sides regardless.
  bool doubleSided = false;

  // Emitted luminance, cd/m², linear Rec.709 (glTF emissiveFactor × KHR_materials_emissive_strength),
  // each channel in [0, ∞). Default 0.
  Rgb emissionLuminance{0.0f};
  TextureRef emissionTexture;  // sRGB-encoded; multiplies emissionLuminance
  // glTF emission without KHR_materials_emissive_strength (a label, a logo, a screen): emissionLuminance then
  // holds a display colour in [0, 1], not cd/m². The GL engine shows it as that fraction of the exposure's
  // white, Lmax = 1.2 · 2^EV100 cd/m² (base/tone_map.h), at any exposure, as glTF viewers show emission; the
  // baker takes no light from it. With the extension, emission is physical (cd/m²) and lights the scene.
  bool emissionDisplay = false;

  // A measured or fitted BRDF that replaces the analytic reflection (diffuse, reflection, glossiness, Fresnel)
  // where an engine supports it — elsewhere the analytic parameters above stand in for it: a MERL table
  // (sdb/measured_brdf.h) read once from measuredBrdfPath, or the compact car-paint model
  // (sdb/car_paint_brdf.h). At most one of the two.
  std::string measuredBrdfPath;                      // "" = none
  std::shared_ptr<const MeasuredBrdf> measuredBrdf;  // the table of measuredBrdfPath
  std::optional<CarPaintBrdf> carPaint;

  // The reflect input of the energy rule for light arriving at angle θ from the normal: with Fresnel
  // reflection the amount is reflectionColor × F(θ) (the realistic material: "the reflection amount is still
  // post-multiplied by the user-given reflection color"), with uniform reflection reflectionColor. So a white
  // Fresnel reflection (glass, plastic, paint) takes F0 ≈ 4 % at normal incidence, not all of the energy.
  Rgb reflectionAt(float cosTheta) const;
  // The energy rule applied to the constant colours at angle θ, and at normal incidence (cos θ = 1), the value
  // summaries and the engines' diffuse albedo use.
  EffectiveComponents effectiveAt(float cosTheta) const {
    return applyEnergyRule(diffuseColor, reflectionAt(cosTheta), transmissionColor);
  }
  EffectiveComponents effective() const { return effectiveAt(1.0f); }
  // Clear glass's transmittance for light crossing at θ from the normal, from either face
  // (base/clear_pane.h): a pane of two Fresnel faces of index ior with absorption inside and the light's
  // internal reflections, whose transmittance at normal incidence is the energy rule's,
  // effective().transmission, per channel; at other angles the slab's (exact Fresnel reflectance, the longer
  // path inside), never above the rule's effectiveAt(cos θ).transmission. With uniform reflection,
  // effective().transmission at every angle. What the pane reflects stays reflectionAt(cos θ), one face's.
  Rgb clearTransmittanceAt(float cosTheta) const;
  // A light source: emission in cd/m² (not a display colour).
  bool isEmissive() const { return !emissionDisplay && maxComponent(emissionLuminance) > 0.0f; }
  bool isTransmissive() const { return maxComponent(effective().transmission) > 0.0f || bool(transmissionTexture); }
  // Clear glass: transmission through a delta lobe (transmission glossiness² below kSmoothAlpha), which both
  // engines treat as a thin-walled pane that light passes straight through, with clearTransmittanceAt(cos θ)
  // at the angle it crosses.
  bool hasClearTransmission() const {
    return maxComponent(effective().transmission) > 0.0f && transmissionGlossiness * transmissionGlossiness < kSmoothAlpha;
  }
  bool isAnisotropic() const { return anisotropyU != anisotropyV || bool(anisotropyTexture); }
  bool isMeasured() const { return measuredBrdf != nullptr || carPaint.has_value(); }
  // Some light may pass where the surface is not covered (alpha mask or blend).
  bool hasAlpha() const { return alphaMode != AlphaMode::kOpaque; }
  // A mirror-like reflector: strong reflection at normal incidence (luminance ≥ 0.5) and a narrow lobe
  // (glossiness ≤ 0.2), the kind that needs a reflection pass rather than a light-map term.
  bool isMirrorLike() const;
  // Whether the OpenGL engine shows a planar reflection on a flat mesh of this material (engineReflection).
  bool showsPlanarReflection() const {
    return engineReflection == EngineReflection::kPlanar || (engineReflection == EngineReflection::kAuto && isMirrorLike());
  }
  // Whether it shows a cube-map reflection on a mesh of this material that is flat (`flatMesh`) or not.
  bool showsCubeMapReflection(bool flatMesh) const {
    return engineReflection == EngineReflection::kCubemap ||
           (engineReflection == EngineReflection::kAuto && isMirrorLike() && !flatMesh);
  }
};

// Coarse class of a material for summaries (`fly info`): the preset's class if it has one, otherwise derived
// from its parameters: "emitter", "measured", "glass", "metal", "glossy", "matte".
std::string materialClass(const Material& m);

// Checks each parameter's range; returns "" when valid, otherwise a sentence naming the first bad parameter,
// its value and its allowed range.
std::string validate(const Material& m);

}  // namespace fly::sdb
