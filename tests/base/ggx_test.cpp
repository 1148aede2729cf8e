// The GGX functions of base/ggx.h against their definitions: the anisotropic widths from the SDB's
// anisotropy, the anisotropic D and Λ reducing to the isotropic ones at equal widths, D's projected area and
// the visible normals' density integrating to 1 by quadrature (which checks Λ against D: the distribution of
// visible normals is normalised exactly when Λ is Smith's for that D, Heitz 2014).
#include "base/ggx.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace fly {
namespace {

// Directions of the upper hemisphere at polar angle θ and azimuth φ.
vec3 direction(double thetaRad, double phiRad) {
  return vec3(float(std::sin(thetaRad) * std::cos(phiRad)), float(std::sin(thetaRad) * std::sin(phiRad)),
              float(std::cos(thetaRad)));
}

// ∫ g(h) dω over the upper hemisphere by the midpoint rule in (v, φ) with cos θ = 1 − v², dω = 2v dv dφ:
// cells crowd towards the pole, where the narrow lobes of this test live.
template <class F>
double hemisphereIntegral(F g, int nv = 4000, int nphi = 512) {
  double sum = 0.0;
  for (int i = 0; i < nv; ++i) {
    const double v = (i + 0.5) / nv;
    const double cosTheta = 1.0 - v * v;
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    for (int j = 0; j < nphi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / nphi;
      const vec3 h(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)), float(cosTheta));
      sum += double(g(h)) * 2.0 * v;
    }
  }
  return sum * (1.0 / nv) * (2.0 * kPi / nphi);
}

TEST(Ggx, AnisotropicAlphasFollowBurleysAspectRatio) {
  const float alpha = 0.35f * 0.35f;
  // Equal values: isotropic.
  for (float u : {0.0f, 0.3f, 1.0f}) {
    const vec2 a = ggxAnisotropicAlphas(alpha, u, u);
    EXPECT_FLOAT_EQ(a.x, alpha);
    EXPECT_FLOAT_EQ(a.y, alpha);
  }
  // The brushed-metal preset (0.6, 0.1): aspect = √(1 − 0.9 · 0.5) = √0.55, wider along U.
  const vec2 brushed = ggxAnisotropicAlphas(alpha, 0.6f, 0.1f);
  EXPECT_NEAR(brushed.x, alpha / std::sqrt(0.55f), 1e-6f);
  EXPECT_NEAR(brushed.y, alpha * std::sqrt(0.55f), 1e-6f);
  EXPECT_NEAR(brushed.x * brushed.y, alpha * alpha, 1e-7f);  // the product stays α²
  // Swapping U and V swaps the widths.
  const vec2 swapped = ggxAnisotropicAlphas(alpha, 0.1f, 0.6f);
  EXPECT_FLOAT_EQ(swapped.x, brushed.y);
  EXPECT_FLOAT_EQ(swapped.y, brushed.x);
  // |u − v| = 1: aspect √0.1, a ratio of 10; differences beyond [−1, 1] are clamped.
  const vec2 extreme = ggxAnisotropicAlphas(alpha, 1.0f, 0.0f);
  EXPECT_NEAR(extreme.x / extreme.y, 10.0f, 1e-4f);
  const vec2 beyond = ggxAnisotropicAlphas(alpha, 3.0f, -2.0f);
  EXPECT_FLOAT_EQ(beyond.x, extreme.x);
  EXPECT_FLOAT_EQ(beyond.y, extreme.y);
}

// Within float rounding: the isotropic D's denominator cos²θ (α² − 1) + 1 cancels near the pole, which costs
// it a relative error of up to a few ε / α² there (3·10⁻⁴ at α = 0.01); the anisotropic form has no such
// cancellation.
TEST(Ggx, EqualWidthsReduceToTheIsotropicFunctions) {
  constexpr float kEps = 0x1p-23f;
  for (float alpha : {0.01f, 0.1225f, 0.5f, 1.0f}) {
    const float a2 = alpha * alpha;
    const float rel = 2e-5f + 4.0f * kEps / a2;
    for (double thetaDeg : {0.0, 10.0, 45.0, 80.0, 89.5}) {
      for (double phiDeg : {0.0, 33.0, 90.0, 200.0}) {
        const vec3 w = direction(thetaDeg * kPi / 180.0, phiDeg * kPi / 180.0);
        EXPECT_NEAR(ggxDAnisotropic(w, alpha, alpha), ggxD(w.z, a2), rel * ggxD(w.z, a2) + 1e-6f)
            << alpha << " " << thetaDeg;
        EXPECT_NEAR(ggxLambdaAnisotropic(w, alpha, alpha), ggxLambda(w.z, a2),
                    2e-5f * ggxLambda(w.z, a2) + 1e-6f)
            << alpha << " " << thetaDeg;
        const vec3 h = direction(0.3 * thetaDeg * kPi / 180.0, (phiDeg + 17.0) * kPi / 180.0);
        if (w.z > 0.05f) {
          EXPECT_NEAR(ggxVisibleReflectionPdfAnisotropic(w, h, alpha, alpha),
                      ggxVisibleReflectionPdf(w, h, a2), rel * ggxVisibleReflectionPdf(w, h, a2));
        }
      }
    }
  }
  // The sampler of visible normals with equal widths is the isotropic one, bit for bit.
  const vec3 w = glm::normalize(vec3(0.4f, -0.2f, 0.8f));
  for (const vec2& u : {vec2(0.1f, 0.2f), vec2(0.7f, 0.9f), vec2(0.5f, 0.01f)}) {
    const vec3 a = sampleGgxVisibleNormal(w, 0.3f, 0.3f, u);
    const vec3 b = sampleGgxVisibleNormal(w, 0.3f, u);
    EXPECT_EQ(a, b);
  }
}

