// The BSDF against analytic answers: albedos by quadrature and by its own sampling, the energy
// rule at every angle, reciprocity, and a chi-square test of sample() against pdf().
#include "raytracer/bsdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "base/ggx.h"
#include "chi2.h"
#include "raytracer/sampler.h"
#include "raytracer/warp.h"
#include "sdb/material.h"

// The baker's bound for a delta lobe is the SDB's, which the raster engine's clear glass follows.
static_assert(fly::raytracer::kSmoothAlpha == fly::sdb::kSmoothAlpha);

namespace fly::raytracer {
namespace {

rdb::TraceMaterial material(const Rgb& diffuse, const Rgb& reflection, float glossiness,
                            const Rgb& transmission = Rgb(0.0f), float transmissionGlossiness = 0.0f,
                            bool fresnel = true, float ior = 1.5f) {
  rdb::TraceMaterial m;
  m.diffuse = diffuse;
  m.reflection = reflection;
  m.reflectionGlossiness = glossiness;
  m.transmission = transmission;
  m.transmissionGlossiness = transmissionGlossiness;
  m.fresnel = fresnel;
  m.ior = ior;
  return m;
}

// m with anisotropy (u, v) rotated by rotationRad.
rdb::TraceMaterial anisotropic(rdb::TraceMaterial m, float u, float v, float rotationRad = 0.0f) {
  m.anisotropyU = u;
  m.anisotropyV = v;
  m.anisotropyRotationRad = rotationRad;
  return m;
}

// A metal of white uniform reflection (F ≡ 1, no diffuse): its one lobe is the GGX lobe alone.
rdb::TraceMaterial whiteMetal(float glossiness, float u = 0.0f, float v = 0.0f, float rotationRad = 0.0f) {
  return anisotropic(material(Rgb(0.0f), Rgb(1.0f), glossiness, Rgb(0.0f), 0.0f, false), u, v, rotationRad);
}

// v turned by angle a about +z.
vec3 turned(const vec3& v, float a) {
  return vec3(std::cos(a) * v.x - std::sin(a) * v.y, std::sin(a) * v.x + std::cos(a) * v.y, v.z);
}

// ∫ f(ωo, ωi) cos θi dωi over the upper hemisphere by quadrature over the half vector h (dωi = 4 (ωo·h) dωh),
// midpoints in (x, φ) with tan θh = width · x / (1 − x): a glossy lobe's half vectors lie within a few of its
// GGX widths of the normal whatever ωo, and there the cells are finest; `width` is the lobe's narrowest.
double halfVectorQuadratureAlbedo(const Bsdf& b, const vec3& wo, double width, int nx = 400, int nphi = 512) {
  double sum = 0.0;
  for (int i = 0; i < nx; ++i) {
    const double x = (i + 0.5) / nx;
    const double tanH = width * x / (1.0 - x);
    const double thetaH = std::atan(tanH);
    const double dThetaDx = width / ((1.0 - x) * (1.0 - x) * (1.0 + tanH * tanH));
    for (int j = 0; j < nphi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / nphi;
      const vec3 h(float(std::sin(thetaH) * std::cos(phi)), float(std::sin(thetaH) * std::sin(phi)),
                   float(std::cos(thetaH)));
      const float oh = glm::dot(wo, h);
      if (!(oh > 0.0f)) continue;
      const vec3 wi = 2.0f * oh * h - wo;
      if (!(wi.z > 0.0f)) continue;
      sum += double(maxComponent(b.eval(wo, wi))) * wi.z * 4.0 * oh * std::sin(thetaH) * dThetaDx;
    }
  }
  return sum * (1.0 / nx) * (2.0 * kPi / nphi);
}

float schlick(float cosTheta, float ior) {
  const float f0 = std::pow((ior - 1.0f) / (ior + 1.0f), 2.0f);
  return f0 + (1.0f - f0) * std::pow(1.0f - cosTheta, 5.0f);
}

vec3 outgoing(float cosTheta) {
  return vec3(std::sqrt(1.0f - cosTheta * cosTheta), 0.0f, cosTheta);
}

// ∫ f(ωo, ωi) |cos θi| dωi over the whole sphere by the midpoint rule in (cos θi, φ): exact enough for the
// diffuse and wide lobes (the integrand is smooth), not for narrow ones.
dvec3 quadratureAlbedo(const Bsdf& b, const vec3& wo, int n = 400) {
  dvec3 sum(0.0);
  for (int i = 0; i < 2 * n; ++i) {
    const double mu = -1.0 + (i + 0.5) / n;
    const double s = std::sqrt(1.0 - mu * mu);
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = kPi * (j + 0.5) / n;
      const vec3 wi(static_cast<float>(s * std::cos(phi)), static_cast<float>(s * std::sin(phi)),
                    static_cast<float>(mu));
      sum += dvec3(b.eval(wo, wi)) * std::abs(mu);
    }
  }
  return sum * (1.0 / n) * (kPi / n);
}

// The mean and standard error of sample()'s weights (delta lobes included): an unbiased estimate of the albedo.
struct SampledAlbedo {
  dvec3 mean{0.0};
  dvec3 stdError{0.0};
  double failedFraction = 0.0;
};
SampledAlbedo sampledAlbedo(const Bsdf& b, const vec3& wo, uint32_t count = 200'000) {
  dvec3 sum(0.0);
  dvec3 sum2(0.0);
  uint32_t failed = 0;
  RandomSampler sampler(7);
  for (uint32_t i = 0; i < count; ++i) {
    sampler.startSample(i);
    const float uLobe = sampler.next1D();
    const vec2 u = sampler.next2D();
    Bsdf::Sample s;
    if (!b.sample(wo, uLobe, u, s)) {
      ++failed;
      continue;
    }
    EXPECT_TRUE(isFinite(s.weight)) << i;
    sum += dvec3(s.weight);
    sum2 += dvec3(s.weight) * dvec3(s.weight);
  }
  SampledAlbedo r;
  r.mean = sum / double(count);
  r.stdError = glm::sqrt(glm::max(sum2 / double(count) - r.mean * r.mean, dvec3(0.0)) / double(count));
  r.failedFraction = double(failed) / count;
  return r;
}

TEST(Bsdf, LambertianAlbedoIsTheDiffuseColour) {
  const Rgb diffuse(0.8f, 0.5f, 0.2f);
  const Bsdf b(material(diffuse, Rgb(0.0f), 0.0f), true);
  for (float cosO : {1.0f, 0.5f, 0.05f}) {
    const dvec3 a = quadratureAlbedo(b, outgoing(cosO));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], diffuse[c], 1e-4) << cosO;
    EXPECT_NEAR(b.eval(outgoing(cosO), vec3(0, 0, 1)).g, 0.5f / kPiF, 1e-7f);
  }
}

