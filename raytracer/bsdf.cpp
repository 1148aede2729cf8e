#include "raytracer/bsdf.h"

#include <cmath>

#include "base/ggx.h"
#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

// The reflection lobe's D G2 / (4 cos θo cos θi) for wo, wi above the surface, and the density per steradian
// of sampling wi by visible normals: G1(wo) D(h) / (4 cos θo) (Heitz 2018, eq. 17 with the reflection
// Jacobian 1 / (4 ωo·h)). `h` receives the half vector.
float ggxReflection(const vec3& wo, const vec3& wi, float alpha, vec3& h, float& pdf) {
  h = glm::normalize(wo + wi);
  const float a2 = alpha * alpha;
  const float d = ggxD(h.z, a2);
  const float lambdaO = ggxLambda(wo.z, a2);
  pdf = ggxVisibleReflectionPdf(wo, h, a2);
  return d / ((1.0f + lambdaO + ggxLambda(wi.z, a2)) * 4.0f * wo.z * wi.z);
}

// The same for the anisotropic lobe of widths ax (along +x) and ay (along +y): wo, wi and h in the lobe's
// frame.
float ggxReflectionAnisotropic(const vec3& wo, const vec3& wi, float ax, float ay, vec3& h, float& pdf) {
  h = glm::normalize(wo + wi);
  const float d = ggxDAnisotropic(h, ax, ay);
  const float lambdaO = ggxLambdaAnisotropic(wo, ax, ay);
  pdf = d / ((1.0f + lambdaO) * 4.0f * wo.z);
  return d / ((1.0f + lambdaO + ggxLambdaAnisotropic(wi, ax, ay)) * 4.0f * wo.z * wi.z);
}

float mean(const Rgb& c) {
  return (c.r + c.g + c.b) / 3.0f;
}

// GGX α from a glossiness in [0, 1]; 0 (a delta lobe) below kSmoothAlpha.
float alphaOf(float glossiness) {
  const float g = std::clamp(glossiness, 0.0f, 1.0f);
  return g * g < kSmoothAlpha ? 0.0f : g * g;
}

// R0 and R90 of m's reflection mixed with its metal (TraceMaterial::metalness), and the share 1 − m.
struct Reflectance {
  Rgb r0, r90;
  float dielectric;
};
Reflectance reflectanceOf(const rdb::TraceMaterial& m) {
  const float q = (std::max(m.ior, 1.0f) - 1.0f) / (std::max(m.ior, 1.0f) + 1.0f);
  const Rgb r = glm::clamp(m.reflection, 0.0f, 1.0f);
  const float metal = std::isfinite(m.metalness) ? std::clamp(m.metalness, 0.0f, 1.0f) : 0.0f;
  if (metal == 0.0f) return {r * (m.fresnel ? q * q : 1.0f), r, 1.0f};
  const Rgb c = glm::clamp(m.diffuseColor, 0.0f, 1.0f);
  return {glm::mix(r * (m.fresnel ? q * q : 1.0f), c, metal), glm::mix(r, c, metal), 1.0f - metal};
}

}  // namespace

Rgb normalIncidenceDiffuse(const rdb::TraceMaterial& m) {
  const Reflectance x = reflectanceOf(m);
  const Rgb t = (Rgb(1.0f) - x.r0) * (x.dielectric * glm::clamp(m.transmission, 0.0f, 1.0f));
  return glm::max(Rgb(1.0f) - x.r0 - t, Rgb(0.0f)) * (x.dielectric * glm::clamp(m.diffuseColor, 0.0f, 1.0f));
}

Bsdf::Bsdf(const rdb::TraceMaterial& m, bool frontFace, float coverage, const MeasuredLobe* measured) {
  coverage_ = std::isfinite(coverage) ? std::clamp(coverage, 0.0f, 1.0f) : 1.0f;
  init(m, frontFace, measured);
  lambertian_ = covered() && hasDiffuse_ && !hasReflection_ && !hasTransmission_;
  nonDelta_ = coverage_ > 0.0f && (measured_ != nullptr || hasDiffuse_ ||
                                   (hasReflection_ && alphaR_ > 0.0f) || frostedTransmission());
  // albedoAt's sum is then 1 · (0 + diffuseKd_ · (1 − 0)) + 0: diffuseKd_ to the bit.
  constantAlbedo_ = lambertian_ && measured_ == nullptr && r90_ == Rgb(0.0f);
}

