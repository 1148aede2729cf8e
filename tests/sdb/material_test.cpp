#include "sdb/material.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "sdb/material_presets.h"

namespace fly::sdb {
namespace {

void expectNear(const Rgb& a, const Rgb& b, float tol = 1e-6f) {
  EXPECT_NEAR(a.r, b.r, tol);
  EXPECT_NEAR(a.g, b.g, tol);
  EXPECT_NEAR(a.b, b.b, tol);
}

TEST(MaterialEnergyRule, FollowsReferenceFormulaPerChannel) {
  // reflect' = reflect; transmission' = (1 − reflect')·transmission; diffuse' = (1 − reflect' − transmission')·diffuse
  const EffectiveComponents e = applyEnergyRule(Rgb(0.8f, 0.5f, 0.2f), Rgb(0.2f, 0.1f, 0.0f), Rgb(0.5f, 1.0f, 0.0f));
  expectNear(e.reflection, Rgb(0.2f, 0.1f, 0.0f));
  expectNear(e.transmission, Rgb(0.4f, 0.9f, 0.0f));
  expectNear(e.diffuse, Rgb(0.8f * 0.4f, 0.5f * 0.0f, 0.2f * 1.0f));
}

TEST(MaterialEnergyRule, WhiteReflectionIsOpaqueAndReflective) {
  const EffectiveComponents e = applyEnergyRule(Rgb(1.0f), Rgb(1.0f), Rgb(1.0f));
  expectNear(e.reflection, Rgb(1.0f));
  expectNear(e.transmission, Rgb(0.0f));
  expectNear(e.diffuse, Rgb(0.0f));
}

TEST(MaterialEnergyRule, SumNeverExceedsOneEvenForOutOfRangeInputs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.5f, 1.5f);
  for (int i = 0; i < 20000; ++i) {
    const EffectiveComponents e = applyEnergyRule(Rgb(u(rng), u(rng), u(rng)), Rgb(u(rng), u(rng), u(rng)),
                                                  Rgb(u(rng), u(rng), u(rng)));
    const Rgb sum = e.diffuse + e.reflection + e.transmission;
    for (int c = 0; c < 3; ++c) {
      ASSERT_LE(sum[c], 1.0f + 1e-6f);
      ASSERT_GE(e.diffuse[c], 0.0f);
      ASSERT_GE(e.reflection[c], 0.0f);
      ASSERT_GE(e.transmission[c], 0.0f);
    }
  }
}

TEST(MaterialFresnel, SchlickMatchesClosedFormValues) {
  EXPECT_NEAR(fresnelF0(1.5f), 0.04f, 1e-6f);           // ((1.5 − 1)/(1.5 + 1))² = 0.04
  EXPECT_NEAR(fresnelF0(1.0f), 0.0f, 1e-7f);
  EXPECT_NEAR(schlickFresnel(1.0f, 0.04f), 0.04f, 1e-7f);
  EXPECT_NEAR(schlickFresnel(0.0f, 0.04f), 1.0f, 1e-7f);  // grazing
  EXPECT_NEAR(schlickFresnel(0.5f, 0.04f), 0.04f + 0.96f * 0.03125f, 1e-7f);  // (1 − 0.5)⁵ = 1/32
}

TEST(MaterialFresnel, WhiteFresnelReflectionKeepsMostOfTheDiffuse) {
  Material m;
  m.diffuseColor = Rgb(0.5f);
  m.reflectionColor = Rgb(1.0f);
  m.ior = 1.5f;
  expectNear(m.effective().reflection, Rgb(0.04f));
  expectNear(m.effective().diffuse, Rgb(0.5f * 0.96f));
  // At grazing incidence Fresnel reflection takes everything.
  expectNear(m.effectiveAt(0.0f).diffuse, Rgb(0.0f));
  m.reflectionModel = ReflectionModel::kUniform;
  expectNear(m.effective().diffuse, Rgb(0.0f));
}

// Clear glass transmits the energy rule's transmittance at normal incidence (scenes' glass head-on is as the
// rule has it) and, at other angles, a pane of two Fresnel faces (base/clear_pane.h), below the rule's one
// face; with uniform reflection the rule's value at every angle. Sum with what it reflects and its diffuse
// share at most 1 at every angle, for every preset and random glass.
TEST(MaterialClearGlass, NormalIncidenceIsTheEnergyRulesAndObliqueIsTheSlabs) {
  Material glass = findMaterialPreset("clear-glass")->material;
  glass.transmissionColor = Rgb(0.9f, 0.8f, 0.7f);
  ASSERT_TRUE(glass.hasClearTransmission());
  expectNear(glass.clearTransmittanceAt(1.0f), glass.effective().transmission);
  expectNear(glass.clearTransmittanceAt(-1.0f), glass.effective().transmission);
  for (const float c : {0.8f, 0.5f, 0.2f}) {
    const Rgb t = glass.clearTransmittanceAt(c);
    for (int ch = 0; ch < 3; ++ch) EXPECT_LT(t[ch], glass.effectiveAt(c).transmission[ch]) << c << " " << ch;
  }
  glass.reflectionModel = ReflectionModel::kUniform;
  glass.reflectionColor = Rgb(0.1f);
  for (const float c : {1.0f, 0.5f, 0.0f})
    expectNear(glass.clearTransmittanceAt(c), glass.effective().transmission);

  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    Material m;
    m.diffuseColor = Rgb(u(rng), u(rng), u(rng));
    m.reflectionColor = Rgb(u(rng), u(rng), u(rng));
    m.transmissionColor = Rgb(u(rng), u(rng), u(rng));
    m.ior = 1.0f + 3.0f * u(rng);
    m.transmissionGlossiness = 0.0f;
    for (const float c : {1.0f, 0.7f, 0.3f, 0.05f, 0.0f}) {
      const EffectiveComponents e = m.effectiveAt(c);
      const Rgb t = m.clearTransmittanceAt(c);
      const Rgb sum = e.reflection + t + e.diffuse;
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_TRUE(std::isfinite(t[ch]));
        ASSERT_GE(t[ch], 0.0f);
        ASSERT_LE(t[ch], e.transmission[ch] + 1e-6f) << "ior " << m.ior << ", cos θ " << c;
        ASSERT_LE(sum[ch], 1.0f + 1e-6f);
      }
    }
  }
}