// The integrator's fast path for diffuse-only materials relies on these: eval() is ρ/π at every angle, and
// sample() draws cos θ / π with weight ρ, whatever uLobe.
TEST(Bsdf, LambertianFastPathAgreesWithEvalAndSample) {
  const Rgb diffuse(0.8f, 0.5f, 0.2f);
  const Bsdf b(material(diffuse, Rgb(0.0f), 0.0f), true);
  ASSERT_TRUE(b.isLambertian());
  EXPECT_EQ(b.lambertAlbedo(), diffuse);
  EXPECT_FALSE(Bsdf(material(diffuse, Rgb(0.04f), 0.0f), true).isLambertian());
  EXPECT_FALSE(Bsdf(material(diffuse, Rgb(0.0f), 0.0f, Rgb(0.5f), 0.3f), true).isLambertian());
  EXPECT_FALSE(Bsdf(material(Rgb(0.0f), Rgb(0.0f), 0.0f), true).isLambertian());  // black
  const vec3 wo = outgoing(0.3f);
  for (float uLobe : {0.0f, 0.5f, 0.999f}) {
    Bsdf::Sample s;
    ASSERT_TRUE(b.sample(wo, uLobe, vec2(0.3f, 0.7f), s));
    EXPECT_EQ(s.lobe, Bsdf::Lobe::kNonDelta);
    EXPECT_NEAR(s.pdf, s.wi.z / kPiF, 1e-6f);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(s.weight[c], diffuse[c], 1e-6f);
      EXPECT_NEAR(b.eval(wo, s.wi)[c], diffuse[c] / kPiF, 1e-7f);
    }
  }
}