// The anisotropic D stretches the isotropic one: along +x it is the isotropic D of width α_x, along +y that
// of width α_y (the slopes' distribution scaled per axis).
TEST(Ggx, AnisotropicDIsTheIsotropicDAlongEachAxis) {
  const float ax = 0.4f, ay = 0.08f;
  for (double thetaDeg : {5.0, 20.0, 60.0}) {
    const double t = thetaDeg * kPi / 180.0;
    // D_aniso(θ, φ = 0) = (α_x / α_y) · ... : with the isotropic form at α = α_x, times α_x / α_y.
    EXPECT_NEAR(ggxDAnisotropic(direction(t, 0.0), ax, ay), ggxD(float(std::cos(t)), ax * ax) * ax / ay,
                1e-4f * ggxD(float(std::cos(t)), ax * ax) * ax / ay);
    EXPECT_NEAR(ggxDAnisotropic(direction(t, kPi / 2), ax, ay), ggxD(float(std::cos(t)), ay * ay) * ay / ax,
                1e-4f * ggxD(float(std::cos(t)), ay * ay) * ay / ax);
    EXPECT_NEAR(ggxLambdaAnisotropic(direction(t, 0.0), ax, ay), ggxLambda(float(std::cos(t)), ax * ax),
                1e-5f);
    EXPECT_NEAR(ggxLambdaAnisotropic(direction(t, kPi / 2), ax, ay), ggxLambda(float(std::cos(t)), ay * ay),
                1e-5f);
  }
}

// ∫ D(h) cos θh dω = 1 (the microfacets' projected area is the macro surface's), and for every ωo the density
// of visible normals G1(ωo) max(0, ωo·h) D(h) / cos θo integrates to 1.
TEST(Ggx, AnisotropicDensitiesIntegrateToOne) {
  struct Widths {
    float ax, ay;
  };
  const std::vector<Widths> cases = {{0.1652f, 0.0908f}, {0.5f, 0.05f}, {0.05f, 0.3f}, {1.2f, 0.4f}};
  for (const Widths& c : cases) {
    const double projected =
        hemisphereIntegral([&](const vec3& h) { return ggxDAnisotropic(h, c.ax, c.ay) * h.z; });
    EXPECT_NEAR(projected, 1.0, 2e-3) << c.ax << " × " << c.ay;
    for (double thetaDeg : {0.0, 40.0, 75.0, 88.0}) {
      for (double phiDeg : {0.0, 30.0, 90.0}) {
        const vec3 wo = direction(thetaDeg * kPi / 180.0, phiDeg * kPi / 180.0);
        const float g1 = 1.0f / (1.0f + ggxLambdaAnisotropic(wo, c.ax, c.ay));
        const double visible = hemisphereIntegral(
            [&](const vec3& h) {
              return g1 * std::max(0.0f, glm::dot(wo, h)) * ggxDAnisotropic(h, c.ax, c.ay) / wo.z;
            },
            2000, 256);
        EXPECT_NEAR(visible, 1.0, 4e-3)
            << c.ax << " × " << c.ay << ", θo " << thetaDeg << "°, φo " << phiDeg << "°";
      }
    }
  }
}

// Extreme widths and directions give finite, non-negative values.
TEST(Ggx, AnisotropicFunctionsStayFinite) {
  for (const vec2& a : {vec2(1e-3f, 3.2e-4f), vec2(3.2f, 0.32f), vec2(1e-3f, 3.2f)}) {
    for (const vec3& w :
         {vec3(0, 0, 1), glm::normalize(vec3(1, 0, 1e-6f)), glm::normalize(vec3(1, 1, 1e-3f))}) {
      EXPECT_TRUE(std::isfinite(ggxDAnisotropic(w, a.x, a.y)));
      EXPECT_GE(ggxDAnisotropic(w, a.x, a.y), 0.0f);
      EXPECT_TRUE(std::isfinite(ggxLambdaAnisotropic(w, a.x, a.y)));
      EXPECT_GE(ggxLambdaAnisotropic(w, a.x, a.y), 0.0f);
      for (const vec2& u : {vec2(0.0f), vec2(0.999f, 0.5f), vec2(0.5f, 0.999f)}) {
        const vec3 h = sampleGgxVisibleNormal(w, a.x, a.y, u);
        EXPECT_TRUE(isFinite(h));
        EXPECT_NEAR(glm::length(h), 1.0f, 1e-5f);
        EXPECT_GT(h.z, 0.0f);
      }
    }
  }
}

}  // namespace
}  // namespace fly
