#include "sdb/material.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "base/clear_pane.h"
#include "sdb/material_presets.h"

namespace fly::sdb {

EffectiveComponents applyEnergyRule(const Rgb& diffuse, const Rgb& reflection, const Rgb& transmission) {
  const Rgb r = glm::clamp(reflection, 0.0f, 1.0f);
  const Rgb t = (Rgb(1.0f) - r) * glm::clamp(transmission, 0.0f, 1.0f);
  // max(…, 0) only absorbs rounding: r + t ≤ 1 holds exactly in real arithmetic.
  const Rgb d = glm::max(Rgb(1.0f) - r - t, Rgb(0.0f)) * glm::clamp(diffuse, 0.0f, 1.0f);
  return {d, r, t};
}

float fresnelF0(float ior) {
  const float q = (ior - 1.0f) / (ior + 1.0f);
  return q * q;
}

float schlickFresnel(float cosTheta, float f0) {
  const float m = 1.0f - std::clamp(cosTheta, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (1.0f - f0) * m2 * m2 * m;
}

Rgb Material::reflectionAt(float cosTheta) const {
  if (reflectionModel == ReflectionModel::kUniform) return reflectionColor;
  return reflectionColor * schlickFresnel(cosTheta, fresnelF0(ior));
}

Rgb Material::clearTransmittanceAt(float cosTheta) const {
  const float f0 = reflectionModel == ReflectionModel::kFresnel ? fresnelF0(ior) : -1.0f;
  return ClearPane(f0, transmissionColor, reflectionColor).at(cosTheta);
}

bool Material::isMirrorLike() const {
  return luminance(effective().reflection) >= 0.5f && reflectionGlossiness <= 0.2f;
}

std::string materialClass(const Material& m) {
  if (const MaterialPreset* p = findMaterialPreset(m.preset)) return std::string(p->materialClass);
  if (m.isEmissive()) return "emitter";
  if (m.isMeasured()) return "measured";
  const EffectiveComponents e = m.effective();
  if (luminance(e.transmission) >= 0.1f || m.transmissionTexture) return "glass";
  if (m.reflectionModel == ReflectionModel::kUniform && luminance(e.reflection) >= 0.3f) return "metal";
  if (maxComponent(m.reflectionColor) > 0.0f && m.reflectionGlossiness <= 0.4f) return "glossy";
  return "matte";
}

namespace {

// Appends a problem for `name` unless `ok`; `range` is written as the allowed range.
class Checker {
 public:
  void check(bool ok, const char* name, const std::string& value, const char* range) {
    if (!ok && problem_.empty()) problem_ = std::string(name) + " = " + value + " is outside " + range;
  }
  void unit(const char* name, float v) { check(v >= 0.0f && v <= 1.0f, name, str(v), "[0, 1]"); }
  void unit(const char* name, const Rgb& c) {
    check(c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f && maxComponent(c) <= 1.0f, name, str(c), "[0, 1] per channel");
  }
  std::string problem() const { return problem_; }

  static std::string str(float v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  static std::string str(const Rgb& c) { return "(" + str(c.r) + ", " + str(c.g) + ", " + str(c.b) + ")"; }

 private:
  std::string problem_;
};

}  // namespace

std::string validate(const Material& m) {
  Checker c;
  // NaN fails every comparison below, so it is reported as out of range.
  c.unit("diffuseColor", m.diffuseColor);
  c.unit("reflectionColor", m.reflectionColor);
  c.unit("transmissionColor", m.transmissionColor);
  c.unit("opacity", m.opacity);
  c.unit("alphaCutoff", m.alphaCutoff);
  c.check(m.ior >= 1.0f && m.ior <= 4.0f, "ior", Checker::str(m.ior), "[1, 4]");
  c.unit("reflectionGlossiness", m.reflectionGlossiness);
  c.unit("anisotropyU", m.anisotropyU);
  c.unit("anisotropyV", m.anisotropyV);
  c.check(std::isfinite(m.anisotropyRotationRad), "anisotropyRotationRad", Checker::str(m.anisotropyRotationRad),
          "the finite numbers");
  c.unit("transmissionGlossiness", m.transmissionGlossiness);
  c.unit("metalnessFactor", m.metalnessFactor);
  c.check(m.scatteringColor.r > 0.0f && m.scatteringColor.g > 0.0f && m.scatteringColor.b > 0.0f &&
              maxComponent(m.scatteringColor) <= 1.0f,
          "scatteringColor", Checker::str(m.scatteringColor), "(0, 1] per channel");
  c.check(m.scatteringDistanceM > 0.0f, "scatteringDistanceM", Checker::str(m.scatteringDistanceM), "(0, ∞]");
  c.check(m.reflectionFogDistanceM > 0.0f, "reflectionFogDistanceM", Checker::str(m.reflectionFogDistanceM),
          "(0, ∞]");
  c.unit("reflectionFogColor", m.reflectionFogColor);
  c.check(m.bumpScale >= 0.0f && std::isfinite(m.bumpScale), "bumpScale", Checker::str(m.bumpScale), "[0, ∞)");
  const Rgb& e = m.emissionLuminance;
  c.check(e.r >= 0.0f && e.g >= 0.0f && e.b >= 0.0f && isFinite(e), "emissionLuminance", Checker::str(e),
          "[0, ∞) cd/m² per channel");
  return c.problem();
}

}  // namespace fly::sdb
