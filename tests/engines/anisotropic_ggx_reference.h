// The SDB material's reflection written out in double precision for the engine tests, with the anisotropic
// GGX lobe that raytracer/bsdf.h does not model yet: f(ωo, ωi) = the coupled diffuse
// k_d (1 − R(θi)) (1 − R(θo)) / ((1 − R̄) π) (k_d = diffuseKd) plus R(ωo·h) D(h) G2(ωo, ωi) / (4 cos θo cos θi), with
//   D(h) = 1 / (π α_t α_b ((h·t / α_t)² + (h·b / α_b)² + (h·n)²)²)          (Heitz 2014, JCGT 3(2), eq. 85)
//   Λ(ω) = (√(1 + (α_t² (ω·t)² + α_b² (ω·b)²) / (ω·n)²) − 1) / 2             (Heitz 2014, eq. 86)
//   G2 = 1 / (1 + Λ(ωo) + Λ(ωi))                                             (height-correlated, eq. 99)
// and (α_t, α_b) = ggxAnisotropicAlphas(glossiness², U, V) (base/ggx.h), the axes t (the tangent turned by the
// rotation about n) and b = n × t. With U = V it is the baker's isotropic Bsdf (checked against Bsdf::eval in
// material_albedo_test.cpp), so once the baker models anisotropy its Bsdf replaces this.
#pragma once

#include <algorithm>
#include <cmath>

#include "base/ggx.h"
#include "base/math.h"
#include "sdb/material.h"