// A white Fresnel mirror over diffuse d: R(θ) = F(θ), D(θ) = (1 − F(θ)) (1 − t) d at every angle, and at
// normal incidence D equals TraceMaterial::diffuse, which holds the rule at normal incidence.
TEST(Bsdf, MirrorAndDiffuseFollowTheEnergyRuleAtEveryAngle) {
  const float ior = 1.5f;
  const float f0 = schlick(1.0f, ior);
  const Rgb d(0.7f, 0.4f, 0.1f);
  const rdb::TraceMaterial m = material(d * (1.0f - f0), Rgb(1.0f), 0.0f);
  const Bsdf b(m, true);
  for (float cosO : {1.0f, 0.8f, 0.4f, 0.1f}) {
    const vec3 wo = outgoing(cosO);
    const float f = schlick(cosO, ior);
    const dvec3 diffuse = quadratureAlbedo(b, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(diffuse[c], (1.0f - f) * d[c], 2e-4) << cosO << " " << c;
    if (cosO == 1.0f) {
      EXPECT_NEAR(diffuse.g, m.diffuse.g, 2e-4);
    }
    // The mirror's weight over its probability, and the total by sampling.
    const SampledAlbedo s = sampledAlbedo(b, wo);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(s.mean[c], f + (1.0f - f) * d[c], 4.0 * s.stdError[c] + 1e-6) << cosO << " " << c;
    }
    EXPECT_EQ(s.failedFraction, 0.0);
    EXPECT_NEAR(b.albedo(cosO).r, f + (1.0f - f) * d.r, 1e-6f);
  }
  // Uniform reflection r: R = r, D = (1 − r) d at every angle.
  const Bsdf uniform(material(Rgb(0.5f * 0.6f), Rgb(0.5f), 0.0f, Rgb(0.0f), 0.0f, false), true);
  for (float cosO : {1.0f, 0.3f}) {
    EXPECT_NEAR(quadratureAlbedo(uniform, outgoing(cosO)).g, 0.3, 2e-4);
    EXPECT_NEAR(sampledAlbedo(uniform, outgoing(cosO)).mean.g, 0.8, 1e-2);
  }
}

