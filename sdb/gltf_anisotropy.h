// glTF's KHR_materials_anisotropy converted into the realistic material's anisotropy (material.h) at import.
//
// KHR_materials_anisotropy (Khronos, ratified 2023; "Anisotropy") stretches the base's GGX lobe along a
// direction d in the tangent plane: with α = roughness² and strength s ∈ [0, 1], the width along d is
// α_d = mix(α, 1, s²) = α + (1 − α) s² and across d it stays α. d is the tangent turned counter-clockwise
// (towards the bitangent w · n × t) by anisotropyRotation; anisotropyTexture turns it further by each texel's
// direction (red, green mapped from [0, 1] to [−1, 1]) and multiplies s by its blue channel.
//
// fly's lobe has the widths base/ggx.h's ggxAnisotropicAlphas(glossiness², U, V) gives: α_f / a along U and
// α_f · a along V, a = √(1 − 0.9 |U − V|), α_f = glossiness². Their product is always α_f² and their ratio
// at most 1 / (1 − 0.9) = 10. Solving for glTF's widths:
//   glossiness = (α_d α)^(1/4),  U = (1 − α / α_d) / 0.9,  V = 0,  rotation = the angle of d,
// which is exact wherever α_d ≤ 10 α. Beyond that (a smooth surface stretched strongly: roughness 0.1 above
// strength 0.30, roughness 0.3 above strength 0.94, roughness above √0.1 = 0.32 never) the ratio is held at
// 10 and α_d kept: the lobe is as long as glTF's along d and α_d / 10 wide across it instead of α.
#pragma once

#include <cstddef>
#include <optional>

#include "base/math.h"
#include "sdb/texture.h"

namespace fly::sdb {

// Largest ratio of the widths of fly's lobe: 1 / (1 − 0.9) at |U − V| = 1 (base/ggx.h).
inline constexpr float kMaxAnisotropicWidthRatio = 10.0f;

// The GGX widths KHR_materials_anisotropy gives a lobe of perceptual roughness `roughness` and strength
// `strength` (both in [0, 1]): x = α_d along the anisotropy direction, y = α across it.
vec2 gltfAnisotropicAlphas(float roughness, float strength);

// fly's lobe parameters (Material::reflectionGlossiness, anisotropyU, anisotropyV) whose widths
// ggxAnisotropicAlphas(glossiness², U, V) are `alphaAlong` along U and `alphaAcross` along V, for
// 0 ≤ alphaAcross ≤ alphaAlong ≤ 1; exact where alphaAlong ≤ 10 alphaAcross, else alphaAlong along U and
// alphaAlong / 10 along V (`clamped`).
struct AnisotropicLobe {
  float glossiness = 0.0f;   // [0, 1]
  float anisotropyU = 0.0f;  // [0, 1]
  float anisotropyV = 0.0f;  // 0: U is the wide axis
  bool clamped = false;      // the ratio of the widths was more than 10
};
AnisotropicLobe anisotropicLobe(float alphaAlong, float alphaAcross);

// A material's KHR_materials_anisotropy with the inputs it depends on, as decoded by the importer.
struct GltfAnisotropyInput {
  float roughness = 1.0f;  // pbrMetallicRoughness.roughnessFactor, [0, 1]
  // metallicRoughnessTexture's decoded image (RGBA, 8 or 16 bits; roughness in green), null when the
  // material has none. Where an anisotropy texture is given too, it must lie on the same UV mapping; it is
  // sampled bilinearly, with these wrap modes, at the anisotropy texture's texel centres.
  const Texture* roughnessTexture = nullptr;
  WrapMode roughnessWrapS = WrapMode::kRepeat;
  WrapMode roughnessWrapT = WrapMode::kRepeat;
  float strength = 0.0f;     // anisotropyStrength, [0, 1]
  float rotationRad = 0.0f;  // anisotropyRotation, radians, counter-clockwise from the tangent; finite
  // anisotropyTexture's decoded image (RGBA, 8 or 16 bits, linear), null when the material has none.
  const Texture* anisotropyTexture = nullptr;
};

// fly's anisotropy for a GltfAnisotropyInput. A parameter that is the same at every texel is a constant;
// one that varies is an 8-bit texture on the grid of the anisotropy texture (else of the roughness texture),
// to be sampled as that texture is. Texels of strength 0 are isotropic; their rotation does not matter.
struct GltfAnisotropyConversion {
  bool anisotropic = false;  // some texel's widths differ; otherwise the material stays as it was
  float glossiness = 0.0f;   // Material::reflectionGlossiness (the largest value where there is a texture)
  float anisotropyU = 0.0f;
  float anisotropyV = 0.0f;
  float rotationRad = 0.0f;
  // One channel: red × glossiness = the glossiness (replaces the roughness texture).
  std::optional<Texture> glossinessTexture;
  // Three channels: red = U, green = V (0), blue 0 (Material::anisotropyTexture).
  std::optional<Texture> anisotropyTexture;
  // One channel: red × 2π = the rotation (Material::anisotropyRotationTexture). An angle stored in [0, 2π)
  // must jump somewhere (from red 1 to 0), and bilinear filtering across a jump turns the lobe wrongly. The
  // lobe repeats every half turn, so of three encodings the one with the fewest jumps between neighbouring
  // texels is kept: the angle modulo π within the half turn whose start no texel points along (no jump for
  // directions spread over less than a half turn), or the direction's own angle, as it is or turned by π
  // (one jump along a radius for a disc's directions, which turn a full circle).
  std::optional<Texture> rotationTexture;
  size_t texels = 1;         // points converted: the grid's texels, or 1 without textures
  size_t clampedTexels = 0;  // of which the widths' ratio was held at 10 (AnisotropicLobe::clamped)
};
GltfAnisotropyConversion convertGltfAnisotropy(const GltfAnisotropyInput& in);

}  // namespace fly::sdb
