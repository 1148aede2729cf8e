#include "raytracer/warp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "chi2.h"
#include "raytracer/sampler.h"

namespace fly::raytracer {
namespace {

constexpr uint32_t kSampleCount = 1'000'000;
const double kSunHalfAngleRad = degToRad(0.2665);

// Directions binned on the equal-area sphere chart, 32 cells in z (edges at z = −1 + k/16) by 64 in φ.
test::Chi2Result directionChi2(const std::function<vec3(vec2)>& warp,
                               const std::function<double(dvec3)>& pdf) {
  test::Chi2Grid grid(32, 64);
  test::forRandomSquarePoints(kSampleCount, 1, [&](vec2 u) {
    const dvec2 st = test::sphereChart(warp(u));
    grid.add(st.x, st.y);
  });
  return grid.test(
      [&](double s, double t) { return pdf(test::sphereChartDirection(s, t)) * test::kSphereChartJacobian; });
}

TEST(Warp, OnbIsOrthonormalAndRightHanded) {
  std::vector<vec3> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0, 0.0f, -1.0f + 1e-7f}};
  test::forRandomSquarePoints(1000, 2, [&](vec2 u) { normals.push_back(sampleUniformSphere(u)); });
  normals.push_back(glm::normalize(vec3(1e-4f, -2e-4f, -1.0f)));
  for (const vec3& raw : normals) {
    const vec3 n = glm::normalize(raw);
    const Onb b = onb(n);
    EXPECT_NEAR(glm::length(b.tangent), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::length(b.bitangent), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(b.tangent, b.bitangent), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(b.tangent, n), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(b.bitangent, n), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(glm::cross(b.tangent, b.bitangent) - n), 0.0f, 1e-6f);
    const vec3 v(0.3f, -0.5f, 0.8f);
    EXPECT_NEAR(glm::length(b.toLocal(b.toWorld(v)) - v), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(b.toWorld(vec3(0, 0, 1)) - n), 0.0f, 1e-7f);
  }
}

TEST(Warp, UniformHemisphereChi2) {
  test::expectFits("uniform hemisphere", directionChi2(sampleUniformHemisphere, [](dvec3 d) {
               return d.z >= 0.0 ? static_cast<double>(kUniformHemispherePdf) : 0.0;
             }));
}

TEST(Warp, CosineHemisphereChi2) {
  test::expectFits("cosine hemisphere", directionChi2(sampleCosineHemisphere, [](dvec3 d) {
               return static_cast<double>(cosineHemispherePdf(static_cast<float>(d.z)));
             }));
}

TEST(Warp, UniformSphereChi2) {
  test::expectFits("uniform sphere", directionChi2(sampleUniformSphere,
                                             [](dvec3) { return static_cast<double>(kUniformSpherePdf); }));
}

TEST(Warp, UniformConeChi2) {
  // Cones whose edge lies on a cell boundary of the chart: cos θmax = 0.875 (29.0°) and −0.25 (104.5°).
  for (float w : {0.125f, 1.25f}) {
    const std::string name = "uniform cone, 1 - cos = " + std::to_string(w);
    test::expectFits(name.c_str(),
               directionChi2(
                   [w](vec2 u) { return sampleUniformCone(u, w); },
                   [w](dvec3 d) { return d.z >= 1.0 - w ? static_cast<double>(uniformConePdf(w)) : 0.0; }));
  }
}

// 1 − cos θ of a unit direction, from its sine: exact for tiny θ, where 1 − z has no digits left.
double oneMinusCosOf(const vec3& d) {
  const double sin2 = static_cast<double>(d.x) * d.x + static_cast<double>(d.y) * d.y;
  return sin2 / (1.0 + static_cast<double>(d.z));
}

