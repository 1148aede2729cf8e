// Warps from the unit square [0, 1)² to the domains the integrator samples, each with its density.
//
// Directions are returned in a local frame whose +z is the axis of the domain (the surface normal, the cone's
// axis); Onb carries them to world space. Densities of directions are per steradian, of points per unit area.
// Every warp is continuous and of low distortion, so that stratified (QMC) input stays well stratified.
#pragma once

#include <algorithm>
#include <cmath>

#include "base/math.h"

namespace fly::raytracer {

// An orthonormal, right-handed basis (tangent, bitangent, normal) around a unit normal.
struct Onb {
  vec3 tangent;
  vec3 bitangent;
  vec3 normal;

  vec3 toWorld(const vec3& local) const { return local.x * tangent + local.y * bitangent + local.z * normal; }
  vec3 toLocal(const vec3& world) const {
    return vec3(glm::dot(world, tangent), glm::dot(world, bitangent), glm::dot(world, normal));
  }
};

// The basis around unit n, without a singularity (it jumps where n.z changes sign):
// Duff, Burgess, Christensen, Hery, Kensler, Liani & Villemin, "Building an orthonormal basis, revisited",
// JCGT 6(1), 2017: Frisvad's construction (2012) made branchless with copysign, without his precision loss
// near n = (0, 0, −1).
inline Onb onb(const vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return Onb{vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x), vec3(b, sign + n.y * n.y * a, -n.y),
             n};
}

// 1 − cos θ for an angle θ in radians, as 2 sin²(θ/2): no cancellation for small θ (the sun's half-angle of
// 0.2665° gives 1.0817·10⁻⁵, which 1 − cos θ in float would get wrong by up to 0.3 %).
inline float oneMinusCos(float angleRad) {
  const float s = std::sin(0.5f * angleRad);
  return 2.0f * s * s;
}

// The unit disk by Shirley & Chiu's concentric map ("A low distortion map between disk and square", JGT 2(3),
// 1997), with Cline's single-branch form (Shirley, "Improved code for concentric map", 2011): squares around
// the centre go to rings.
inline vec2 sampleConcentricDisk(const vec2& u) {
  const float a = 2.0f * u.x - 1.0f;
  const float b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return vec2(0.0f);
  float r;
  float phi;
  if (a * a > b * b) {
    r = a;
    phi = 0.25f * kPiF * (b / a);
  } else {
    r = b;
    phi = 0.5f * kPiF - 0.25f * kPiF * (a / b);
  }
  return r * vec2(std::cos(phi), std::sin(phi));
}

// Per unit area on the unit disk.
inline constexpr float kUniformDiskPdf = 1.0f / kPiF;

// Uniform over the hemisphere z ≥ 0: z = u.x, φ = 2π u.y (Archimedes: z is uniform on a sphere).
inline vec3 sampleUniformHemisphere(const vec2& u) {
  const float z = u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPiF * u.y;
  return vec3(r * std::cos(phi), r * std::sin(phi), z);
}

inline constexpr float kUniformHemispherePdf = 1.0f / (2.0f * kPiF);

// Uniform over the unit sphere: z = 1 − 2u.x, φ = 2π u.y.
inline vec3 sampleUniformSphere(const vec2& u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPiF * u.y;
  return vec3(r * std::cos(phi), r * std::sin(phi), z);
}

inline constexpr float kUniformSpherePdf = 1.0f / (4.0f * kPiF);

// Cosine-weighted over the hemisphere z ≥ 0 by Malley's method: a uniform point on the concentric disk lifted
// onto the hemisphere.
inline vec3 sampleCosineHemisphere(const vec2& u) {
  const vec2 d = sampleConcentricDisk(u);
  return vec3(d, std::sqrt(std::max(0.0f, 1.0f - glm::dot(d, d))));
}

// cos θ / π above the surface, 0 below.
inline float cosineHemispherePdf(float cosTheta) {
  return std::max(cosTheta, 0.0f) / kPiF;
}

// Uniform over the cone of directions within θmax of +z, given w_max = 1 − cos θmax (oneMinusCos()): w = 1 −
// cos θ is uniform on [0, w_max] and sin θ = √(w (2 − w)), so that tiny cones (the sun) keep their precision;
// sin θ is never computed as √(1 − cos² θ).
inline vec3 sampleUniformCone(const vec2& u, float oneMinusCosThetaMax) {
  const float w = u.x * oneMinusCosThetaMax;
  const float sinTheta = std::sqrt(std::max(0.0f, w * (2.0f - w)));
  const float phi = 2.0f * kPiF * u.y;
  return vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), 1.0f - w);
}

// 1 / (2π (1 − cos θmax)) inside the cone: the reciprocal of its solid angle.
inline float uniformConePdf(float oneMinusCosThetaMax) {
  return 1.0f / (2.0f * kPiF * oneMinusCosThetaMax);
}

// Barycentric coordinates (b0, b1, b2) of a point uniform in area over a triangle, by Heitz's low-distortion
// map
// ("A low-distortion map between triangle and square", Unity Technologies tech. report, 2019): the square's
// diagonal u.x = u.y goes to the median from the vertex of b2, each half to a half of the triangle, linearly.
inline vec3 sampleUniformTriangle(const vec2& u) {
  float b0;
  float b1;
  if (u.y > u.x) {
    b0 = 0.5f * u.x;
    b1 = u.y - b0;
  } else {
    b1 = 0.5f * u.y;
    b0 = u.x - b1;
  }
  return vec3(b0, b1, 1.0f - b0 - b1);
}

// Per unit area on a triangle of the given area (square metres).
inline float uniformTrianglePdf(float area) {
  return 1.0f / area;
}

}  // namespace fly::raytracer
