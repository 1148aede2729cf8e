// The BSDF against analytic answers: albedos by quadrature and by its own sampling, the energy
// rule at every angle, reciprocity, and a chi-square test of sample() against pdf().
#include "raytracer/bsdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

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

// Clear glass (r = t = 1): reflects F(θ), transmits 1 − F(θ) straight through, nothing else; the back face
// of a one-sided pane only transmits.
TEST(Bsdf, ClearGlassTransmitsOneMinusFresnelStraightThrough) {
  const float ior = 1.52f;
  const rdb::TraceMaterial glass = material(Rgb(0.0f), Rgb(1.0f), 0.0f, Rgb(1.0f), 0.0f, true, ior);
  const Bsdf front(glass, true);
  const Bsdf back(glass, false);
  EXPECT_TRUE(front.passesStraight() && back.passesStraight());
  EXPECT_FALSE(front.hasNonDelta());
  for (float cosO : {1.0f, 0.6f, 0.2f}) {
    const vec3 wo = outgoing(cosO);
    const float f = schlick(cosO, ior);
    EXPECT_NEAR(front.straightTransmittance(cosO).g, 1.0f - f, 1e-6f);
    EXPECT_NEAR(back.straightTransmittance(cosO).g, 1.0f - f, 1e-6f);
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
      EXPECT_NEAR(s.weight.g, 1.0f, 1e-5f);  // each lobe chosen in proportion to its weight
      ASSERT_TRUE(back.sample(wo, sampler.next1D(), sampler.next2D(), s));
      EXPECT_EQ(s.lobe, Bsdf::Lobe::kStraight);
      EXPECT_NEAR(s.weight.g, 1.0f - f, 1e-5f);
    }
    // Binomial: the mirror is chosen with probability F.
    const double sigma = std::sqrt(count * f * (1.0 - f));
    EXPECT_NEAR(mirror, count * f, 4.0 * sigma + 1.0) << cosO;
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

// sample() draws directions with the density pdf() reports: a diffuse + glossy + frosted mixture binned on
// the equal-area sphere chart. Draws that fall below the surface (the glossy lobes' tails) return false; pdf()
// integrates to the rest.
TEST(Bsdf, SamplingFollowsPdf) {
  const Bsdf b(material(Rgb(0.4f), Rgb(1.0f), 0.6f, Rgb(0.5f), 0.7f), true);
  for (float cosO : {0.9f, 0.35f}) {
    const vec3 wo = outgoing(cosO);
    test::Chi2Grid grid(32, 64);
    uint32_t drawn = 0;
    constexpr uint32_t kCount = 1'000'000;
    RandomSampler sampler(5);
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
    test::expectFits(cosO > 0.5f ? "bsdf mixture, cos θo 0.9" : "bsdf mixture, cos θo 0.35",
                     grid.test([&](double s, double t) {
                       const vec3 wi(test::sphereChartDirection(s, t));
                       return scale * b.pdf(wo, wi) * test::kSphereChartJacobian;
                     }));
  }
}

}  // namespace
}  // namespace fly::raytracer
