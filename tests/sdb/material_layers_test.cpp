#include "sdb/material_layers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sdb/material_presets.h"

namespace fly::sdb {
namespace {

Material dielectric(Rgb diffuse, float ior, float glossiness) {
  Material m;
  m.diffuseColor = diffuse;
  m.reflectionModel = ReflectionModel::kFresnel;
  m.reflectionColor = Rgb(1.0f);
  m.ior = ior;
  m.reflectionGlossiness = glossiness;
  return m;
}

Material metal(Rgb f0, float glossiness) {
  Material m;
  m.diffuseColor = Rgb(0.0f);
  m.reflectionModel = ReflectionModel::kUniform;
  m.reflectionColor = f0;
  m.reflectionGlossiness = glossiness;
  return m;
}

// The glTF reference at angle θ (KHR_materials_clearcoat: coated = mix(base, coat, amount · F_coat(θ))), its
// directional albedo with each lobe's albedo taken as its Fresnel reflectance and the diffuse lobe's as its
// colour: amount·F_c + (1 − amount·F_c) · base albedo, where the base albedo of a dielectric is
// F_b + (1 − F_b)·diffuse and of a metal its reflectance.
float gltfCoatedAlbedo(const Material& base, float amount, float cosTheta, int channel) {
  const float fc = amount * schlickFresnel(cosTheta, fresnelF0(kClearCoatIor));
  float baseAlbedo = 0.0f;
  if (base.reflectionModel == ReflectionModel::kUniform) {
    baseAlbedo = base.reflectionColor[channel] + base.diffuseColor[channel];
  } else {
    const float fb = base.reflectionColor[channel] * schlickFresnel(cosTheta, fresnelF0(base.ior));
    baseAlbedo = fb + (1.0f - fb) * base.diffuseColor[channel];
  }
  return fc + (1.0f - fc) * baseAlbedo;
}

float flyAlbedo(const Material& m, float cosTheta, int channel) {
  const EffectiveComponents e = m.effectiveAt(cosTheta);
  return e.diffuse[channel] + e.reflection[channel] + e.transmission[channel];
}

TEST(ClearCoat, FullCoatOverADielectricBecomesTheReflectionLobe) {
  const Material base = dielectric(Rgb(0.6f, 0.05f, 0.05f), 1.5f, 0.6f);
  const CoatedMaterial c = applyClearCoat(base, {1.0f, 0.1f});
  EXPECT_TRUE(c.coatIsLobe);
  EXPECT_EQ(c.material.reflectionModel, ReflectionModel::kFresnel);
  EXPECT_FLOAT_EQ(c.material.ior, 1.5f);
  EXPECT_FLOAT_EQ(c.material.reflectionGlossiness, 0.1f);
  // amount · F0(1.5) / F0(1.5) = 1: the coat's whole Fresnel reflection.
  EXPECT_FLOAT_EQ(c.material.reflectionColor.r, 1.0f);
  EXPECT_EQ(c.material.diffuseColor, base.diffuseColor);
}

TEST(ClearCoat, PartialCoatSumsTheCoveredAndUncoveredReflectances) {
  // Base ior 2 (F0 = 1/9), 20 % coat: covered 0.2·0.04 = 0.008 < uncovered 0.8/9 = 0.0889, so the lobe keeps
  // the base's ior and glossiness, and reflectionColor = (0.008 + 0.0889) / (1/9) = 0.872.
  const Material base = dielectric(Rgb(0.5f), 2.0f, 0.4f);
  const CoatedMaterial c = applyClearCoat(base, {0.2f, 0.05f});
  EXPECT_FALSE(c.coatIsLobe);
  EXPECT_FLOAT_EQ(c.material.ior, 2.0f);
  EXPECT_FLOAT_EQ(c.material.reflectionGlossiness, 0.4f);
  EXPECT_NEAR(c.material.reflectionColor.g, (0.2f * 0.04f + 0.8f / 9.0f) * 9.0f, 1e-5f);
  // 60 % coat: covered 0.024 > uncovered 0.4/9 · 0.5 (reflectionColor 0.5) = 0.0222: the coat's lobe.
  Material halfSpecular = base;
  halfSpecular.reflectionColor = Rgb(0.5f);
  const CoatedMaterial d = applyClearCoat(halfSpecular, {0.6f, 0.05f});
  EXPECT_TRUE(d.coatIsLobe);
  EXPECT_FLOAT_EQ(d.material.ior, 1.5f);
  EXPECT_FLOAT_EQ(d.material.reflectionGlossiness, 0.05f);
  EXPECT_NEAR(d.material.reflectionColor.b, std::min(1.0f, (0.024f + 0.4f * 0.5f / 9.0f) / 0.04f), 1e-5f);
}

TEST(ClearCoat, CarPaintMovesTheMetalsReflectanceIntoTheDiffuse) {
  const Material base = metal(Rgb(0.9f, 0.5f, 0.2f), 0.5f);
  const CoatedMaterial c = applyClearCoat(base, {1.0f, 0.05f});
  EXPECT_TRUE(c.coatIsLobe);
  EXPECT_EQ(c.material.reflectionModel, ReflectionModel::kFresnel);
  EXPECT_FLOAT_EQ(c.material.reflectionColor.r, 1.0f);
  EXPECT_FLOAT_EQ(c.material.reflectionGlossiness, 0.05f);
  EXPECT_FLOAT_EQ(c.material.diffuseColor.r, 0.9f);
  EXPECT_FLOAT_EQ(c.material.diffuseColor.g, 0.5f);
  EXPECT_FLOAT_EQ(c.material.diffuseColor.b, 0.2f);
  // At normal incidence fly's albedo equals the glTF layering's: 0.04 + 0.96 · F0_metal.
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(flyAlbedo(c.material, 1.0f, ch), gltfCoatedAlbedo(base, 1.0f, 1.0f, ch), 1e-6f);
  }
}

TEST(ClearCoat, MetalSharperThanItsCoatKeepsItsLobe) {
  const Material base = metal(Rgb(0.95f), 0.05f);
  const CoatedMaterial c = applyClearCoat(base, {1.0f, 0.2f});
  EXPECT_FALSE(c.coatIsLobe);
  EXPECT_EQ(c.material.reflectionModel, ReflectionModel::kUniform);
  EXPECT_EQ(c.material.reflectionColor, base.reflectionColor);
  EXPECT_EQ(applyClearCoat(base, {0.0f, 0.0f}).material.reflectionColor, base.reflectionColor);
}

// Over a grid of bases and coats, every coated material is valid, its directional albedo is at most 1 at
// every angle, and it never exceeds the glTF layering's by more than the coat's own Fresnel rise that the
// single-lobe form cannot drop below: the approximation does not create energy.
TEST(ClearCoat, DirectionalAlbedoStaysWithinOneAndTheGltfReference) {
  int checked = 0;
  for (float amount : {0.0f, 0.1f, 0.5f, 0.9f, 1.0f}) {
    for (float coatGloss : {0.0f, 0.3f, 1.0f}) {
      for (float baseGloss : {0.0f, 0.5f, 1.0f}) {
        for (float ior : {1.0f, 1.33f, 1.5f, 2.5f, 4.0f}) {
          for (const Material& base :
               {dielectric(Rgb(0.9f, 0.5f, 0.0f), ior, baseGloss), dielectric(Rgb(1.0f), ior, baseGloss),
                metal(Rgb(1.0f, 0.7f, 0.3f), baseGloss)}) {
            const Material m = applyClearCoat(base, {amount, coatGloss}).material;
            ASSERT_EQ(validate(m), "") << "amount " << amount << " ior " << ior;
            for (int k = 0; k <= 20; ++k) {
              const float cosTheta = float(k) / 20.0f;
              for (int ch = 0; ch < 3; ++ch) {
                const float a = flyAlbedo(m, cosTheta, ch);
                EXPECT_LE(a, 1.0f + 1e-6f);
                EXPECT_GE(a, 0.0f);
                EXPECT_LE(
                    a, std::max(gltfCoatedAlbedo(base, amount, cosTheta, ch), m.reflectionAt(cosTheta)[ch]) +
                           1e-5f)
                    << "amount " << amount << " ior " << ior << " cos " << cosTheta;
                ++checked;
              }
            }
          }
        }
      }
    }
  }
  EXPECT_EQ(checked, 5 * 3 * 3 * 5 * 3 * 21 * 3);
}

TEST(ClearCoat, CarPaintPresetsAreCoated) {
  for (const char* name : {"car-paint", "metallic-car-paint", "pearl-car-paint"}) {
    const MaterialPreset* p = findMaterialPreset(name);
    ASSERT_NE(p, nullptr) << name;
    EXPECT_EQ(p->material.reflectionModel, ReflectionModel::kFresnel) << name;
    EXPECT_FLOAT_EQ(p->material.ior, kClearCoatIor) << name;
    EXPECT_FLOAT_EQ(p->material.reflectionGlossiness, 0.03f) << name;
    EXPECT_FLOAT_EQ(p->material.reflectionColor.r, 1.0f) << name;
  }
  // The metallic paint's flakes (reflectance 0.45–0.48) become its diffuse colour.
  const Material& metallic = findMaterialPreset("metallic-car-paint")->material;
  EXPECT_FLOAT_EQ(metallic.diffuseColor.r, 0.45f);
  EXPECT_FLOAT_EQ(metallic.diffuseColor.b, 0.48f);
}

// Charlie sheen (Estevez and Kulla 2017) with Ashikhmin's visibility, evaluated independently of the library.
double charlieBrdf(double roughness, const double l[3], const double v[3]) {
  const double alpha = roughness * roughness;
  double h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
  const double len = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  const double cosH = h[2] / len;
  const double sinH = std::sqrt(std::max(0.0, 1.0 - cosH * cosH));
  const double d = (2.0 + 1.0 / alpha) * std::pow(sinH, 1.0 / alpha) / (2.0 * kPi);
  const double vis = 1.0 / (4.0 * (l[2] + v[2] - l[2] * v[2]));
  return d * vis;
}

// Ē = (1/π) ∫∫ f cos θi cos θo dωi dωo, estimated with directions uniform on the hemisphere (pdf 1/2π each).
TEST(Sheen, AlbedoMatchesAMonteCarloEstimate) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto direction = [&](double out[3]) {
    const double z = u(rng), phi = 2.0 * kPi * u(rng), r = std::sqrt(1.0 - z * z);
    out[0] = r * std::cos(phi);
    out[1] = r * std::sin(phi);
    out[2] = z;
  };
  for (float roughness : {0.3f, 0.5f, 1.0f}) {
    const int n = 400000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
      double l[3], v[3];
      direction(l);
      direction(v);
      const double x = charlieBrdf(roughness, l, v) * l[2] * v[2] * (2.0 * kPi) * (2.0 * kPi) / kPi;
      sum += x;
      sum2 += x * x;
    }
    const double mean = sum / n;
    const double stderr = std::sqrt((sum2 / n - mean * mean) / n);
    EXPECT_NEAR(sheenAlbedo(roughness), mean, 4.0 * stderr + 2e-3 * mean) << "roughness " << roughness;
    EXPECT_GT(sheenAlbedo(roughness), 0.0f);
    EXPECT_LT(sheenAlbedo(roughness), 1.0f);
  }
  // Below 0.1 the albedo falls linearly to 0.
  EXPECT_NEAR(sheenAlbedo(0.05f), 0.5f * sheenAlbedo(0.1f), 1e-6f);
  EXPECT_EQ(sheenAlbedo(0.0f), 0.0f);
}

TEST(Sheen, FoldsIntoTheDiffuseWithinTheEnergyRule) {
  const Material base = dielectric(Rgb(0.2f, 0.4f, 0.8f), 1.5f, 0.8f);
  const Rgb sheen(1.0f, 0.33f, 0.1f);
  const float e = sheenAlbedo(0.8f);
  const Material m = applySheen(base, sheen, 0.8f);
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(m.diffuseColor[ch], base.diffuseColor[ch] * (1.0f - e) + sheen[ch] * e, 1e-6f);
  }
  // A white base under a white sheen stays at most white.
  const Material white = applySheen(dielectric(Rgb(1.0f), 1.5f, 0.5f), Rgb(1.0f), 1.0f);
  EXPECT_LE(maxComponent(white.diffuseColor), 1.0f);
  EXPECT_EQ(validate(white), "");
}

}  // namespace
}  // namespace fly::sdb