void Bsdf::init(const rdb::TraceMaterial& m, bool frontFace, const MeasuredLobe* measured) {
  if (m.isMeasured() && measured != nullptr) {
    if (frontFace) measured_ = measured;
    return;
  }
  const Reflectance x = reflectanceOf(m);
  r0_ = x.r0;
  r90_ = x.r90;
  transmission_ = x.dielectric * glm::clamp(m.transmission, 0.0f, 1.0f);
  alphaR_ = alphaOf(m.reflectionGlossiness);
  if (alphaR_ > 0.0f && m.anisotropyU != m.anisotropyV) {
    const vec2 widths = ggxAnisotropicAlphas(alphaR_, std::clamp(m.anisotropyU, 0.0f, 1.0f),
                                             std::clamp(m.anisotropyV, 0.0f, 1.0f));
    anisotropic_ = widths.x != widths.y;
    alphaU_ = widths.x;
    alphaV_ = widths.y;
    const float rotationRad = std::isfinite(m.anisotropyRotationRad) ? m.anisotropyRotationRad : 0.0f;
    rotationCos_ = std::cos(rotationRad);
    rotationSin_ = std::sin(rotationRad);
  }
  alphaT_ = alphaOf(m.transmissionGlossiness);
  // R is smallest at normal incidence (R0), so T(θ) > 0 somewhere iff t (1 − R0) > 0.
  hasTransmission_ = maxComponent(transmission_ * (Rgb(1.0f) - r0_)) > 0.0f;
  clearTransmission_ = hasTransmission_ && alphaT_ == 0.0f;
  if (clearTransmission_) {
    const float q = (std::max(m.ior, 1.0f) - 1.0f) / (std::max(m.ior, 1.0f) + 1.0f);
    pane_ = ClearPane(m.fresnel ? q * q : -1.0f, transmission_, r0_, r90_);
  }
  if (!frontFace) return;
  hasReflection_ = maxComponent(r90_) > 0.0f;
  // Σ R μ over the hemisphere: R̄ = 2∫₀¹ (R0 + (R90 − R0)(1 − μ)⁵) μ dμ = R0 + (R90 − R0)·2·B(2, 6) = R0 +
  // (R90 − R0)/21.
  const Rgb rBar = r0_ + (r90_ - r0_) / 21.0f;
  const Rgb diffuse = glm::clamp(m.diffuse, 0.0f, 1.0f);
  for (int c = 0; c < 3; ++c) {
    const float atNormal = 1.0f - r0_[c];
    const float norm = 1.0f - rBar[c];
    if (atNormal > 0.0f && norm > 0.0f && diffuse[c] > 0.0f) {
      diffuseKd_[c] = std::min(diffuse[c] / atNormal, 1.0f);
      diffuseNorm_[c] = 1.0f / norm;
    }
  }
  hasDiffuse_ = maxComponent(diffuseKd_) > 0.0f;
}

float Bsdf::reflectionLobe(const vec3& wo, const vec3& wi, vec3& h, float& pdf) const {
  if (!anisotropic_) return ggxReflection(wo, wi, alphaR_, h, pdf);
  vec3 hLobe;
  const float g = ggxReflectionAnisotropic(toLobe(wo), toLobe(wi), alphaU_, alphaV_, hLobe, pdf);
  h = fromLobe(hLobe);
  return g;
}

Rgb Bsdf::albedoAt(float cosO) const {
  if (measured_) return coverage_ * measured_->albedo(cosO) + Rgb(1.0f - coverage_);
  const Rgb reflected = reflectance(cosO);
  Rgb a(0.0f);
  if (hasDiffuse_) a += diffuseKd_ * (Rgb(1.0f) - reflected);
  if (hasReflection_) a += reflected;
  if (hasTransmission_) a += transmissionAlbedo(cosO, reflected);
  return coverage_ * a + Rgb(1.0f - coverage_);
}

vec4 Bsdf::lobeProbabilities(float cosO) const {
  if (measured_) {
    // A floor keeps the lobe chosen where its albedo estimate is 0 but f is not.
    const vec2 w(coverage_ * std::max(mean(measured_->albedo(cosO)), 1e-4f), 1.0f - coverage_);
    const float sum = w.x + w.y;
    return sum > 0.0f ? vec4(w.x, 0.0f, 0.0f, w.y) / sum : vec4(0.0f);
  }
  const Rgb reflected = reflectance(cosO);
  const vec4 w(hasDiffuse_ ? coverage_ * mean(diffuseKd_ * (Rgb(1.0f) - reflected)) : 0.0f,
               hasReflection_ ? coverage_ * mean(reflected) : 0.0f,
               hasTransmission_ ? coverage_ * mean(transmissionAlbedo(cosO, reflected)) : 0.0f,
               1.0f - coverage_);
  const float sum = w.x + w.y + w.z + w.w;
  return sum > 0.0f ? w / sum : vec4(0.0f);
}

