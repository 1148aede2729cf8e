// Layers that glTF stacks on its base material (KHR_materials_clearcoat, KHR_materials_sheen), approximated
// by the realistic material (material.h), which has one Lambertian diffuse term and one reflection lobe. The
// material presets and the glTF importer use the same functions.
#pragma once

#include "sdb/material.h"

namespace fly::sdb {

// A clear coat: a smooth dielectric film over the base (KHR_materials_clearcoat; a car's lacquer).
inline constexpr float kClearCoatIor =
    1.5f;  // KHR_materials_clearcoat fixes the coat's ior at 1.5 (F0 = 0.04)

struct ClearCoat {
  float amount = 1.0f;      // [0,1], glTF clearcoatFactor: the fraction of the surface the coat covers
  float glossiness = 0.0f;  // [0,1], glTF clearcoatRoughness (perceptual roughness, GGX α = glossiness²)
};

struct CoatedMaterial {
  Material material;
  bool coatIsLobe = false;  // the reflection lobe is the coat's (its textures then belong to the coat)
};

// The coat as one Fresnel reflection lobe (ior 1.5) over `base`. The realistic material has a single lobe,
// so:
//  - Dielectric base (Fresnel reflection): the coat covers a fraction `amount` of the surface; there light
//    meets the coat's interface, and the base's own interface below it reflects ((n − 1.5)/(n + 1.5))² ≈ 0
//    for the usual n ≈ 1.5, so it is dropped. Uncovered, the base's interface reflects as before. The lobe's
//    normal-incidence reflectance is the sum, amount·F0(1.5) + (1 − amount)·reflectionColor·F0(ior); it takes
//    the glossiness (and, when the coat's share is the larger, the ior 1.5) of the larger share, and
//    reflectionColor = that sum / F0(lobe ior), clamped to 1.
//  - Metallic base (uniform reflection) under a coat that is sharper than the metal's lobe (car paint: metal
//    flakes under lacquer): the lobe becomes the coat (Fresnel, ior 1.5, colour = amount, the coat's
//    glossiness, isotropic), and the metal's coloured reflectance moves into the diffuse colour
//    (diffuse = min(diffuse + reflectionColor, 1)), i.e. the rough metal lobe is approximated by a Lambertian
//    one of the same albedo and colour; its directional peak and the flop of the colour with angle are lost.
//    The energy rule then scales that diffuse by (1 − amount·F(θ)), the light the coat lets through.
//  - Metallic base at least as sharp as the coat: the metal's lobe is kept and the coat is dropped (its
//    4 % highlight lies inside the metal's brighter, sharper one).
// amount = 0 leaves the base unchanged. Preconditions: amount and glossiness in [0,1].
CoatedMaterial applyClearCoat(const Material& base, const ClearCoat& coat);

// Sheen (KHR_materials_sheen): the Charlie microfibre lobe (Estevez and Kulla 2017, "Production Friendly
// Microfacet Sheen BRDF"; D(h) = (2 + 1/α)·sin(θh)^(1/α) / 2π, α = sheenRoughness², with Ashikhmin's
// visibility V = 1 / (4(n·l + n·v − (n·l)(n·v)))) that glTF adds to the base, scaling the base by
// (1 − max(sheenColor)·E) to conserve energy. Its cosine-weighted hemispherical albedo Ē (the fraction of
// uniform diffuse light it reflects), by numerical quadrature (0.037 at sheenRoughness 0.1, 0.17 at 0.5, 0.24
// at 1). Below 0.1 the lobe is too thin for the quadrature; there Ē is taken as Ē(0.1)·roughness/0.1, as it
// falls almost linearly to 0 (0.037, 0.075, 0.11 at 0.1, 0.2, 0.3). sheenRoughness is clamped to [0, 1].
float sheenAlbedo(float sheenRoughness);

// The sheen folded into the Lambertian diffuse term: diffuse' = diffuse·(1 − max(sheenColor)·Ē) +
// sheenColor·Ē, clamped to [0,1]. Its angular shape (brighter at grazing angles) is lost; its share of the
// energy under uniform light and its colour are kept. Precondition: sheenColor in [0,1] per channel.
Material applySheen(const Material& base, const Rgb& sheenColor, float sheenRoughness);

}  // namespace fly::sdb
