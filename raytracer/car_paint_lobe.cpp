#include "raytracer/car_paint_lobe.h"

#include <algorithm>
#include <cmath>

#include "base/ggx.h"
#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

constexpr int kCoat = 0;
constexpr int kFirstFlake = 1;
constexpr int kBase = 1 + CarPaintBrdf::kMaxLobes;

float mean(const Rgb& c) { return (c.r + c.g + c.b) / 3.0f; }

// The radical inverse of i in base 2 (Hammersley's second coordinate).
float radicalInverse2(uint32_t i) {
  i = (i << 16u) | (i >> 16u);
  i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
  i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
  i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
  i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
  return float(i) * 0x1p-32f;
}

}  // namespace

CarPaintBsdfLobe::CarPaintBsdfLobe(const CarPaintBrdf& paint) : paint_(paint), coated_(paint.coatIor > 1.0f) {
  // The albedo table: f cos θi / pdf over a Hammersley set (u) with an independent golden-ratio sequence for
  // the layer choice.
  constexpr uint32_t kDraws = 1024;
  for (int n = 0; n < kAlbedoNodes; ++n) {
    const float cosO = (float(n) + 1.0f) / kAlbedoNodes;
    const vec3 wo(std::sqrt(std::max(0.0f, 1.0f - cosO * cosO)), 0.0f, cosO);
    dvec3 sum(0.0);
    for (uint32_t i = 0; i < kDraws; ++i) {
      const vec2 u((float(i) + 0.5f) / kDraws, radicalInverse2(i));
      const float uChoice = std::fmod(0.5f + 0.61803398875f * float(i), 1.0f);
      vec3 wi;
      if (!sample(wo, uChoice, u, wi)) continue;
      const float p = pdf(wo, wi);
      if (p > 0.0f) sum += dvec3(eval(wo, wi) * (wi.z / p));
    }
    albedo_[size_t(n)] = Rgb(sum / double(kDraws));
  }
}

Rgb CarPaintBsdfLobe::albedo(float cosO) const {
  const float x = std::clamp(cosO * kAlbedoNodes - 1.0f, 0.0f, float(kAlbedoNodes - 1));
  const int i = std::min(int(x), kAlbedoNodes - 2);
  return glm::mix(albedo_[size_t(i)], albedo_[size_t(i) + 1], x - float(i));
}

std::array<float, CarPaintBsdfLobe::kLayers> CarPaintBsdfLobe::layerProbabilities(float cosO) const {
  std::array<float, kLayers> w{};
  const float reflected = coated_ ? dielectricFresnel(cosO, paint_.coatIor) : 0.0f;
  const float entering = 1.0f - reflected;
  w[kCoat] = reflected;
  for (int k = 0; k < CarPaintBrdf::kMaxLobes; ++k) {
    const Rgb& f0 = paint_.lobes[size_t(k)].f0;
    // A lobe of a tiny F0 still reflects at grazing angles (Schlick): a floor keeps it sampled.
    if (f0 != Rgb(0.0f)) w[size_t(kFirstFlake + k)] = entering * std::max(mean(f0), 0.02f);
  }
  if (paint_.baseAlbedo != Rgb(0.0f)) w[kBase] = entering * std::max(mean(paint_.baseAlbedo), 0.02f);
  float sum = 0.0f;
  for (float x : w) sum += x;
  if (sum > 0.0f) {
    for (float& x : w) x /= sum;
  }
  return w;
}

float CarPaintBsdfLobe::layerPdf(int layer, const vec3& wo, const vec3& wi) const {
  if (layer == kBase) return cosineHemispherePdf(wi.z);
  if (layer == kCoat) {
    const float a2 = paint_.coatAlpha * paint_.coatAlpha;
    return ggxVisibleReflectionPdf(wo, glm::normalize(wo + wi), a2);
  }
  const float alpha = paint_.lobes[size_t(layer - kFirstFlake)].alpha;
  const float eta = coated_ ? paint_.coatIor : 1.0f;
  const vec3 woIn = refractIntoLayer(wo, eta);
  const vec3 wiIn = refractIntoLayer(wi, eta);
  const vec3 h = glm::normalize(woIn + wiIn);
  // Density of ωi' inside, times dωi'/dωi = cos θi / (η² cos θi').
  return ggxVisibleReflectionPdf(woIn, h, alpha * alpha) * wi.z / (eta * eta * wiIn.z);
}

float CarPaintBsdfLobe::pdf(const vec3& wo, const vec3& wi) const {
  if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
  const std::array<float, kLayers> p = layerProbabilities(wo.z);
  float sum = 0.0f;
  for (int layer = 0; layer < kLayers; ++layer) {
    if (p[size_t(layer)] > 0.0f) sum += p[size_t(layer)] * layerPdf(layer, wo, wi);
  }
  return sum;
}

bool CarPaintBsdfLobe::sample(const vec3& wo, float uChoice, const vec2& u, vec3& wi) const {
  if (!(wo.z > 0.0f)) return false;
  const std::array<float, kLayers> p = layerProbabilities(wo.z);
  int layer = -1;
  float cumulative = 0.0f;
  for (int l = 0; l < kLayers; ++l) {
    if (p[size_t(l)] <= 0.0f) continue;
    layer = l;  // rounding past the last interval falls to the last layer
    cumulative += p[size_t(l)];
    if (uChoice < cumulative) break;
  }
  if (layer < 0) return false;
  if (layer == kBase) {
    wi = sampleCosineHemisphere(u);
    return wi.z > 0.0f;
  }
  if (layer == kCoat) {
    const vec3 h = sampleGgxVisibleNormal(wo, paint_.coatAlpha, u);
    wi = glm::normalize(2.0f * glm::dot(wo, h) * h - wo);
    return wi.z > 0.0f;
  }
  const float eta = coated_ ? paint_.coatIor : 1.0f;
  const vec3 woIn = refractIntoLayer(wo, eta);
  const vec3 h = sampleGgxVisibleNormal(woIn, paint_.lobes[size_t(layer - kFirstFlake)].alpha, u);
  const vec3 wiIn = 2.0f * glm::dot(woIn, h) * h - woIn;
  if (!(wiIn.z > 0.0f)) return false;
  // Out through the coat: the tangential part grows by η; beyond the critical angle the coat reflects it back.
  const vec2 tangential = eta * vec2(wiIn.x, wiIn.y) / glm::length(wiIn);
  const float sin2 = glm::dot(tangential, tangential);
  if (!(sin2 < 1.0f)) return false;
  wi = vec3(tangential, std::sqrt(1.0f - sin2));
  return true;
}

}  // namespace fly::raytracer