TEST(Warp, SunConeChi2) {
  // Chart: s = (1 − cos θ) / (1.25 w_max), t = φ / 2π; dω = d(1 − cos θ) dφ = 1.25 w_max 2π ds dt. Directions
  // outside the cone land in the cells s ≥ 0.8, whose density is 0.
  const float w = oneMinusCos(static_cast<float>(kSunHalfAngleRad));
  test::Chi2Grid grid(40, 40);
  test::forRandomSquarePoints(kSampleCount, 3, [&](vec2 u) {
    const vec3 d = sampleUniformCone(u, w);
    const double phi = std::atan2(static_cast<double>(d.y), static_cast<double>(d.x));
    grid.add(oneMinusCosOf(d) / (1.25 * w), (phi < 0.0 ? phi + 2.0 * kPi : phi) / (2.0 * kPi));
  });
  const double jacobian = 1.25 * w * 2.0 * kPi;
  test::expectFits("sun cone (0.2665 deg)", grid.test([&](double s, double) {
    return s < 0.8 ? static_cast<double>(uniformConePdf(w)) * jacobian : 0.0;
  }));
}

TEST(Warp, SunConeStaysInsideWithExactPdf) {
  const double exactOneMinusCos = 1.0 - std::cos(kSunHalfAngleRad);  // 1.0817·10⁻⁵; double keeps 11 digits
  const float w = oneMinusCos(static_cast<float>(kSunHalfAngleRad));
  EXPECT_NEAR(w / exactOneMinusCos, 1.0, 1e-6);
  EXPECT_NEAR(static_cast<double>(uniformConePdf(w)) * 2.0 * kPi * exactOneMinusCos, 1.0, 1e-6);
  const auto expectInside = [&](vec2 u) {
    const vec3 d = sampleUniformCone(u, w);
    const double angle = std::atan2(
        std::sqrt(static_cast<double>(d.x) * d.x + static_cast<double>(d.y) * d.y), static_cast<double>(d.z));
    ASSERT_LE(angle, kSunHalfAngleRad * (1.0 + 1e-6)) << u.x << " " << u.y;
    ASSERT_NEAR(glm::length(dvec3(d)), 1.0, 1e-6);
  };
  constexpr float kLast = 0x1.fffffep-1f;  // the largest u below 1
  for (float a : {0.0f, 0.5f, kLast}) {
    for (float b : {0.0f, 0.25f, kLast}) expectInside(vec2(a, b));
  }
  test::forRandomSquarePoints(kSampleCount, 4, expectInside);
}

TEST(Warp, ConcentricDiskChi2) {
  // Chart: s = r² / 1.25, t = φ / 2π; dA = r dr dφ = ½ d(r²) dφ = 1.25 π ds dt.
  test::Chi2Grid grid(40, 40);
  test::forRandomSquarePoints(kSampleCount, 5, [&](vec2 u) {
    const dvec2 p(sampleConcentricDisk(u));
    const double phi = std::atan2(p.y, p.x);
    grid.add(glm::dot(p, p) / 1.25, (phi < 0.0 ? phi + 2.0 * kPi : phi) / (2.0 * kPi));
  });
  test::expectFits("concentric disk", grid.test([](double s, double) {
    return s < 0.8 ? static_cast<double>(kUniformDiskPdf) * 1.25 * kPi : 0.0;
  }));
}

TEST(Warp, UniformTriangleChi2) {
  // Chart: the inverse of the square-root parameterisation, s = (1 − b0)² / 1.25, t = b1 / ((1 − b0) 1.25),
  // under which the barycentric area is ½ · 1.25² ds dt; a point with b0 < 0 or b2 < 0 leaves [0, 0.8)².
  test::Chi2Grid grid(40, 40);
  test::forRandomSquarePoints(kSampleCount, 6, [&](vec2 u) {
    const dvec3 b(sampleUniformTriangle(u));
    if (b.y < 0.0) {
      grid.add(-1.0, -1.0);
      return;
    }
    grid.add((1.0 - b.x) * (1.0 - b.x) / 1.25, b.y / ((1.0 - b.x) * 1.25));
  });
  // The reference triangle of the barycentric plane has area ½: density 2.
  test::expectFits("uniform triangle", grid.test([](double s, double t) {
    return s < 0.8 && t < 0.8 ? static_cast<double>(uniformTrianglePdf(0.5f)) * 0.5 * 1.25 * 1.25 : 0.0;
  }));
}

