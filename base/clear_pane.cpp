#include "base/clear_pane.h"

#include <algorithm>
#include <cmath>

namespace fly {
namespace {

// Bounds that keep every quotient finite: at grazing incidence (cos θ = 0) and n = 1 the numerators vanish
// with the denominators.
constexpr float kTiny = 1e-30f;
constexpr float kMinCosRefracted = 1e-6f;
// F0 below 1, so that n stays finite (an ior of 4 gives F0 = 0.36).
constexpr float kMaxF0 = 0.99f;

struct Interface {
  float cosRefracted;  // cos θt
  vec2 transmitted;    // 1 − R for s and p polarisation
};

// One air–glass face at cos θ = c (the Fresnel equations): 1 − R_s = 4 n c c_t / (c + n c_t)², 1 − R_p =
// 4 n c c_t / (n c + c_t)², written so that no 1 − R is taken of an R near 1.
Interface interfaceAt(float c, float n) {
  const float ct = std::sqrt(std::max(1.0f - (1.0f - c * c) / (n * n), 0.0f));
  const float k = 4.0f * n * c * ct;
  const float s = c + n * ct;
  const float p = n * c + ct;
  return {ct, vec2(std::min(k / std::max(s * s, kTiny), 1.0f), std::min(k / std::max(p * p, kTiny), 1.0f))};
}

// One polarisation's slab transmittance (1 − R)² τ / (1 − R² τ²), tr = 1 − R; 1 − R²τ² = (1 − Rτ)(1 + Rτ)
// with 1 − Rτ = (1 − τ) + tr τ.
float slabPolarised(float tr, float tau) {
  const float den = ((1.0f - tau) + tr * tau) * (1.0f + (1.0f - tr) * tau);
  return tr * tr * tau / std::max(den, kTiny);
}

float internalAt(float tau0, float cosRefracted) {
  return std::pow(tau0, 1.0f / std::max(cosRefracted, kMinCosRefracted));
}

float indexOf(float f0) {
  const float q = std::sqrt(std::clamp(f0, 0.0f, kMaxF0));
  return (1.0f + q) / (1.0f - q);
}

}  // namespace

float slabInternalTransmittance(float r0, float normalT) {
  const float r = std::clamp(r0, 0.0f, kMaxF0);
  const float t = std::clamp(normalT, 0.0f, 1.0f);
  const float b = (1.0f - r) * (1.0f - r);
  return std::min(2.0f * t / (b + std::sqrt(b * b + 4.0f * t * t * r * r)), 1.0f);
}

float slabTransmittance(float cosTheta, float n, float tau0) {
  const Interface f = interfaceAt(std::min(std::abs(cosTheta), 1.0f), std::max(n, 1.0f));
  const float tau = internalAt(std::clamp(tau0, 0.0f, 1.0f), f.cosRefracted);
  return 0.5f * (slabPolarised(f.transmitted.x, tau) + slabPolarised(f.transmitted.y, tau));
}

ClearPane::ClearPane(float f0, const Rgb& transmission, const Rgb& r0, const Rgb& r90)
    : fresnel_(f0 >= 0.0f),
      t_(glm::clamp(transmission, 0.0f, 1.0f)),
      r0_(glm::clamp(r0, 0.0f, 1.0f)),
      r90_(glm::clamp(r90, 0.0f, 1.0f)) {
  normalT_ = t_ * (Rgb(1.0f) - r0_);
  if (!fresnel_) return;
  f0_ = std::min(f0, kMaxF0);
  n_ = indexOf(f0_);
  for (int ch = 0; ch < 3; ++ch) {
    tau0_[ch] = slabInternalTransmittance(f0_, normalT_[ch]);
    const float s0 = slabTransmittance(1.0f, n_, tau0_[ch]);
    scale_[ch] = s0 > 0.0f ? normalT_[ch] / s0 : 0.0f;
  }
}

Rgb ClearPane::at(float cosTheta) const {
  if (!fresnel_) return normalT_;
  const float c = std::min(std::abs(cosTheta), 1.0f);
  const Interface f = interfaceAt(c, n_);
  const float m = 1.0f - c;
  const float m2 = m * m;
  const Rgb reflected = glm::min(r0_ + (r90_ - r0_) * (m2 * m2 * m), Rgb(1.0f));
  Rgb t(0.0f);
  for (int ch = 0; ch < 3; ++ch) {
    const float tau = internalAt(tau0_[ch], f.cosRefracted);
    const float s = 0.5f * (slabPolarised(f.transmitted.x, tau) + slabPolarised(f.transmitted.y, tau));
    t[ch] = std::min(scale_[ch] * s, t_[ch] * (1.0f - reflected[ch]));
  }
  return t;
}

}  // namespace fly