// Clear glass (r = t = 1): reflects F(θ) as a mirror and transmits the pane's T(θ) straight through
// (base/clear_pane.h: 1 − F0 at normal incidence, the lossless slab's fall-off beyond, below 1 − F(θ)),
// nothing else; the back face of a one-sided pane only transmits.
TEST(Bsdf, ClearGlassTransmitsThePanesTransmittanceStraightThrough) {
  const float ior = 1.52f;
  const rdb::TraceMaterial glass = material(Rgb(0.0f), Rgb(1.0f), 0.0f, Rgb(1.0f), 0.0f, true, ior);
  const Bsdf front(glass, true);
  const Bsdf back(glass, false);
  EXPECT_TRUE(front.passesStraight() && back.passesStraight());
  EXPECT_FALSE(front.hasNonDelta());
  const ClearPane pane(schlick(1.0f, ior), Rgb(1.0f), Rgb(1.0f));
  EXPECT_NEAR(pane.at(1.0f).g, 1.0f - schlick(1.0f, ior), 1e-6f);
  for (float cosO : {1.0f, 0.6f, 0.2f}) {
    const vec3 wo = outgoing(cosO);
    const float f = schlick(cosO, ior);
    const float t = pane.at(cosO).g;
    EXPECT_LE(t, 1.0f - f + 1e-6f);
    EXPECT_NEAR(front.straightTransmittance(cosO).g, t, 1e-6f);
    EXPECT_NEAR(back.straightTransmittance(cosO).g, t, 1e-6f);
    EXPECT_NEAR(front.albedo(cosO).g, f + t, 1e-6f);
    uint32_t straight = 0;
    uint32_t mirror = 0;
    const uint32_t count = 10000;
    RandomSampler sampler(3);
    for (uint32_t i = 0; i < count; ++i) {
      sampler.startSample(i);
      Bsdf::Sample s;
      ASSERT_TRUE(front.sample(wo, sampler.next1D(), sampler.next2D(), s));
      if (s.lobe == Bsdf::Lobe::kStraight) {
        ++straight;
        EXPECT_EQ(s.wi, -wo);
      } else {
        ASSERT_EQ(s.lobe, Bsdf::Lobe::kMirror);
        ++mirror;
        EXPECT_EQ(s.wi, vec3(-wo.x, -wo.y, wo.z));
      }
      EXPECT_NEAR(s.weight.g, f + t, 1e-5f);  // each lobe chosen in proportion to its weight
      ASSERT_TRUE(back.sample(wo, sampler.next1D(), sampler.next2D(), s));
      EXPECT_EQ(s.lobe, Bsdf::Lobe::kStraight);
      EXPECT_NEAR(s.weight.g, t, 1e-5f);
    }
    // Binomial: the mirror is chosen with probability F / (F + T).
    const double p = f / (f + t);
    const double sigma = std::sqrt(count * p * (1.0 - p));
    EXPECT_NEAR(mirror, count * p, 4.0 * sigma + 1.0) << cosO;
    EXPECT_EQ(straight + mirror, count);
  }
}

// Glossy and frosted lobes (GGX loses energy to single scattering, never gains): the sampled albedo is at
// most 1, and for wide lobes it agrees with quadrature of eval(), which checks sample()'s weights against
// eval() and pdf().
TEST(Bsdf, GlossyAndFrostedAlbedosStayAtMostOne) {
  struct Case {
    const char* name;
    rdb::TraceMaterial m;
    bool wide;  // quadrature is accurate
  };
  const std::vector<Case> cases = {
      {"white paint, glossiness 0.2", material(Rgb(0.96f), Rgb(1.0f), 0.2f), false},
      {"white paint, glossiness 0.5", material(Rgb(0.96f), Rgb(1.0f), 0.5f), true},
      {"white paint, glossiness 1", material(Rgb(0.96f), Rgb(1.0f), 1.0f), true},
      {"rough white metal", material(Rgb(0.0f), Rgb(1.0f), 0.7f, Rgb(0.0f), 0.0f, false), true},
      {"frosted glass 0.6", material(Rgb(0.0f), Rgb(1.0f), 0.6f, Rgb(1.0f), 0.6f, true, 1.52f), true},
      {"frosted glass over diffuse", material(Rgb(0.3f), Rgb(1.0f), 0.8f, Rgb(0.5f), 0.8f), true},
  };
  for (const Case& c : cases) {
    const Bsdf b(c.m, true);
    for (float cosO : {1.0f, 0.7f, 0.3f, 0.05f}) {
      const vec3 wo = outgoing(cosO);
      const SampledAlbedo s = sampledAlbedo(b, wo);
      std::cout << "[ albedo   ] " << c.name << ", cos θo " << cosO << ": " << s.mean.g << " ± " << s.stdError.g
                << " (tail below the surface " << s.failedFraction << ")\n";
      for (int ch = 0; ch < 3; ++ch) EXPECT_LE(s.mean[ch], 1.0 + 4.0 * s.stdError[ch]) << c.name << cosO;
      if (c.wide && cosO >= 0.3f) {
        const dvec3 q = quadratureAlbedo(b, wo);
        for (int ch = 0; ch < 3; ++ch) {
          EXPECT_NEAR(s.mean[ch], q[ch], 4.0 * s.stdError[ch] + 2e-3 * q[ch]) << c.name << " " << cosO;
        }
      }
    }
  }
}

