#include "base/car_paint.h"

#include <algorithm>
#include <cmath>

#include "base/ggx.h"

namespace fly {
namespace {

// D · G1(ωi) G1(ωo) / (4 cos θi cos θo) of a GGX lobe (separable Smith masking, Walter et al. 2007, eq. 23),
// without its Fresnel factor; cosThetaD = ωi · h.
float ggxLobe(const vec3& wi, const vec3& wo, float alpha, float& cosThetaD) {
  const vec3 h = glm::normalize(wi + wo);
  cosThetaD = std::clamp(glm::dot(wi, h), 0.0f, 1.0f);
  const float a2 = alpha * alpha;
  return ggxD(h.z, a2) * ggxSmithG1(wi.z, a2) * ggxSmithG1(wo.z, a2) / (4.0f * wi.z * wo.z);
}

}  // namespace

vec3 refractIntoLayer(const vec3& w, float eta) {
  const vec3 t(w.x / eta, w.y / eta, 0.0f);
  return {t.x, t.y, std::sqrt(std::max(0.0f, 1.0f - t.x * t.x - t.y * t.y))};
}

float dielectricFresnel(float cosTheta, float eta) {
  const float c = std::clamp(cosTheta, 0.0f, 1.0f);
  const float sin2t = (1.0f - c * c) / (eta * eta);
  if (sin2t >= 1.0f) return 1.0f;
  const float ct = std::sqrt(1.0f - sin2t);
  const float rs = (c - eta * ct) / (c + eta * ct);
  const float rp = (eta * c - ct) / (eta * c + ct);
  return 0.5f * (rs * rs + rp * rp);
}

float internalDiffuseReflectance(float eta) {
  if (!(eta > 1.0f)) return 0.0f;
  // The last η asked for, per thread: a fit or an image evaluates one coat many times.
  thread_local float cachedEta = 0.0f, cachedValue = 0.0f;
  if (eta == cachedEta) return cachedValue;
  // F̄ext = ∫₀¹ F(μ) 2μ dμ = ∫₀¹ F(√s) ds (s = μ²), midpoint rule.
  constexpr int kSteps = 4096;
  double external = 0.0;
  for (int i = 0; i < kSteps; ++i) external += dielectricFresnel(float(std::sqrt((i + 0.5) / kSteps)), eta);
  external /= kSteps;
  cachedEta = eta;
  cachedValue = float(1.0 - (1.0 - external) / (double(eta) * eta));
  return cachedValue;
}

Rgb CarPaintBrdf::evalPerSr(const vec3& wi, const vec3& wo) const {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return Rgb(0.0f);
  Rgb f(0.0f);
  float through = 1.0f;
  vec3 wiBase = wi, woBase = wo;
  if (coatIor > 1.0f) {
    float cosThetaD;
    const float lobe = ggxLobe(wi, wo, coatAlpha, cosThetaD);
    f += Rgb(dielectricFresnel(cosThetaD, coatIor) * lobe);
    through = (1.0f - dielectricFresnel(wi.z, coatIor)) * (1.0f - dielectricFresnel(wo.z, coatIor)) /
              (coatIor * coatIor);
    wiBase = refractIntoLayer(wi, coatIor);
    woBase = refractIntoLayer(wo, coatIor);
  }
  const float internal = internalDiffuseReflectance(coatIor);
  Rgb base = baseAlbedo / (kPiF * (Rgb(1.0f) - baseAlbedo * internal));
  for (const CarPaintLobe& l : lobes) {
    if (l.f0 == Rgb(0.0f)) continue;
    float cosThetaD;
    const float lobe = ggxLobe(wiBase, woBase, l.alpha, cosThetaD);
    const float schlick = std::pow(1.0f - cosThetaD, 5.0f);
    base += (l.f0 + (Rgb(1.0f) - l.f0) * schlick) * lobe;
  }
  return f + through * base;
}

std::string CarPaintBrdf::validate() const {
  auto unit = [](const Rgb& c) { return c.r >= 0 && c.r <= 1 && c.g >= 0 && c.g <= 1 && c.b >= 0 && c.b <= 1; };
  if (!unit(baseAlbedo)) return "the base albedo must lie in [0, 1] in each channel";
  for (const CarPaintLobe& l : lobes) {
    if (!unit(l.f0)) return "a flake lobe's reflectance must lie in [0, 1] in each channel";
    if (!(l.alpha >= 0.01f && l.alpha <= 1.0f)) return "a flake lobe's roughness α must lie in [0.01, 1]";
  }
  if (!(coatIor >= 1.0f && coatIor <= 3.0f)) return "the coat's refractive index must lie in [1, 3]";
  if (!(coatAlpha >= 0.001f && coatAlpha <= 1.0f)) return "the coat's roughness α must lie in [0.001, 1]";
  return "";
}

}  // namespace fly
