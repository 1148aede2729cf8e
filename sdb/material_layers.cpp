#include "sdb/material_layers.h"

#include <algorithm>
#include <cmath>

namespace fly::sdb {

CoatedMaterial applyClearCoat(const Material& base, const ClearCoat& coat) {
  CoatedMaterial out{base, false};
  if (coat.amount <= 0.0f) return out;
  Material& m = out.material;
  const float coatF0 = fresnelF0(kClearCoatIor);
  if (base.reflectionModel == ReflectionModel::kFresnel) {
    const Rgb covered = Rgb(coat.amount * coatF0);
    const Rgb uncovered = (1.0f - coat.amount) * base.reflectionColor * fresnelF0(base.ior);
    out.coatIsLobe = maxComponent(covered) >= maxComponent(uncovered);
    if (out.coatIsLobe) {
      m.ior = kClearCoatIor;
      m.reflectionGlossiness = coat.glossiness;
    }
    // The larger share is > 0 (amount > 0), so F0 of the lobe's ior is > 0 too.
    m.reflectionColor = glm::min((covered + uncovered) / fresnelF0(m.ior), Rgb(1.0f));
    return out;
  }
  if (coat.glossiness >= base.reflectionGlossiness) return out;  // the metal's lobe is the sharper one
  out.coatIsLobe = true;
  m.diffuseColor = glm::min(base.diffuseColor + base.reflectionColor, Rgb(1.0f));
  m.reflectionModel = ReflectionModel::kFresnel;
  m.reflectionColor = Rgb(coat.amount);
  m.ior = kClearCoatIor;
  m.reflectionGlossiness = coat.glossiness;
  m.anisotropyU = m.anisotropyV = 0.0f;
  m.anisotropyRotationRad = 0.0f;
  m.anisotropyTexture = {};
  m.anisotropyRotationTexture = {};
  return out;
}

namespace {

// Ē for sheen roughness r in [0.1, 1] (material_layers.h).
double sheenAlbedoQuadrature(double r) {
  const double invAlpha = 1.0 / (r * r);
  const double norm = (2.0 + invAlpha) / (2.0 * kPi);
  // Midpoint quadrature over the outgoing cosine μo (weight 2μo dμo: cosine-weighted average over incidence)
  // and over the incoming hemisphere in (cos θi, φ) (dω = d cos θi dφ). The integrand is symmetric in φ.
  constexpr int kMu = 48, kCos = 96, kPhi = 96;
  double sum = 0.0;
  for (int a = 0; a < kMu; ++a) {
    const double muO = (a + 0.5) / kMu;
    const double sinO = std::sqrt(1.0 - muO * muO);
    double directional = 0.0;  // E(μo) = ∫ D·V·cos θi dωi
    for (int b = 0; b < kCos; ++b) {
      const double muI = (b + 0.5) / kCos;
      const double sinI = std::sqrt(1.0 - muI * muI);
      const double v = 1.0 / (4.0 * (muI + muO - muI * muO));
      for (int c = 0; c < kPhi; ++c) {
        const double phi = (c + 0.5) / kPhi * kPi;  // [0, π]; doubled below
        // h ∝ l + v with v = (sinO, 0, μo), l = (sinI cos φ, sinI sin φ, μI): cos θh = (μI + μO)/|l + v|.
        const double hx = sinI * std::cos(phi) + sinO, hy = sinI * std::sin(phi), hz = muI + muO;
        const double len2 = hx * hx + hy * hy + hz * hz;
        const double sinH2 = (hx * hx + hy * hy) / len2;
        const double d = norm * std::pow(sinH2, 0.5 * invAlpha);
        directional += d * v * muI;
      }
    }
    directional *= (1.0 / kCos) * (2.0 * kPi / kPhi);
    sum += 2.0 * muO * directional / kMu;
  }
  return sum;
}

}  // namespace

float sheenAlbedo(float sheenRoughness) {
  constexpr double kThinnest = 0.1;
  const double r = std::clamp(double(sheenRoughness), 0.0, 1.0);
  if (r < kThinnest) return float(sheenAlbedoQuadrature(kThinnest) * r / kThinnest);
  return float(sheenAlbedoQuadrature(r));
}

Material applySheen(const Material& base, const Rgb& sheenColor, float sheenRoughness) {
  Material m = base;
  const float e = sheenAlbedo(sheenRoughness);
  m.diffuseColor =
      glm::clamp(base.diffuseColor * (1.0f - maxComponent(sheenColor) * e) + sheenColor * e, 0.0f, 1.0f);
  return m;
}

}  // namespace fly::sdb
