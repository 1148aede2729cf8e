// The scattering function of a TraceMaterial (the SDB's realistic material): Lambertian diffuse, specular or
// glossy reflection, and thin-walled transmission, with the SDB's energy rule evaluated at the actual angle.
//
// Energy rule (sdb/material.h), per channel, for light arriving at θ from the normal:
//   R(θ) = r·F(θ),  T(θ) = (1 − R(θ))·t,  D(θ) = (1 − R(θ) − T(θ))·d = (1 − R(θ))·(1 − t)·d,
// r, t, d the reflection, transmission and diffuse colours; F Schlick's Fresnel term with F0 = ((ior − 1) /
// (ior + 1))² ("fresnel" materials; Schlick, "An inexpensive BRDF model for physically-based rendering",
// Computer Graphics Forum 13(3), 1994, eq. 24) or F ≡ 1 (uniform reflection). R is kept per channel as
// R(θ) = R0 + (R90 − R0)(1 − cos θ)⁵ (R0 = r F0, R90 = r), the shape that a metalness mix keeps
// (TraceMaterial::metalness: R0, R90 mixed with the metal's colour, t and d scaled by 1 − m). In what follows
// r F(θ) stands for R(θ). TraceMaterial::diffuse holds D(0) (the rule at normal incidence), so the
// constructor recovers (1 − t)·d = diffuse / (1 − R0).
//
// Lobes, in a local frame whose +z is the surface normal on the side of ωo (the direction towards the
// sensor; ωi towards the light):
//   - Diffuse: f = (1 − t)d/π · (1 − R(θi)) (1 − R(θo)) / (1 − R̄), R̄ = 2∫₀¹ R(μ) μ dμ = R0 + (R90 −
//     R0)/21. Symmetric in ωi, ωo, and its albedo for light from θi is exactly D(θi): the
//     coupling of Kelemen & Szirmay-Kalos ("A microfacet based coupled specular-matte BRDF model with
//     importance sampling", Eurographics 2001 short papers), with Schlick's F in place of the microfacet
//     albedo.
//   - Reflection, glossiness g = 0 (or α = g² < kSmoothAlpha): a perfect mirror of weight R(θ). Otherwise GGX
//     (Walter, Marschner, Li & Torrance, "Microfacet models for refraction through rough surfaces", EGSR
//     2007) with α = g², the height-correlated Smith masking-shadowing G2 (Heitz, "Understanding the masking-
//     shadowing function in microfacet-based BRDFs", JCGT 3(2), 2014, eq. 99), f = r F(ωo·h) D(h) G2 /
//     (4 cos θo cos θi); its albedo is close to R(θ) for smooth lobes and below it for rough ones (single
//     scattering loses energy), sampled by the distribution of visible normals (Heitz, "Sampling the GGX
//     distribution of visible normals", JCGT 7(4), 2018).
//     Anisotropic (anisotropyU ≠ anisotropyV, sdb/material.h): the same lobe with the GGX widths α_U, α_V of
//     ggxAnisotropicAlphas (base/ggx.h: α / a and α a, a = √(1 − 0.9 |u − v|), so α_U α_V = α²) along the
//     axes U, V: the local +x (the surface's tangent, when the integrator builds the frame from the tangents:
//     surface_point.h, shadingFrameAt) turned by anisotropyRotationRad towards +y (the bitangent), and V a
//     further quarter turn. D and Λ are the anisotropic ones (Λ with the width projected on a direction's
//     azimuth), the visible normals are sampled by Heitz 2018's stretch by (α_U, α_V); eval, pdf and sample
//     stay consistent and reciprocal, and equal values are the isotropic lobe exactly. A mirror (α below
//     kSmoothAlpha) stays a mirror, and frosted transmission stays isotropic.
//   - Transmission: thin-walled, as daylighting tools model a window pane (Radiance's `glass` material:
//     Ward, "The RADIANCE lighting simulation and rendering system", SIGGRAPH 1994): light passes straight
//     through with no refraction offset. Clear glass transmits base/clear_pane.h's T(θ): a slab of two
//     Fresnel faces with absorption and internal reflections, T(0) = t (1 − r F0) (the energy rule at normal
//     incidence), never above the rule's t (1 − r F(θ)); with uniform reflection t (1 − r). Frosted glass
//     (transmissionGlossiness g_t > 0) scatters into the GGX lobe of α = g_t² mirrored through the surface
//     plane around the straight-through direction (the thin-surface transmission of Burley, "Extending the
//     Disney BRDF to a BSDF with integrated subsurface scattering", SIGGRAPH 2015 course notes, §4):
//     f = t (1 − r F(ωo·h)) D(h) G2 / (4 |cos θo| |cos θi|), h = normalize(ωo + ωi'), ωi' = ωi mirrored to
//     ωo's side.
//
// Faces: the front face (or either face of a double-sided material) has every lobe; the back face of a
// one-sided material transmits only (the rule's reflected and diffuse shares are absorbed there): a pane
// passes light both ways, and glTF culls one-sided back faces.
//
// Sampling chooses one lobe with probability proportional to its estimated albedo at θo (channel mean of
// D(θo), R(θo), T(θo)) and samples it; eval() and pdf() cover the non-delta lobes (the mixture's density,
// for multiple importance sampling with light sampling); the mirror and clear transmission are deltas.
//
// Coverage c (glTF alpha, partial coverage): the surface is there with probability c. Every lobe above is
// scaled by c, and a fraction 1 − c passes straight through, unbent and without Fresnel, as the light between
// the fibres of a curtain: the straight-through transmittance is (1 − c) + c T_clear(θ), one delta lobe.
//
// Measured BRDFs (a tabulated table or the car-paint model, TraceMaterial::isMeasured()) replace the analytic
// lobes: the front face (or either face of a double-sided material) scatters by the MeasuredLobe alone, which
// eval(), pdf() and sample() then forward to, and the back face of a one-sided measured material is black (a
// measured paint is opaque). The energy rule does not apply to them: a measured table carries its own balance
// of diffuse and glossy reflection (the baker scales a table that reflects more than it receives down to an
// albedo of 1: rdb::TraceBrdfTable::scale), and the car-paint model conserves energy by construction.
// Coverage applies as above.
//
// A Bsdf holds one point's colours: the integrator builds one per material, or per ray hit for materials that
// vary over their surface (raytracer/surface_point.h: textured anisotropy and rotation included).
#pragma once