TEST(Bsdf, EvalIsReciprocal) {
  const std::vector<rdb::TraceMaterial> materials = {
      material(Rgb(0.6f, 0.5f, 0.4f), Rgb(1.0f), 0.4f),
      material(Rgb(0.3f), Rgb(0.8f, 0.6f, 0.2f), 0.7f, Rgb(0.0f), 0.0f, false),
      material(Rgb(0.2f), Rgb(1.0f), 0.5f, Rgb(0.7f), 0.5f, true, 1.52f),
      anisotropic(material(Rgb(0.3f), Rgb(1.0f), 0.45f), 0.9f, 0.1f, 0.7f),
  };
  RandomSampler sampler(11);
  for (const rdb::TraceMaterial& m : materials) {
    const Bsdf b(m, true);
    for (uint32_t i = 0; i < 2000; ++i) {
      sampler.startSample(i);
      const vec3 wo = sampleUniformHemisphere(sampler.next2D());
      const vec3 wi = sampleUniformSphere(sampler.next2D());
      if (wo.z < 1e-3f || std::abs(wi.z) < 1e-3f) continue;
      const Rgb f = b.eval(wo, wi);
      // Light reversed: it arrives along wo and leaves along wi; in the frame of wi's side, +z flips.
      const Rgb g = wi.z > 0.0f ? b.eval(wi, wo) : b.eval(vec3(wi.x, wi.y, -wi.z), vec3(wo.x, wo.y, -wo.z));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], g[c], 1e-4f * std::max(f[c], 1.0f)) << i;
    }
  }
}

// A million draws of b.sample() from wo (a non-delta mixture): each reports the density pdf() gives, and
// their directions, binned on the equal-area sphere chart, fit the density by the chi-square test. Draws
// that fall below the surface (the glossy lobes' tails) return false; pdf() integrates to the rest.
void expectSamplingFollowsPdf(const Bsdf& b, const vec3& wo, uint64_t seed, const char* what) {
  test::Chi2Grid grid(32, 64);
  uint32_t drawn = 0;
  constexpr uint32_t kCount = 1'000'000;
  RandomSampler sampler(seed);
  for (uint32_t i = 0; i < kCount; ++i) {
    sampler.startSample(i);
    const float uLobe = sampler.next1D();
    Bsdf::Sample s;
    if (!b.sample(wo, uLobe, sampler.next2D(), s)) continue;
    ASSERT_EQ(s.lobe, Bsdf::Lobe::kNonDelta);
    EXPECT_NEAR(s.pdf, b.pdf(wo, s.wi), 1e-4f * s.pdf);
    ++drawn;
    const dvec2 st = test::sphereChart(s.wi);
    grid.add(st.x, st.y);
  }
  const double scale = double(kCount) / drawn;
  test::expectFits(what, grid.test([&](double s, double t) {
                     const vec3 wi(test::sphereChartDirection(s, t));
                     return scale * b.pdf(wo, wi) * test::kSphereChartJacobian;
                   }));
}

// sample() draws directions with the density pdf() reports: a diffuse + glossy + frosted mixture binned on
// the equal-area sphere chart. Draws that fall below the surface (the glossy lobes' tails) return false; pdf()
// integrates to the rest.
TEST(Bsdf, SamplingFollowsPdf) {
  const Bsdf b(material(Rgb(0.4f), Rgb(1.0f), 0.6f, Rgb(0.5f), 0.7f), true);
  for (float cosO : {0.9f, 0.35f}) {
    expectSamplingFollowsPdf(b, outgoing(cosO), 5, cosO > 0.5f ? "bsdf mixture, cos θo 0.9" : "bsdf mixture, cos θo 0.35");
  }
}