Rgb Bsdf::eval(const vec3& wo, const vec3& wi) const {
  if (measured_) return wi.z > 0.0f ? coverage_ * measured_->eval(wo, wi) : Rgb(0.0f);
  Rgb f(0.0f);
  if (wi.z > 0.0f) {
    if (hasDiffuse_) {
      const Rgb oneMinusRi = Rgb(1.0f) - reflectance(wi.z);
      const Rgb oneMinusRo = Rgb(1.0f) - reflectance(wo.z);
      f += diffuseKd_ * diffuseNorm_ * oneMinusRi * oneMinusRo / kPiF;
    }
    if (hasReflection_ && alphaR_ > 0.0f) f += glossyReflection(wo, wi);
  } else if (wi.z < 0.0f && frostedTransmission()) {
    vec3 h;
    float pdfUnused;
    const float g = ggxReflection(wo, vec3(wi.x, wi.y, -wi.z), alphaT_, h, pdfUnused);
    f += transmission_ * (Rgb(1.0f) - reflectance(glm::dot(wo, h))) * g;
  }
  return coverage_ * f;
}

Rgb Bsdf::glossyReflection(const vec3& wo, const vec3& wi) const {
  vec3 h;
  float pdfUnused;
  const float g = reflectionLobe(wo, wi, h, pdfUnused);
  return reflectance(glm::dot(wo, h)) * g;
}

Rgb Bsdf::evalReflection(const vec3& wo, const vec3& wi) const {
  if (measured_ || !hasReflection_ || !(alphaR_ > 0.0f) || !(wi.z > 0.0f)) return Rgb(0.0f);
  return coverage_ * glossyReflection(wo, wi);
}

float Bsdf::pdf(const vec3& wo, const vec3& wi) const {
  const vec4 p = lobeProbabilities(wo.z);
  if (measured_) return wi.z > 0.0f ? p.x * measured_->pdf(wo, wi) : 0.0f;
  vec3 h;
  float lobePdf = 0.0f;
  float sum = 0.0f;
  if (wi.z > 0.0f) {
    if (hasDiffuse_) sum += p.x * wi.z / kPiF;
    if (hasReflection_ && alphaR_ > 0.0f) {
      reflectionLobe(wo, wi, h, lobePdf);
      sum += p.y * lobePdf;
    }
  } else if (wi.z < 0.0f && frostedTransmission()) {
    ggxReflection(wo, vec3(wi.x, wi.y, -wi.z), alphaT_, h, lobePdf);
    sum += p.z * lobePdf;
  }
  return sum;
}

bool Bsdf::sample(const vec3& wo, float uLobe, const vec2& u, Sample& out) const {
  const vec4 p = lobeProbabilities(wo.z);
  if (p.x + p.y + p.z + p.w <= 0.0f) return false;
  // The lobe whose interval of [0, 1) holds uLobe; rounding past the last interval falls to the last lobe.
  int lobe = uLobe < p.x ? 0 : (uLobe < p.x + p.y ? 1 : (uLobe < p.x + p.y + p.z ? 2 : 3));
  while (p[lobe] == 0.0f) lobe = (lobe + 3) % 4;
  if (lobe == 3 || (lobe == 2 && clearTransmission_)) {
    // Straight through: clear glass and the uncovered fraction are one delta lobe, chosen with the sum of
    // their probabilities.
    const float pStraight = (clearTransmission_ ? p.z : 0.0f) + p.w;
    out.wi = -wo;
    out.pdf = pStraight;
    out.weight = straightTransmittance(wo.z) / pStraight;
    out.lobe = Lobe::kStraight;
    return true;
  }
  if (lobe == 0 && measured_) {
    // The rest of uLobe within the lobe's interval chooses among the measured lobe's strategies.
    if (!measured_->sample(wo, std::min(uLobe / p.x, 0x1.fffffep-1f), u, out.wi)) return false;
  } else if (lobe == 0) {
    out.wi = sampleCosineHemisphere(u);
  } else if (lobe == 1) {
    if (alphaR_ == 0.0f) {
      out.wi = vec3(-wo.x, -wo.y, wo.z);
      out.pdf = p.y;
      out.weight = reflectance(wo.z) * (coverage_ / p.y);
      out.lobe = Lobe::kMirror;
      return true;
    }
    const vec3 h = anisotropic_ ? fromLobe(sampleGgxVisibleNormal(toLobe(wo), alphaU_, alphaV_, u))
                                : sampleGgxVisibleNormal(wo, alphaR_, u);
    out.wi = 2.0f * glm::dot(wo, h) * h - wo;
    if (out.wi.z <= 0.0f) return false;
  } else {
    const vec3 h = sampleGgxVisibleNormal(wo, alphaT_, u);
    const vec3 mirrored = 2.0f * glm::dot(wo, h) * h - wo;
    if (mirrored.z <= 0.0f) return false;
    out.wi = vec3(mirrored.x, mirrored.y, -mirrored.z);
  }
  out.wi = glm::normalize(out.wi);
  out.pdf = pdf(wo, out.wi);
  if (!(out.pdf > 0.0f) || !std::isfinite(out.pdf)) return false;
  out.weight = eval(wo, out.wi) * (std::abs(out.wi.z) / out.pdf);
  out.lobe = Lobe::kNonDelta;
  return true;
}

}  // namespace fly::raytracer
