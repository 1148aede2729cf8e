// The GGX (Trowbridge–Reitz) microfacet distribution that fly's glossy lobes share: its normal distribution,
// Smith's masking function and sampling of visible normals, in a local frame whose +z is the macro normal,
// isotropic (one width α) and anisotropic (widths α_x along the frame's +x, α_y along +y).
// Walter, Marschner, Li & Torrance, "Microfacet models for refraction through rough surfaces", EGSR 2007;
// Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2), 2014; Heitz,
// "Sampling the GGX distribution of visible normals", JCGT 7(4), 2018.
#pragma once

#include <algorithm>
#include <cmath>

#include "base/math.h"

namespace fly {

// The normal distribution D(h) at cos θh > 0, with a2 = α² (Walter et al. 2007, eq. 33), 1/sr.
inline float ggxD(float cosH, float a2) {
  const float den = cosH * cosH * (a2 - 1.0f) + 1.0f;
  return a2 / (kPiF * den * den);
}

// Smith's Λ at cos θ > 0, with a2 = α² (Heitz 2014, eq. 72).
inline float ggxLambda(float cosTheta, float a2) {
  const float c2 = cosTheta * cosTheta;
  if (c2 >= 1.0f) return 0.0f;
  return 0.5f * (std::sqrt(1.0f + a2 * (1.0f - c2) / std::max(c2, 1e-12f)) - 1.0f);
}

// Smith's masking G1 = 1 / (1 + Λ) (Heitz 2014, eq. 43; Walter et al. 2007, eq. 34 in closed form).
inline float ggxSmithG1(float cosTheta, float a2) { return 1.0f / (1.0f + ggxLambda(cosTheta, a2)); }

// The anisotropic normal distribution D(h) for h.z > 0, widths ax along +x and ay along +y (Heitz 2014, §5's
// anisotropic GGX; Pharr, Jakob & Humphreys, "Physically Based Rendering", 4th ed., §9.6.1):
// 1 / (π α_x α_y (h_x²/α_x² + h_y²/α_y² + h_z²)²), 1/sr. Equal widths give ggxD(h.z, α²).
inline float ggxDAnisotropic(const vec3& h, float ax, float ay) {
  const float x = h.x / ax;
  const float y = h.y / ay;
  const float den = x * x + y * y + h.z * h.z;
  return 1.0f / (kPiF * ax * ay * den * den);
}

// Smith's Λ for a direction w (w.z > 0) on the anisotropic distribution: the isotropic Λ with the width
// projected on w's azimuth, α(φ)² tan² θ = (α_x² w_x² + α_y² w_y²) / w_z² (Heitz 2014, §5; Pharr et al.,
// 4th ed., §9.6.2).
inline float ggxLambdaAnisotropic(const vec3& w, float ax, float ay) {
  const float z2 = w.z * w.z;
  const float a2Tan2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / std::max(z2, 1e-12f);
  return 0.5f * (std::sqrt(1.0f + a2Tan2) - 1.0f);
}

// A microfacet normal of the anisotropic distribution of normals visible from w (w.z > 0), u ∈ [0, 1)²:
// Heitz 2018, listing 1, which stretches w by (α_x, α_y) to the hemisphere configuration, samples the
// projected hemisphere there and stretches the normal back. Its density is G1(w) max(0, w·h) D(h) / w.z per
// steradian of h.
inline vec3 sampleGgxVisibleNormal(const vec3& w, float ax, float ay, const vec2& u) {
  const vec3 vh = glm::normalize(vec3(ax * w.x, ay * w.y, w.z));
  const float lensq = vh.x * vh.x + vh.y * vh.y;
  const vec3 t1 = lensq > 0.0f ? vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : vec3(1.0f, 0.0f, 0.0f);
  const vec3 t2 = glm::cross(vh, t1);
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * kPiF * u.y;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.0f + vh.z);
  const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * std::sin(phi);
  const vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(vec3(ax * nh.x, ay * nh.y, std::max(1e-6f, nh.z)));
}

// The isotropic case, α_x = α_y = alpha.
inline vec3 sampleGgxVisibleNormal(const vec3& w, float alpha, const vec2& u) {
  return sampleGgxVisibleNormal(w, alpha, alpha, u);
}

// The density per steradian of ωi = reflect(ωo, h) when h is drawn by sampleGgxVisibleNormal from ωo:
// G1(ωo) D(h) / (4 cos θo) (Heitz 2018, eq. 17 with the reflection Jacobian 1 / (4 ωo·h)); wo.z > 0, h.z > 0.
inline float ggxVisibleReflectionPdf(const vec3& wo, const vec3& h, float a2) {
  return ggxD(h.z, a2) * ggxSmithG1(wo.z, a2) / (4.0f * wo.z);
}

// The anisotropic ggxVisibleReflectionPdf: G1(ωo) D(h) / (4 cos θo) with D and Λ of widths (ax, ay).
inline float ggxVisibleReflectionPdfAnisotropic(const vec3& wo, const vec3& h, float ax, float ay) {
  return ggxDAnisotropic(h, ax, ay) / ((1.0f + ggxLambdaAnisotropic(wo, ax, ay)) * 4.0f * wo.z);
}

// The GGX widths (α along the tangent, α along the bitangent) of a lobe of isotropic width α (= glossiness²)
// and the SDB's anisotropy values u, v ∈ [0, 1] (sdb/material.h: the larger, the wider the lobe along that
// axis; equal values are isotropic). Burley's aspect ratio ("Physically-based shading at Disney", SIGGRAPH
// 2012 course notes, §5.4), aspect = √(1 − 0.9 |u − v|): the wider axis gets α / aspect, the narrower
// α · aspect, so α_t α_b = α² (the lobe's solid angle stays about that of the isotropic lobe) and the
// ratio of the widths reaches 1/0.1 = 10 at |u − v| = 1. Shared by the baker (raytracer/bsdf.h) and the GL
// engine's shaders (raster/shaders), which must agree.
inline vec2 ggxAnisotropicAlphas(float alpha, float anisotropyU, float anisotropyV) {
  const float d = std::clamp(anisotropyU - anisotropyV, -1.0f, 1.0f);
  const float aspect = std::sqrt(1.0f - 0.9f * std::abs(d));
  return d >= 0.0f ? vec2(alpha / aspect, alpha * aspect) : vec2(alpha * aspect, alpha / aspect);
}

}  // namespace fly