// Equal anisotropy values are the isotropic lobe exactly (eval, pdf and sample bit for bit), and values a
// hair apart (the anisotropic code's path) give it within float rounding.
TEST(Bsdf, EqualAnisotropyIsTheIsotropicLobe) {
  const Bsdf isotropic(material(Rgb(0.3f), Rgb(1.0f), 0.35f), true);
  const Bsdf equal(anisotropic(material(Rgb(0.3f), Rgb(1.0f), 0.35f), 0.6f, 0.6f, 1.0f), true);
  const Bsdf nearlyEqual(anisotropic(material(Rgb(0.3f), Rgb(1.0f), 0.35f), 0.6f, 0.6f + 1e-6f, 1.0f), true);
  RandomSampler sampler(13);
  for (uint32_t i = 0; i < 2000; ++i) {
    sampler.startSample(i);
    const vec3 wo = sampleUniformHemisphere(sampler.next2D());
    const vec3 wi = sampleUniformHemisphere(sampler.next2D());
    if (wo.z < 1e-3f || wi.z < 1e-3f) continue;
    EXPECT_EQ(equal.eval(wo, wi), isotropic.eval(wo, wi)) << i;
    EXPECT_EQ(equal.pdf(wo, wi), isotropic.pdf(wo, wi)) << i;
    const Rgb f = isotropic.eval(wo, wi);
    const Rgb g = nearlyEqual.eval(wo, wi);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(g[c], f[c], 1e-4f * f[c] + 1e-7f) << i;
    EXPECT_NEAR(nearlyEqual.pdf(wo, wi), isotropic.pdf(wo, wi), 1e-4f * isotropic.pdf(wo, wi) + 1e-7f) << i;
    const float uLobe = sampler.next1D();
    const vec2 u = sampler.next2D();
    Bsdf::Sample a, b;
    ASSERT_EQ(equal.sample(wo, uLobe, u, a), isotropic.sample(wo, uLobe, u, b));
    EXPECT_EQ(a.wi, b.wi);
    EXPECT_EQ(a.weight, b.weight);
  }
}

// The lobe turns with anisotropyRotationRad: f(R ωo, R ωi) at rotation θ is f(ωo, ωi) at rotation 0 (R the
// turn by θ about the normal), and a quarter turn swaps the U and V widths.
TEST(Bsdf, AnisotropyRotationTurnsTheLobe) {
  const float theta = 0.7f;
  const Bsdf straight(whiteMetal(0.4f, 0.8f, 0.1f), true);
  const Bsdf rotated(whiteMetal(0.4f, 0.8f, 0.1f, theta), true);
  const Bsdf quarter(whiteMetal(0.4f, 0.8f, 0.1f, 0.5f * kPiF), true);
  const Bsdf swapped(whiteMetal(0.4f, 0.1f, 0.8f), true);
  RandomSampler sampler(17);
  for (uint32_t i = 0; i < 2000; ++i) {
    sampler.startSample(i);
    const vec3 wo = sampleUniformHemisphere(sampler.next2D());
    const vec3 wi = sampleUniformHemisphere(sampler.next2D());
    if (wo.z < 1e-3f || wi.z < 1e-3f) continue;
    const float f = straight.eval(wo, wi).g;
    EXPECT_NEAR(rotated.eval(turned(wo, theta), turned(wi, theta)).g, f, 2e-4f * f + 1e-6f) << i;
    EXPECT_NEAR(rotated.pdf(turned(wo, theta), turned(wi, theta)), straight.pdf(wo, wi),
                2e-4f * straight.pdf(wo, wi) + 1e-6f);
    const float g = swapped.eval(wo, wi).g;
    EXPECT_NEAR(quarter.eval(wo, wi).g, g, 2e-4f * g + 1e-6f) << i;
  }
}