TEST(Warp, PdfsIntegrateToOne) {
  // Over the sphere by the midpoint rule in z (the densities do not depend on φ).
  constexpr int kSteps = 100000;
  double cosine = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double z = -1.0 + (i + 0.5) * 2.0 / kSteps;
    cosine += static_cast<double>(cosineHemispherePdf(static_cast<float>(z))) * (2.0 / kSteps) * 2.0 * kPi;
  }
  EXPECT_NEAR(cosine, 1.0, 1e-6);
  EXPECT_NEAR(static_cast<double>(kUniformHemispherePdf) * 2.0 * kPi, 1.0, 1e-7);
  EXPECT_NEAR(static_cast<double>(kUniformSpherePdf) * 4.0 * kPi, 1.0, 1e-7);
  EXPECT_NEAR(static_cast<double>(kUniformDiskPdf) * kPi, 1.0, 1e-7);
  EXPECT_NEAR(static_cast<double>(uniformTrianglePdf(3.5f)) * 3.5, 1.0, 1e-7);
  // Cones: the solid angle ∫₀^θmax 2π sin θ dθ by the midpoint rule.
  for (double halfAngle : {kSunHalfAngleRad, 0.5, 2.0, kPi}) {
    double solidAngle = 0.0;
    for (int i = 0; i < kSteps; ++i) {
      solidAngle += 2.0 * kPi * std::sin((i + 0.5) * halfAngle / kSteps) * halfAngle / kSteps;
    }
    EXPECT_NEAR(static_cast<double>(uniformConePdf(oneMinusCos(static_cast<float>(halfAngle)))) * solidAngle,
                1.0, 1e-6)
        << halfAngle;
  }
}

// |∂w/∂u × ∂w/∂v| by central differences: the area (or solid angle) that a unit of the square maps to.
template <class Warp>
double jacobian(Warp warp, vec2 u) {
  constexpr float h = 1e-3f;
  const dvec3 du = (dvec3(warp(u + vec2(h, 0))) - dvec3(warp(u - vec2(h, 0)))) / (2.0 * h);
  const dvec3 dv = (dvec3(warp(u + vec2(0, h))) - dvec3(warp(u - vec2(0, h)))) / (2.0 * h);
  return glm::length(glm::cross(du, dv));
}

TEST(Warp, DensityIsTheInverseJacobian) {
  // Away from the maps' kinks: the diagonals of the concentric map, the diagonal u = v of Heitz's map.
  const auto awayFromKinks = [](vec2 u) {
    const float a = std::abs(2.0f * u.x - 1.0f);
    const float b = std::abs(2.0f * u.y - 1.0f);
    return std::abs(a - b) > 0.01f && std::abs(u.x - u.y) > 0.01f;
  };
  const auto disk3 = [](vec2 u) { return vec3(sampleConcentricDisk(u), 0.0f); };
  const auto triangle = [](vec2 u) {  // a right triangle of area ½ in the plane
    const vec3 b = sampleUniformTriangle(u);
    return vec3(b.x, b.y, 0.0f);
  };
  const auto cone = [](vec2 u) { return sampleUniformCone(u, 0.3f); };
  int tested = 0;
  test::forRandomSquarePoints(2000, 7, [&](vec2 r) {
    const vec2 u = 0.02f + 0.96f * r;
    if (!awayFromKinks(u)) return;
    ++tested;
    EXPECT_NEAR(static_cast<double>(kUniformHemispherePdf) * jacobian(sampleUniformHemisphere, u), 1.0, 2e-3);
    EXPECT_NEAR(static_cast<double>(kUniformSpherePdf) * jacobian(sampleUniformSphere, u), 1.0, 2e-3);
    EXPECT_NEAR(static_cast<double>(cosineHemispherePdf(sampleCosineHemisphere(u).z)) *
                    jacobian(sampleCosineHemisphere, u),
                1.0, 2e-3);
    EXPECT_NEAR(static_cast<double>(uniformConePdf(0.3f)) * jacobian(cone, u), 1.0, 2e-3);
    EXPECT_NEAR(static_cast<double>(kUniformDiskPdf) * jacobian(disk3, u), 1.0, 2e-3);
    EXPECT_NEAR(static_cast<double>(uniformTrianglePdf(0.5f)) * jacobian(triangle, u), 1.0, 2e-3);
  });
  EXPECT_GT(tested, 1500);
}

