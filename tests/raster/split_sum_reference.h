// The split sum of fly's GGX by an independent quadrature (header-only: the test glob compiles *_test.cpp),
// the reference of the environment light's table (environment_light_test.cpp) and of the scene pass's
// image-based light (image_based_light_test.cpp).
#pragma once

#include <cmath>

#include "base/ggx.h"
#include "base/math.h"

namespace fly::raster::test {

// Calls f(ω, dω) over a midpoint grid of the hemisphere around +z: θ = u² π/2 (dense near the pole, where a
// narrow GGX lobe lives; dθ = u π du) × φ, dω = sin θ dθ dφ.
template <class F>
inline void overWarpedHemisphere(int thetaSteps, int phiSteps, const F& f) {
  for (int i = 0; i < thetaSteps; ++i) {
    const double u = (i + 0.5) / thetaSteps, theta = u * u * kPi / 2.0, dTheta = u * kPi / thetaSteps;
    const double sinT = std::sin(theta), cosT = std::cos(theta);
    for (int j = 0; j < phiSteps; ++j) {
      const double phi = (j + 0.5) / phiSteps * 2.0 * kPi;
      f(vec3(float(sinT * std::cos(phi)), float(sinT * std::sin(phi)), float(cosT)), sinT * dTheta * 2.0 * kPi / phiSteps);
    }
  }
}

// The split sum (A, B)(cos θo, α) by a fine quadrature over half vectors of fly's GGX (base/ggx.h, the
// height-correlated G2 of raytracer/bsdf.cpp): ∫ f₁ cos θi dωi = ∫ D(h) G2 (ωo·h) / cos θo dωh over the h
// for which ωi lies above the surface, split by Schlick's Fc = (1 − ωo·h)⁵.
inline vec2 splitSumByQuadrature(float cosO, float alpha, int thetaSteps = 2048, int phiSteps = 512) {
  const float a2 = alpha * alpha;
  const vec3 wo(std::sqrt(1.0f - cosO * cosO), 0.0f, cosO);
  const float lambdaO = ggxLambda(cosO, a2);
  double a = 0.0, b = 0.0;
  overWarpedHemisphere(thetaSteps, phiSteps, [&](const vec3& h, double dOmega) {
    const float oh = glm::dot(wo, h);
    if (oh <= 0.0f) return;
    const vec3 wi = 2.0f * oh * h - wo;
    if (wi.z <= 0.0f) return;
    const double g2 = 1.0 / (1.0 + lambdaO + ggxLambda(wi.z, a2));
    const double value = ggxD(h.z, a2) * g2 * oh / cosO * dOmega;
    const double fc = std::pow(1.0 - oh, 5.0);
    a += (1.0 - fc) * value;
    b += fc * value;
  });
  return vec2(float(a), float(b));
}

}  // namespace fly::raster::test