// The lobe is wider along U when U > V. In the plane of the normal and U the anisotropic lobe is the
// isotropic lobe of width α_U scaled by α_U / α_V (D there is the isotropic D of width α_U times α_U / α_V,
// and Λ of directions in that plane is the isotropic Λ of width α_U), in the plane of V the one of width α_V
// scaled by α_V / α_U: seen along the normal, its half widths are those of the isotropic lobes of widths α_U
// and α_V, whose tangents stand close to the ratio α_U / α_V = 1 / (1 − 0.9 |u − v|) (base/ggx.h).
TEST(Bsdf, AnisotropicLobeIsWiderAlongTheLargerValue) {
  const float glossiness = 0.35f;  // the brushed-metal preset's lobe
  const float alpha = glossiness * glossiness;
  const float aspect = std::sqrt(1.0f - 0.9f * 0.5f);
  const float alphaU = alpha / aspect, alphaV = alpha * aspect;
  const Bsdf b(whiteMetal(glossiness, 0.6f, 0.1f), true);
  const Bsdf isotropicU(whiteMetal(std::sqrt(alphaU)), true);
  const Bsdf isotropicV(whiteMetal(std::sqrt(alphaV)), true);
  RandomSampler sampler(19);
  for (uint32_t i = 0; i < 500; ++i) {
    sampler.startSample(i);
    const vec2 u = sampler.next2D();
    // ωo and ωi in the plane of the normal and U (x), then of the normal and V (y).
    const float to = 1.5f * (u.x - 0.5f), ti = 1.5f * (u.y - 0.5f);
    const vec3 woU(std::sin(to), 0.0f, std::cos(to)), wiU(std::sin(ti), 0.0f, std::cos(ti));
    const float fU = isotropicU.eval(woU, wiU).g * alphaU / alphaV;
    EXPECT_NEAR(b.eval(woU, wiU).g, fU, 1e-4f * fU) << to << " " << ti;
    const vec3 woV(0.0f, std::sin(to), std::cos(to)), wiV(0.0f, std::sin(ti), std::cos(ti));
    const float fV = isotropicV.eval(woV, wiV).g * alphaV / alphaU;
    EXPECT_NEAR(b.eval(woV, wiV).g, fV, 1e-4f * fV) << to << " " << ti;
  }
  // θh where f along azimuth φ falls to half its peak, ωo along the normal, by bisection.
  const vec3 wo(0.0f, 0.0f, 1.0f);
  const float peak = b.eval(wo, wo).g;
  auto halfWidthTan = [&](float phi) {
    float lo = 0.0f, hi = 0.7f;
    for (int k = 0; k < 60; ++k) {
      const float mid = 0.5f * (lo + hi);
      const vec3 wi(std::sin(2.0f * mid) * std::cos(phi), std::sin(2.0f * mid) * std::sin(phi),
                    std::cos(2.0f * mid));
      (b.eval(wo, wi).g > 0.5f * peak ? lo : hi) = mid;
    }
    return std::tan(0.5f * (lo + hi));
  };
  const float alongU = halfWidthTan(0.0f), alongV = halfWidthTan(0.5f * kPiF);
  std::cout << "[ lobe     ] half widths tan θh: along U " << alongU << ", along V " << alongV << ", ratio "
            << alongU / alongV << " (α_U / α_V = " << alphaU / alphaV << ")\n";
  // D alone halves at tan θh = α √(√2 − 1); 1 / cos θi and G2 widen the wider lobe a little more (3 % here).
  const float k = std::sqrt(std::sqrt(2.0f) - 1.0f);
  EXPECT_NEAR(alongV, alphaV * k, 0.02f * alphaV * k);
  EXPECT_NEAR(alongU, alphaU * k, 0.05f * alphaU * k);
  EXPECT_GT(alongU / alongV, alphaU / alphaV);
  EXPECT_LT(alongU / alongV, 1.05f * alphaU / alphaV);
}