namespace fly::test {

struct AnisotropicFrame {
  dvec3 n{0, 0, 1};
  dvec3 t{1, 0, 0};  // the lobe's first axis (α_t), after the rotation
  dvec3 b{0, 1, 0};  // n × t (α_b)
};

// The lobe's frame of a surface with normal n and (unrotated) tangent t0, turned by `rotationRad` about n
// (counter-clockwise seen from n's side), as rdb::RasterMaterial::anisotropic says.
inline AnisotropicFrame anisotropicFrame(const dvec3& n, const dvec3& t0, double rotationRad) {
  const dvec3 t = std::cos(rotationRad) * t0 + std::sin(rotationRad) * glm::cross(n, t0);
  return {n, t, glm::cross(n, t)};
}

// The lobe's widths of material m (U, V given: the texture's values where it has one).
inline dvec2 anisotropicAlphas(const sdb::Material& m, float u, float v) {
  return dvec2(ggxAnisotropicAlphas(m.reflectionGlossiness * m.reflectionGlossiness, u, v));
}

inline double anisotropicLambda(const dvec3& w, const AnisotropicFrame& f, const dvec2& a) {
  const double c = glm::dot(w, f.n);
  const double x = a.x * glm::dot(w, f.t), y = a.y * glm::dot(w, f.b);
  return 0.5 * (std::sqrt(1.0 + (x * x + y * y) / std::max(c * c, 1e-300)) - 1.0);
}

inline double anisotropicD(const dvec3& h, const AnisotropicFrame& f, const dvec2& a) {
  const double x = glm::dot(h, f.t) / a.x, y = glm::dot(h, f.b) / a.y, z = glm::dot(h, f.n);
  if (z <= 0.0) return 0.0;
  const double s = x * x + y * y + z * z;
  return 1.0 / (kPi * a.x * a.y * s * s);
}

// R(θ) of the energy rule per channel (sdb::Material::reflectionAt, clamped to [0, 1] as the engines do).
inline dvec3 reflectAt(const sdb::Material& m, double cosTheta) {
  return dvec3(glm::clamp(m.reflectionAt(float(cosTheta)), Rgb(0.0f), Rgb(1.0f)));
}

// The coupled diffuse's k_d: the energy rule's diffuse share at normal incidence over 1 − R(0), at most 1
// (raytracer/bsdf.h), so that its albedo towards θo is k_d (1 − R(θo)).
inline dvec3 diffuseKd(const sdb::Material& m) {
  const dvec3 atNormal = dvec3(1.0) - reflectAt(m, 1.0);
  const dvec3 d = glm::clamp(dvec3(m.effective().diffuse), dvec3(0.0), dvec3(1.0));
  return glm::min(d / glm::max(atNormal, dvec3(1e-12)), dvec3(1.0));
}

// f(ωo, ωi) cos θi of an opaque material m with the anisotropic lobe (α_t, α_b) in frame f, sr⁻¹; unit ωo, ωi.
inline dvec3 anisotropicBrdfCos(const sdb::Material& m, const dvec2& alphas, const AnisotropicFrame& f,
                                const dvec3& wo, const dvec3& wi) {
  const double cosO = glm::dot(wo, f.n), cosI = glm::dot(wi, f.n);
  if (cosO <= 0.0 || cosI <= 0.0) return dvec3(0.0);
  const dvec3 f0 = reflectAt(m, 1.0), f90 = reflectAt(m, 0.0);
  const dvec3 meanR = f0 + (f90 - f0) / 21.0;
  const dvec3 kd = diffuseKd(m);
  const dvec3 one(1.0);
  const dvec3 diffuse = kd * (one - reflectAt(m, cosI)) * (one - reflectAt(m, cosO)) /
                        (glm::max(one - meanR, dvec3(1e-6)) * kPi);
  const dvec3 h = glm::normalize(wo + wi);
  const double g2 = 1.0 / (1.0 + anisotropicLambda(wo, f, alphas) + anisotropicLambda(wi, f, alphas));
  const dvec3 specular = reflectAt(m, glm::dot(wo, h)) * (anisotropicD(h, f, alphas) * g2 / (4.0 * cosO * cosI));
  return (diffuse + specular) * cosI;
}

// The radiance the anisotropic lobe alone reflects towards ωo from an environment of radiance L(ωi) (any
// callable dvec3 → double): ∫ R(ωo·h) D G2 / (4 cos θo cos θi) L(ωi) cos θi dωi, per channel of R, by an n × n
// midpoint rule in the lobe's own parameters: with x = (h·t / h·n) / α_t, y = (h·b / h·n) / α_b in polar form
// (ρ, φ) and q = ρ² / (1 + ρ²), D(h) (h·n) dω_h = dq dφ / (2π), and dωi = 4 (ωo·h) dω_h, so the integral is the
// mean over (q, φ) ∈ [0, 1) × [0, 2π) of R(ωo·h) G2 (ωo·h) L(ωi) / (cos θo (h·n)) where ωi is above the surface.
template <class Radiance>
dvec3 anisotropicLobeIntegral(const sdb::Material& m, const dvec2& a, const AnisotropicFrame& f, const dvec3& wo,
                              int n, const Radiance& radiance) {
  const double cosO = glm::dot(wo, f.n);
  dvec3 sum(0.0);
  for (int i = 0; i < n; ++i) {
    const double q = (i + 0.5) / n;
    const double rho = std::sqrt(q / (1.0 - q));
    for (int j = 0; j < n; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / n;
      const dvec3 h = glm::normalize(a.x * rho * std::cos(phi) * f.t + a.y * rho * std::sin(phi) * f.b + f.n);
      const double oh = glm::dot(wo, h);
      const dvec3 wi = 2.0 * oh * h - wo;
      if (oh <= 0.0 || glm::dot(wi, f.n) <= 0.0) continue;
      const double g2 = 1.0 / (1.0 + anisotropicLambda(wo, f, a) + anisotropicLambda(wi, f, a));
      sum += reflectAt(m, oh) * (g2 * oh * radiance(wi) / (cosO * glm::dot(h, f.n)));
    }
  }
  return sum / double(n) / double(n);
}

// The directional albedo of the anisotropic lobe alone towards ωo (the integral under L = 1).
inline dvec3 anisotropicLobeAlbedo(const sdb::Material& m, const dvec2& a, const AnisotropicFrame& f,
                                   const dvec3& wo, int n) {
  return anisotropicLobeIntegral(m, a, f, wo, n, [](const dvec3&) { return 1.0; });
}

}  // namespace fly::test