// The series-based sine and cosine that the warps use in place of libm: within 2.5·10⁻⁷ of the double-precision
// values (a couple of float ulps at 1) over the whole turn, quadrant edges included, and exact on the axes.
TEST(Warp, SinCosTwoPiMatchesLibm) {
  double worst = 0.0;
  for (uint32_t k = 0; k <= 1u << 20; ++k) {
    const float u = std::min(static_cast<float>(k) * 0x1p-20f, 0x1.fffffep-1f);
    const vec2 sc = sinCosTwoPi(u);
    const double phi = 2.0 * kPi * static_cast<double>(u);
    worst = std::max({worst, std::abs(sc.x - std::sin(phi)), std::abs(sc.y - std::cos(phi))});
  }
  EXPECT_LT(worst, 2.5e-7);
  EXPECT_EQ(sinCosTwoPi(0.0f), vec2(0.0f, 1.0f));
  EXPECT_EQ(sinCosTwoPi(0.25f), vec2(1.0f, 0.0f));
  EXPECT_EQ(sinCosTwoPi(0.5f), vec2(0.0f, -1.0f));
  EXPECT_EQ(sinCosTwoPi(0.75f), vec2(-1.0f, 0.0f));
  for (float x : {-0.7853982f, -0.3f, 1e-20f, 0.1f, 0.5235988f, 0.7853982f}) {
    EXPECT_NEAR(sinCosQuarterPi(x).x, std::sin(static_cast<double>(x)), 1.5e-7) << x;
    EXPECT_NEAR(sinCosQuarterPi(x).y, std::cos(static_cast<double>(x)), 1.5e-7) << x;
  }
}

// The Cephes-based asin and atan2 that the one-ring sampling and the sky lookup use: within 3·10⁻⁷ rad of the
// double-precision values over their whole domains (every octant of atan2, the seam at ±π included).
TEST(Warp, AsinAndAtan2ApproximationsMatchLibm) {
  double worstAsin = 0.0;
  for (int k = -(1 << 20); k <= 1 << 20; ++k) {
    const float y = static_cast<float>(k) * 0x1p-20f;
    worstAsin = std::max(worstAsin, std::abs(asinApprox(y) - std::asin(static_cast<double>(y))));
  }
  EXPECT_LT(worstAsin, 3e-7);
  EXPECT_EQ(asinApprox(0.0f), 0.0f);
  double worstAtan = 0.0;
  for (uint32_t k = 0; k < 1u << 20; ++k) {
    const double phi = 2.0 * kPi * (static_cast<double>(k) + 0.5) / static_cast<double>(1u << 20) - kPi;
    for (float r : {1e-3f, 1.0f, 7.0f}) {
      const auto x = static_cast<float>(r * std::cos(phi));
      const auto y = static_cast<float>(r * std::sin(phi));
      double err = std::abs(atan2Approx(y, x) - std::atan2(static_cast<double>(y), static_cast<double>(x)));
      worstAtan = std::max(worstAtan, std::min(err, 2.0 * kPi - err));
    }
  }
  EXPECT_LT(worstAtan, 3e-7);
  EXPECT_EQ(atan2Approx(0.0f, 1.0f), 0.0f);
  EXPECT_EQ(atan2Approx(1.0f, 0.0f), 0.5f * kPiF);
  EXPECT_EQ(atan2Approx(0.0f, -1.0f), kPiF);
}

}  // namespace
}  // namespace fly::raytracer