// sample() follows pdf() for an anisotropic, rotated lobe over a diffuse base: the chi-square test on the
// equal-area sphere chart, as for the isotropic mixture.
TEST(Bsdf, AnisotropicSamplingFollowsPdf) {
  const Bsdf b(anisotropic(material(Rgb(0.3f), Rgb(1.0f), 0.5f), 0.9f, 0.05f, 0.4f), true);
  for (float cosO : {0.9f, 0.35f}) {
    expectSamplingFollowsPdf(b, turned(outgoing(cosO), 1.1f), 23,
                             cosO > 0.5f ? "anisotropic bsdf, cos θo 0.9" : "anisotropic bsdf, cos θo 0.35");
  }
}

// The directional albedo of anisotropic lobes: sample()'s mean weight agrees with quadrature of eval() over
// half vectors (exact enough for narrow lobes) and stays at most 1. For the brushed-metal lobe it is close to
// that of the isotropic lobe of the same α_U α_V = α²: the energy that single scattering loses (1 − albedo,
// F ≡ 1) is lost to masking, Λ ≈ α(φ)² tan² θ / 4 for small α tan θ (Heitz 2014), with the width α(φ) that
// a direction's azimuth projects between α_V = 0.74 α and α_U = 1.35 α (aspect √0.55): so the anisotropic
// loss is between 0.55 and 1.82 times the isotropic one, and the test asks for [0.5, 2].
TEST(Bsdf, AnisotropicAlbedoAgreesWithQuadratureAndTheIsotropicLobe) {
  struct Case {
    const char* name;
    rdb::TraceMaterial m;
  };
  const std::vector<Case> cases = {
      {"brushed metal", whiteMetal(0.35f, 0.6f, 0.1f)},
      {"ratio 10, glossiness 1", whiteMetal(1.0f, 1.0f, 0.0f)},
      {"ratio 10, glossiness 0.1", whiteMetal(0.1f, 0.0f, 1.0f, 1.0f)},
  };
  const Bsdf isotropicBrushed(whiteMetal(0.35f), true);
  for (const Case& c : cases) {
    const Bsdf b(c.m, true);
    const float alpha = c.m.reflectionGlossiness * c.m.reflectionGlossiness;
    const vec2 widths = ggxAnisotropicAlphas(alpha, c.m.anisotropyU, c.m.anisotropyV);
    const double narrowest = std::min(widths.x, widths.y);
    for (float cosO : {1.0f, 0.7f, 0.3f, 0.05f}) {
      for (float phiO : {0.0f, 1.2f}) {
        if (cosO == 1.0f && phiO != 0.0f) continue;  // the same ωo
        const vec3 wo = turned(outgoing(cosO), phiO);
        const SampledAlbedo s = sampledAlbedo(b, wo);
        const double q = halfVectorQuadratureAlbedo(b, wo, narrowest);
        std::cout << "[ albedo   ] " << c.name << ", cos θo " << cosO << ", φo " << phiO << ": sampled "
                  << s.mean.g << " ± " << s.stdError.g << ", quadrature " << q << "\n";
        EXPECT_LE(s.mean.g, 1.0 + 4.0 * s.stdError.g) << c.name;
        EXPECT_NEAR(s.mean.g, q, 4.0 * s.stdError.g + 2e-3 * q)
            << c.name << " cos θo " << cosO << " φo " << phiO;
        if (std::string(c.name).starts_with("brushed")) {
          const double iso = halfVectorQuadratureAlbedo(isotropicBrushed, wo, alpha);
          std::cout << "[ albedo   ]   isotropic of the same α_U α_V: " << iso << ", loss ratio "
                    << (1.0 - q) / (1.0 - iso) << "\n";
          EXPECT_GE(1.0 - q, 0.5 * (1.0 - iso)) << c.name << " cos θo " << cosO << " φo " << phiO;
          EXPECT_LE(1.0 - q, 2.0 * (1.0 - iso)) << c.name << " cos θo " << cosO << " φo " << phiO;
        }
      }
    }
  }
}

}  // namespace
}  // namespace fly::raytracer