#include <algorithm>
#include <cstdint>

#include "base/clear_pane.h"
#include "base/color.h"
#include "base/math.h"
#include "raytracer/measured_lobe.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// GGX α below which a lobe is a delta (mirror or clear transmission): at α = 10⁻³ (glossiness 0.032) the lobe
// is 0.06° wide, far narrower than the sun (0.53°), and its density overflows float precision (pbrt-v4's
// TrowbridgeReitzDistribution::EffectivelySmooth uses the same bound). sdb::kSmoothAlpha, which the raster
// engine's clear glass follows, is the same (raytracer/ may not include sdb/; bsdf_test.cpp checks).
inline constexpr float kSmoothAlpha = 1e-3f;

// Schlick's approximation, cos θ clamped to [0, 1].
inline float schlickFresnel(float cosTheta, float f0) {
  const float m = 1.0f - std::clamp(cosTheta, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (1.0f - f0) * m2 * m2 * m;
}

class Bsdf {
 public:
  enum class Lobe : uint8_t {
    kNonDelta,  // diffuse, glossy reflection or frosted transmission: eval() and pdf() describe it
    kMirror,    // perfect specular reflection
    kStraight,  // clear thin-walled transmission, ωi = −ωo
  };

  struct Sample {
    vec3 wi{0.0f};     // local, unit
    Rgb weight{0.0f};  // f |cos θi| / pdf; for a delta lobe its reflectance or transmittance / probability
    float pdf = 0.0f;  // per steradian (non-delta), or the probability of choosing the delta lobe
    Lobe lobe = Lobe::kNonDelta;
  };

  // frontFace: false for the back face of a one-sided material (transmission only). coverage in [0, 1].
  // measured: the lobe of m's measured BRDF, which must outlive the Bsdf; when m has one but `measured` is
  // null, the analytic parameters stand in for it (as in engines without measured BRDFs).
  Bsdf(const rdb::TraceMaterial& m, bool frontFace, float coverage = 1.0f, const MeasuredLobe* measured = nullptr);

  // f(ωo, ωi) of the non-delta lobes in 1/sr, local directions with wo.z > 0; ωi on either side.
  Rgb eval(const vec3& wo, const vec3& wi) const;
  // The part of eval() that the glossy reflection lobe contributes (0 for other lobes and measured BRDFs):
  // what reflection fog fades (raytracer/integrator.h).
  Rgb evalReflection(const vec3& wo, const vec3& wi) const;
  // Density per steradian with which sample() draws ωi by a non-delta lobe (times that lobe's probability).
  float pdf(const vec3& wo, const vec3& wi) const;
  // One direction: uLobe chooses the lobe, u the direction in it. False when nothing scatters (black, or a
  // direction below the surface from a glossy lobe's tail).
  bool sample(const vec3& wo, float uLobe, const vec2& u, Sample& out) const;

  // Straight-through transmittance at |cos θ| = absCos: T(θ) for clear glass (base/clear_pane.h), 0
  // otherwise. The shadow rays of light sampling pass clear glass with this factor.
  Rgb straightTransmittance(float absCos) const {
    const Rgb clear = clearTransmission_ ? pane_.at(absCos) : Rgb(0.0f);
    return Rgb(1.0f - coverage_) + coverage_ * clear;
  }
  // The albedo for light leaving towards ωo, cos θo = cosO (exact for the diffuse, mirror and clear lobes, an
  // estimate for glossy ones): the lobe weights and Russian roulette's survival guide. A Lambertian Bsdf
  // without any reflection colour has lambertAlbedo() at every angle.
  Rgb albedo(float cosO) const { return constantAlbedo_ ? diffuseKd_ : albedoAt(cosO); }

  bool isBlack() const {
    return covered() && measured_ == nullptr && !hasDiffuse_ && !hasReflection_ && !hasTransmission_;
  }
  // Diffuse only (no reflection, no transmission, full coverage): then f = lambertAlbedo() / π, sample()
  // draws cos θ / π, its weight is lambertAlbedo(), and uLobe is not used. The integrator's fast path for the
  // common case, asked at every vertex and light sample: kept from the constructor.
  bool isLambertian() const { return lambertian_; }
  const Rgb& lambertAlbedo() const { return diffuseKd_; }
  // Whether eval() can be non-zero: light sampling is pointless otherwise. Kept from the constructor.
  bool hasNonDelta() const { return nonDelta_; }
  // Whether non-delta light arrives from below the surface (frosted transmission).
  bool hasNonDeltaTransmission() const { return coverage_ > 0.0f && frostedTransmission(); }
  // Whether light passes straight through (clear glass or partial coverage).
  bool passesStraight() const { return clearTransmission_ || !covered(); }
  // Clear glass: straight-through transmission by the material (not by partial coverage).
  bool hasClearTransmission() const { return clearTransmission_; }

 private:
  // The constructor's work; the constructor then keeps the flags below.
  void init(const rdb::TraceMaterial& m, bool frontFace, const MeasuredLobe* measured);
  Rgb albedoAt(float cosO) const;
  // The reflect input R(θ) = R0 + (R90 − R0)(1 − cos θ)⁵, cos θ clamped to [0, 1].
  Rgb reflectance(float cosTheta) const {
    const float m = 1.0f - std::clamp(cosTheta, 0.0f, 1.0f);
    const float m2 = m * m;
    return r0_ + (r90_ - r0_) * (m2 * m2 * m);
  }
  bool frostedTransmission() const { return hasTransmission_ && !clearTransmission_; }
  // The transmission lobe's albedo towards cos θo, before coverage: clear glass's T(θo), or frosted glass's
  // t (1 − r F(θo)).
  Rgb transmissionAlbedo(float cosO, const Rgb& reflected) const {
    return clearTransmission_ ? pane_.at(cosO) : transmission_ * (Rgb(1.0f) - reflected);
  }
  // The glossy reflection lobe's f for wi above the surface, before coverage.
  Rgb glossyReflection(const vec3& wo, const vec3& wi) const;
  bool covered() const { return coverage_ >= 1.0f; }
  // The glossy reflection lobe's D G2 / (4 cos θo cos θi) and its sampling density per steradian (ωo, ωi
  // above the surface), isotropic or anisotropic; h receives the half vector.
  float reflectionLobe(const vec3& wo, const vec3& wi, vec3& h, float& pdf) const;
  // A local direction in the anisotropy's frame, whose +x is the U axis (the local +x turned by the rotation
  // towards +y), and back.
  vec3 toLobe(const vec3& v) const {
    return vec3(rotationCos_ * v.x + rotationSin_ * v.y, rotationCos_ * v.y - rotationSin_ * v.x, v.z);
  }
  vec3 fromLobe(const vec3& v) const {
    return vec3(rotationCos_ * v.x - rotationSin_ * v.y, rotationSin_ * v.x + rotationCos_ * v.y, v.z);
  }
  // Lobe choice probabilities at cos θo: diffuse (or the measured lobe), reflection, transmission, passing
  // uncovered (sum 1 unless black).
  vec4 lobeProbabilities(float cosO) const;

  Rgb diffuseKd_{0.0f};     // (1 − t)·d: the diffuse colour before the rule's (1 − R) factor
  Rgb diffuseNorm_{0.0f};   // 1 / (1 − r F̄), 0 where the diffuse share is 0
  Rgb r0_{0.0f};            // R0, [0, 1]
  Rgb r90_{0.0f};           // R90 ≥ R0, [0, 1]
  Rgb transmission_{0.0f};  // t, [0, 1] (after the metalness mix)
  float alphaR_ = 0.0f;  // GGX α of reflection, 0 = mirror
  // Anisotropic reflection (α_R > 0 and unequal widths): the GGX widths along the U and V axes
  // (ggxAnisotropicAlphas), and the rotation of U from the local +x towards +y.
  bool anisotropic_ = false;
  float alphaU_ = 0.0f;
  float alphaV_ = 0.0f;
  float rotationCos_ = 1.0f;
  float rotationSin_ = 0.0f;
  float alphaT_ = 0.0f;  // GGX α of transmission, 0 = clear
  bool hasDiffuse_ = false;
  bool hasReflection_ = false;
  bool hasTransmission_ = false;
  bool clearTransmission_ = false;
  ClearPane pane_;  // clear glass's T(θ)
  float coverage_ = 1.0f;
  const MeasuredLobe* measured_ = nullptr;  // replaces the lobes above where set
  bool lambertian_ = false;                 // isLambertian()
  bool nonDelta_ = false;                   // hasNonDelta()
  bool constantAlbedo_ = false;             // Lambertian with r = 0: albedo() is diffuseKd_ exactly
};

// The diffuse albedo D(0) of the energy rule at normal incidence (sdb::applyEnergyRule, with Fresnel
// reflection r F0) for m's diffuseColor, reflection and transmission, each clamped to [0, 1], and its
// metalness mix: what TraceMaterial::diffuse holds for constant colours, evaluated for a point's textured
// ones.
Rgb normalIncidenceDiffuse(const rdb::TraceMaterial& m);

}  // namespace fly::raytracer
