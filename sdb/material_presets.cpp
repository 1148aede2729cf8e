#include "sdb/material_presets.h"

#include <array>

#include "sdb/material_layers.h"

namespace fly::sdb {

// Values: diffuse reflectances are linear Rec.709 albedos of typical samples; metal reflectances are the
// normal-incidence reflectances (F0) of pure metals as tabulated for physically based rendering (Filament's
// material guide, "Metallic" table: aluminium (0.913, 0.922, 0.924), iron (0.562, 0.565, 0.578)); indices of
// refraction from standard tables (soda-lime glass 1.52, polymers 1.46–1.59, lacquer 1.5); building-material
// albedos from the ranges in CIBSE Lighting Guide LG11 ("Surface reflectance and colour") and IES RP-5:
// concrete 0.35–0.5, white marble 0.7–0.85, light wood 0.35–0.5, dark polished wood 0.15–0.3. Glossiness is
// glTF's perceptual roughness (material.h) chosen to match the look of each class.
namespace {

Material base(std::string_view name) {
  Material m;
  m.name = std::string(name);
  m.preset = std::string(name);
  m.reflectionModel = ReflectionModel::kFresnel;
  m.reflectionColor = Rgb(1.0f);  // white Fresnel reflection: a dielectric with F0 from the IOR
  return m;
}

Material dielectric(std::string_view name, Rgb diffuse, float ior, float glossiness) {
  Material m = base(name);
  m.diffuseColor = diffuse;
  m.ior = ior;
  m.reflectionGlossiness = glossiness;
  return m;
}

Material metal(std::string_view name, Rgb f0, float glossiness) {
  Material m = base(name);
  m.reflectionModel = ReflectionModel::kUniform;  // metals: the coloured reflectance at every angle
  m.reflectionColor = f0;
  m.diffuseColor = Rgb(0.0f);
  m.reflectionGlossiness = glossiness;
  return m;
}

Material brushed(Material m) {
  // Brushing streaks widen the highlight across the brushing direction (U along the tangent).
  m.anisotropyU = 0.6f;
  m.anisotropyV = 0.1f;
  return m;
}

// A base under a clear lacquer (ior 1.5) covering the whole surface (material_layers.h): the lacquer is the
// reflection lobe; a metallic base's reflectance becomes part of the diffuse colour. Car paints have a
// mirror-smooth coat (glossiness 0.03), moulded coated plastic a slightly softer one (0.05).
Material lacquered(const Material& base, float coatGlossiness = 0.03f) {
  return applyClearCoat(base, ClearCoat{1.0f, coatGlossiness}).material;
}

// A lacquered paint whose engines' full BRDF is the car-paint model (car_paint_brdf.h): `paint` for the
// engines that evaluate it, the lacquered analytic material for the others.
Material withCarPaint(Material analytic, const CarPaintBrdf& paint) {
  analytic.carPaint = paint;
  return analytic;
}

// Silver metallic: aluminium flakes (F0 ≈ 0.9 of aluminium, half covered by binder: 0.45) in a grey binder
// of albedo 0.1, under a factory clear coat (η 1.5, GGX α 0.01). Pearl white: a white base (0.8) whose
// interference pigments reflect a narrow warm lobe and a wide cool one, so the tint shifts from gold at the
// highlight to blue-grey away from it (the "flop" of pearlescent paints).
CarPaintBrdf silverMetallicPaint() {
  CarPaintBrdf p;
  p.baseAlbedo = Rgb(0.1f);
  p.lobes[0] = {Rgb(0.45f, 0.46f, 0.48f), 0.2f};
  p.lobes[1] = {Rgb(0.1f), 0.5f};
  p.coatIor = 1.5f;
  p.coatAlpha = 0.01f;
  return p;
}
CarPaintBrdf pearlWhitePaint() {
  CarPaintBrdf p;
  p.baseAlbedo = Rgb(0.8f, 0.78f, 0.74f);
  p.lobes[0] = {Rgb(0.3f, 0.25f, 0.12f), 0.12f};
  p.lobes[1] = {Rgb(0.05f, 0.08f, 0.14f), 0.45f};
  p.coatIor = 1.5f;
  p.coatAlpha = 0.01f;
  return p;
}

Material glass(std::string_view name, float transmissionGlossiness) {
  Material m = base(name);
  m.diffuseColor = Rgb(0.0f);
  m.transmissionColor = Rgb(1.0f);
  m.ior = 1.52f;
  m.reflectionGlossiness = transmissionGlossiness;
  m.transmissionGlossiness = transmissionGlossiness;
  m.doubleSided = true;  // panes are thin sheets seen and lit from both sides
  return m;
}

const std::array<MaterialPreset, 16>& table() {
  static const std::array<MaterialPreset, 16> presets = {{
      {"matte-plastic", "plastic", "grey moulded polymer, IOR 1.46, rough surface",
       dielectric("matte-plastic", Rgb(0.5f), 1.46f, 0.6f)},
      {"shiny-plastic", "plastic", "grey injection-moulded polymer, IOR 1.5, smooth",
       dielectric("shiny-plastic", Rgb(0.5f), 1.5f, 0.15f)},
      {"coated-plastic", "plastic", "plastic under a clear lacquer, IOR 1.5, a sharp coat highlight",
       lacquered(dielectric("coated-plastic", Rgb(0.5f), 1.5f, 0.15f), 0.05f)},
      {"brushed-metal", "metal", "brushed aluminium, F0 (0.913, 0.922, 0.924), anisotropic",
       brushed(metal("brushed-metal", Rgb(0.913f, 0.922f, 0.924f), 0.35f))},
      {"polished-metal", "metal", "polished steel (iron F0 (0.562, 0.565, 0.578)), near mirror",
       metal("polished-metal", Rgb(0.562f, 0.565f, 0.578f), 0.05f)},
      {"car-paint", "car-paint", "solid red paint under a clear coat (ior 1.5, glossiness 0.03)",
       lacquered(dielectric("car-paint", Rgb(0.5f, 0.03f, 0.03f), 1.5f, 0.4f))},
      {"metallic-car-paint", "car-paint",
       "silver metallic paint: aluminium flakes (two GGX lobes, reflectance 0.45–0.48 and 0.1) in a grey "
       "binder under a clear coat (car-paint BRDF); where an engine lacks it, the flakes' reflection is "
       "taken as diffuse",
       withCarPaint(lacquered(metal("metallic-car-paint", Rgb(0.45f, 0.46f, 0.48f), 0.45f)), silverMetallicPaint())},
      {"pearl-car-paint", "car-paint",
       "pearl white paint under a clear coat: a warm narrow and a cool wide pigment lobe (car-paint BRDF)",
       withCarPaint(lacquered(dielectric("pearl-car-paint", Rgb(0.8f, 0.78f, 0.74f), 1.5f, 0.4f)), pearlWhitePaint())},
      {"concrete", "stone", "grey cast concrete, albedo 0.45",
       dielectric("concrete", Rgb(0.45f), 1.5f, 0.9f)},
      {"marble", "stone", "polished white marble, albedo 0.75",
       dielectric("marble", Rgb(0.75f, 0.74f, 0.72f), 1.49f, 0.2f)},
      {"tiles", "stone", "glazed ceramic tiles, albedo 0.6",
       dielectric("tiles", Rgb(0.6f, 0.58f, 0.55f), 1.5f, 0.1f)},
      {"raw-wood", "wood", "unfinished light timber (pine), albedo ≈ 0.4",
       dielectric("raw-wood", Rgb(0.5f, 0.36f, 0.22f), 1.5f, 0.8f)},
      {"polished-wood", "wood", "lacquered dark hardwood (walnut), albedo ≈ 0.2",
       dielectric("polished-wood", Rgb(0.3f, 0.17f, 0.09f), 1.5f, 0.15f)},
      {"clear-glass", "glass", "clear soda-lime float glass, IOR 1.52", glass("clear-glass", 0.0f)},
      {"frosted-glass", "glass", "acid-etched glass, IOR 1.52, wide transmission cone",
       glass("frosted-glass", 0.6f)},
      {"fabric", "fabric", "woven textile, albedo 0.5, a faint broad sheen",
       dielectric("fabric", Rgb(0.5f), 1.5f, 1.0f)},
  }};
  return presets;
}

}  // namespace

std::span<const MaterialPreset> materialPresets() { return table(); }

const MaterialPreset* findMaterialPreset(std::string_view name) {
  for (const MaterialPreset& p : table()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

}  // namespace fly::sdb