TEST(MaterialValidate, NamesTheParameterOutOfRange) {
  Material m;
  EXPECT_EQ(validate(m), "");
  m.ior = 0.5f;
  EXPECT_NE(validate(m).find("ior = 0.5 is outside [1, 4]"), std::string::npos);
  m = Material();
  m.diffuseColor = Rgb(1.2f, 0.0f, 0.0f);
  EXPECT_NE(validate(m).find("diffuseColor"), std::string::npos);
  m = Material();
  m.reflectionGlossiness = std::nanf("");
  EXPECT_NE(validate(m).find("reflectionGlossiness"), std::string::npos);
  m = Material();
  m.emissionLuminance = Rgb(std::numeric_limits<float>::infinity());
  EXPECT_NE(validate(m).find("emissionLuminance"), std::string::npos);
}

TEST(MaterialPresets, AllClassesArePresentValidAndDistinct) {
  const std::set<std::string> expected = {
      "matte-plastic", "shiny-plastic", "coated-plastic", "brushed-metal", "polished-metal", "car-paint",
      "metallic-car-paint", "pearl-car-paint", "concrete", "marble", "tiles", "raw-wood", "polished-wood",
      "clear-glass", "frosted-glass", "fabric"};
  std::set<std::string> names;
  for (const MaterialPreset& p : materialPresets()) {
    names.insert(std::string(p.name));
    EXPECT_EQ(validate(p.material), "") << p.name;
    EXPECT_EQ(p.material.preset, p.name);
    EXPECT_EQ(materialClass(p.material), p.materialClass) << p.name;
    EXPECT_FALSE(p.description.empty()) << p.name;
    const EffectiveComponents e = p.material.effective();
    EXPECT_LE(maxComponent(e.diffuse + e.reflection + e.transmission), 1.0f + 1e-6f) << p.name;
  }
  EXPECT_EQ(names, expected);
  EXPECT_EQ(findMaterialPreset("no-such"), nullptr);
}

TEST(MaterialPresets, PhysicalPropertiesOfKeyPresets) {
  // Clear glass: F0 = ((1.52 − 1)/(1.52 + 1))² ≈ 0.0426, the rest transmitted, nothing diffuse.
  const Material& glass = findMaterialPreset("clear-glass")->material;
  EXPECT_NEAR(glass.effective().reflection.g, 0.04258f, 1e-4f);
  EXPECT_NEAR(glass.effective().transmission.g, 1.0f - 0.04258f, 1e-4f);
  EXPECT_EQ(glass.effective().diffuse, Rgb(0.0f));
  EXPECT_TRUE(glass.isTransmissive());
  EXPECT_TRUE(glass.doubleSided);
  // Polished metal: uniform coloured reflection, mirror-like, not transmissive.
  const Material& steel = findMaterialPreset("polished-metal")->material;
  EXPECT_EQ(steel.reflectionModel, ReflectionModel::kUniform);
  EXPECT_TRUE(steel.isMirrorLike());
  EXPECT_FALSE(steel.isTransmissive());
  // Brushed metal is anisotropic; frosted glass scatters its transmission.
  EXPECT_TRUE(findMaterialPreset("brushed-metal")->material.isAnisotropic());
  EXPECT_GT(findMaterialPreset("frosted-glass")->material.transmissionGlossiness, 0.3f);
  // Concrete's diffuse albedo stays in the published 0.35–0.5 range after the energy rule.
  const float concrete = luminance(findMaterialPreset("concrete")->material.effective().diffuse);
  EXPECT_GT(concrete, 0.35f);
  EXPECT_LT(concrete, 0.5f);
}

TEST(MaterialClass, DerivedFromParametersWithoutPreset) {
  Material m;
  m.reflectionGlossiness = 0.8f;
  EXPECT_EQ(materialClass(m), "matte");
  m.reflectionColor = Rgb(1.0f);
  m.reflectionGlossiness = 0.1f;
  EXPECT_EQ(materialClass(m), "glossy");
  m.reflectionModel = ReflectionModel::kUniform;
  m.reflectionColor = Rgb(0.9f);
  EXPECT_EQ(materialClass(m), "metal");
  m = Material();
  m.transmissionColor = Rgb(1.0f);
  EXPECT_EQ(materialClass(m), "glass");
  m.emissionLuminance = Rgb(100.0f);
  EXPECT_EQ(materialClass(m), "emitter");
}

}  // namespace
}  // namespace fly::sdb
