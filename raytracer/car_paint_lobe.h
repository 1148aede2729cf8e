// The compact car-paint BRDF (base/car_paint.h: a clear coat over GGX metallic flakes and a diffuse base) as a
// Bsdf lobe: evaluated by the model itself, sampled by a mixture of its layers' own strategies:
//   - the coat: GGX visible normals from ωo (Heitz 2018, base/ggx.h), ωi its mirror about them;
//   - flake lobe k: visible normals of its GGX from ωo' (ωo refracted into the coat), ωi' their mirror, then
//     ωi refracted out of the coat (Snell about the macro normal; a draw that the coat reflects totally back
//     in returns false), with the refraction's Jacobian dωi'/dωi = cos θi / (η² cos θi');
//   - the base: cosine-distributed ωi.
// The mixture's weights at ωo estimate each layer's share of the albedo: the coat's Fresnel reflectance F(θo),
// and of the light that enters (1 − F(θo)) the flakes' mean F0 and the base's mean albedo. sample() draws from
// one layer; pdf() is the whole mixture's density, so that eval, pdf and sample agree and multiple importance
// sampling with light sampling sees the density it needs.
#pragma once

#include <array>

#include "base/car_paint.h"
#include "raytracer/measured_lobe.h"

namespace fly::raytracer {

class CarPaintBsdfLobe final : public MeasuredLobe {
 public:
  // Layers: the coat, the flake lobes, the base.
  static constexpr int kLayers = 2 + CarPaintBrdf::kMaxLobes;
  // cos θo nodes of the albedo table (albedo()), evenly spaced over (0, 1].
  static constexpr int kAlbedoNodes = 16;

  explicit CarPaintBsdfLobe(const CarPaintBrdf& paint);

  Rgb eval(const vec3& wo, const vec3& wi) const override { return paint_.evalPerSr(wi, wo); }
  float pdf(const vec3& wo, const vec3& wi) const override;
  bool sample(const vec3& wo, float uChoice, const vec2& u, vec3& wi) const override;
  // Interpolated from a table at kAlbedoNodes angles estimated at construction with 1024 stratified draws of
  // sample() each (a quasi-Monte-Carlo estimate: exact enough for Russian roulette and lobe choice).
  Rgb albedo(float cosO) const override;

 private:
  // The layers' choice probabilities at ωo (sum 1, or all 0 for a black paint).
  std::array<float, kLayers> layerProbabilities(float cosO) const;
  // The density per steradian of ωi by layer `layer` alone.
  float layerPdf(int layer, const vec3& wo, const vec3& wi) const;

  CarPaintBrdf paint_;
  bool coated_ = false;  // η > 1: the coat reflects and refracts
  std::array<Rgb, kAlbedoNodes> albedo_{};
};

}  // namespace fly::raytracer
