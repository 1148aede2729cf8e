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

// (sin x, cos x) for x ∈ [−π/4, π/4] by the minimax polynomials of Cephes' sinf and cosf (Moshier, "Methods
// and Programs for Mathematical Functions", 1989): within a float ulp or two. Several times cheaper than
// libm's sincosf, which must also reduce arbitrary arguments; the warps below call it once per sample.
inline vec2 sinCosQuarterPi(float x) {
  const float z = x * x;
  const float s = x + x * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
  const float c = 1.0f - 0.5f * z +
                  z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
  return vec2(s, c);
}

// (sin 2πu, cos 2πu) for u ∈ [0, 1]: the quadrant q = round(4u), then the series on 2π (u − q/4) ∈
// [−π/4, π/4] (u − q/4 is exact in float) and a rotation by q quarter turns.
inline vec2 sinCosTwoPi(float u) {
  const float q = std::nearbyint(4.0f * u);
  const vec2 sc = sinCosQuarterPi(2.0f * kPiF * (u - 0.25f * q));
  switch (static_cast<int>(q) & 3) {
    case 0:
      return sc;
    case 1:
      return vec2(sc.y, -sc.x);
    case 2:
      return vec2(-sc.x, -sc.y);
    default:
      return vec2(-sc.y, sc.x);
  }
}

// asin y for y ∈ [−1, 1], by Cephes' asinf polynomial (Moshier 1989) on |y| ≤ 1/2 and asin y = π/2 − 2 asin
// √((1 − y) / 2) above: within a few float ulps, without libm's call.
inline float asinApprox(float y) {
  const float a = std::abs(y);
  const bool large = a > 0.5f;
  const float x = large ? std::sqrt(0.5f * (1.0f - a)) : a;
  const float z = x * x;
  const float p =
      x +
      x * z *
          (1.6666752422e-1f +
           z * (7.4953002686e-2f + z * (4.5470025998e-2f + z * (2.4181311049e-2f + z * 4.2163199048e-2f))));
  return std::copysign(large ? 0.5f * kPiF - 2.0f * p : p, y);
}

// atan2(y, x) in (−π, π], by Cephes' atanf polynomial (Moshier 1989) after reducing |y/x| or |x/y| to
// [0, tan(π/8)]: within a few float ulps, without libm's call.
inline float atan2Approx(float y, float x) {
  const float ax = std::abs(x);
  const float ay = std::abs(y);
  // θ ∈ [0, π/2] for (ax, ay), reduced by the octant.
  const bool steep = ay > ax;
  const float num = steep ? ax : ay;
  const float den = steep ? ay : ax;
  if (den == 0.0f) return std::atan2(y, x);  // the origin (and signed zeros) as libm has them
  float t = num / den;                       // [0, 1]
  float base = 0.0f;
  if (t > 0.41421356f) {  // tan(π/8): atan t = π/4 + atan((t − 1) / (t + 1))
    t = (t - 1.0f) / (t + 1.0f);
    base = 0.25f * kPiF;
  }
  const float z = t * t;
  const float p =
      -3.33329491539e-1f + z * (1.99777106478e-1f + z * (-1.38776856032e-1f + z * 8.05374449538e-2f));
  float theta = base + t + t * z * p;
  if (steep) theta = 0.5f * kPiF - theta;
  if (x < 0.0f) theta = kPiF - theta;
  return std::copysign(theta, y);
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
  // φ = π/4 · b/a, or π/2 − π/4 · a/b, whose cosine and sine are the sine and cosine of π/4 · a/b.
  if (a * a > b * b) {
    const vec2 sc = sinCosQuarterPi(0.25f * kPiF * (b / a));
    return a * vec2(sc.y, sc.x);
  }
  return b * sinCosQuarterPi(0.25f * kPiF * (a / b));
}

// Per unit area on the unit disk.
inline constexpr float kUniformDiskPdf = 1.0f / kPiF;

// Uniform over the hemisphere z ≥ 0: z = u.x, φ = 2π u.y (Archimedes: z is uniform on a sphere).
inline vec3 sampleUniformHemisphere(const vec2& u) {
  const float z = u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const vec2 sc = sinCosTwoPi(u.y);
  return vec3(r * sc.y, r * sc.x, z);
}

inline constexpr float kUniformHemispherePdf = 1.0f / (2.0f * kPiF);

// Uniform over the unit sphere: z = 1 − 2u.x, φ = 2π u.y.
inline vec3 sampleUniformSphere(const vec2& u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const vec2 sc = sinCosTwoPi(u.y);
  return vec3(r * sc.y, r * sc.x, z);
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
  const vec2 sc = sinCosTwoPi(u.y);
  return vec3(sinTheta * sc.y, sinTheta * sc.x, 1.0f - w);
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
