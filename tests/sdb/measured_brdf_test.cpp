// MERL tables written from analytic BRDFs (Lambert, GGX, a clear-coated metallic car paint) and read back:
// the half/difference angles, the reader against the analytic values, the interpolation, the albedo against
// quadrature of the analytic BRDF, and the reader's errors.
#include "sdb/measured_brdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "base/error.h"
#include "base/file_io.h"
#include "gltf_builder.h"

namespace fly::sdb {
namespace {

constexpr float kPi = 3.14159265358979f;

// Walter et al. 2007 (eq. 33, 34): the GGX distribution and Smith's masking for one direction.
float ggxD(float cosThetaH, float alpha) {
  const float a2 = alpha * alpha;
  const float c2 = cosThetaH * cosThetaH;
  const float d = c2 * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}
float smithG1(float cosTheta, float alpha) {
  const float c2 = cosTheta * cosTheta;
  const float tan2 = (1.0f - c2) / std::max(c2, 1e-12f);
  return 2.0f / (1.0f + std::sqrt(1.0f + alpha * alpha * tan2));
}
float schlick(float f0, float cosThetaD) { return f0 + (1.0f - f0) * std::pow(1.0f - cosThetaD, 5.0f); }

// A microfacet lobe f = F · D · G / (4 cos θi cos θo) at directions in the local frame.
Rgb ggxLobe(const vec3& wi, const vec3& wo, float alpha, const Rgb& f0) {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return Rgb(0.0f);
  const vec3 h = glm::normalize(wi + wo);
  const float cd = glm::dot(wi, h);
  const Rgb f(schlick(f0.r, cd), schlick(f0.g, cd), schlick(f0.b, cd));
  return f * ggxD(h.z, alpha) * smithG1(wi.z, alpha) * smithG1(wo.z, alpha) / (4.0f * wi.z * wo.z);
}

// A metallic car paint: a clear coat (GGX α = 0.04, F0 = 0.04) over metal flakes in a blue binder (a GGX
// lobe α = 0.25 of F0 (0.5, 0.55, 0.7) weighted 0.3) and a diffuse base (0.02, 0.04, 0.2); what the coat
// does not reflect on the way in reaches the base.
Rgb carPaint(const vec3& wi, const vec3& wo) {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return Rgb(0.0f);
  const Rgb coat = ggxLobe(wi, wo, 0.04f, Rgb(0.04f));
  const float through = (1.0f - schlick(0.04f, wi.z)) * (1.0f - schlick(0.04f, wo.z));
  const Rgb flakes = 0.3f * ggxLobe(wi, wo, 0.25f, Rgb(0.5f, 0.55f, 0.7f));
  const Rgb base = Rgb(0.02f, 0.04f, 0.2f) / kPi;
  return coat + through * (flakes + base);
}

Rgb atAngles(Rgb (*f)(const vec3&, const vec3&), const HalfDiffAngles& a) {
  vec3 wi, wo;
  directionsOf(a, wi, wo);
  return f(wi, wo);
}

Rgb ggx03(const vec3& wi, const vec3& wo) { return ggxLobe(wi, wo, 0.3f, Rgb(0.9f, 0.6f, 0.3f)); }

// A unit direction in the upper hemisphere from two uniform numbers (uniform in solid angle).
vec3 hemisphere(float u1, float u2) {
  const float z = std::max(u1, 1e-3f);
  const float r = std::sqrt(1.0f - z * z);
  return {r * std::cos(2.0f * kPi * u2), r * std::sin(2.0f * kPi * u2), z};
}

class MeasuredBrdfTest : public ::testing::Test {
 protected:
  MeasuredBrdf tableOf(Rgb (*f)(const vec3&, const vec3&), const std::string& name) {
    const std::filesystem::path file = dir_ / name;
    writeMerlBrdf(file, [f](const HalfDiffAngles& a) { return atAngles(f, a); });
    EXPECT_EQ(std::filesystem::file_size(file), 12u + 3u * MeasuredBrdf::kSamples * 8u);
    return readMerlBrdf(file);
  }
  test::TempDir dir_;
};

TEST(HalfDiffAngles, RoundTripAndKnownConfigurations) {
  // Mirror configuration: the half vector is the normal, θd = θi.
  const float t = 0.6f;
  const HalfDiffAngles mirror = halfDiffAngles(vec3(std::sin(t), 0, std::cos(t)), vec3(-std::sin(t), 0, std::cos(t)));
  EXPECT_NEAR(mirror.thetaHalfRad, 0.0f, 1e-6f);
  EXPECT_NEAR(mirror.thetaDiffRad, t, 1e-6f);
  // Retro-reflection: ωi = ωo, θh = θi, θd = 0.
  const vec3 w = glm::normalize(vec3(0.3f, -0.2f, 0.8f));
  const HalfDiffAngles retro = halfDiffAngles(w, w);
  EXPECT_NEAR(retro.thetaHalfRad, std::acos(w.z), 1e-6f);
  EXPECT_NEAR(retro.thetaDiffRad, 0.0f, 1e-3f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int n = 0; n < 1000; ++n) {
    const HalfDiffAngles a{u(rng) * 1.2f, u(rng) * 1.2f, u(rng) * 2.0f * kPi};
    vec3 wi, wo;
    directionsOf(a, wi, wo);
    EXPECT_NEAR(glm::length(wi), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(wo), 1.0f, 1e-5f);
    const HalfDiffAngles b = halfDiffAngles(wi, wo);
    EXPECT_NEAR(b.thetaHalfRad, a.thetaHalfRad, 1e-4f);
    EXPECT_NEAR(b.thetaDiffRad, a.thetaDiffRad, 1e-4f);
    if (a.thetaDiffRad > 1e-2f) {
      EXPECT_NEAR(std::remainder(b.phiDiffRad - a.phiDiffRad, 2.0f * kPi), 0.0f, 1e-3f);
    }
  }
}

TEST_F(MeasuredBrdfTest, LambertTableIsExactAndItsAlbedoIsTheReflectance) {
  const MeasuredBrdf t = tableOf([](const vec3& wi, const vec3& wo) {
    return wi.z > 0.0f && wo.z > 0.0f ? Rgb(0.8f, 0.5f, 0.2f) / kPi : Rgb(0.0f);
  }, "lambert.binary");
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int n = 0; n < 200; ++n) {
    const Rgb f = t.evalPerSr(hemisphere(u(rng), u(rng)), hemisphere(u(rng), u(rng)));
    EXPECT_NEAR(f.r, 0.8f / kPi, 1e-6f);
    EXPECT_NEAR(f.b, 0.2f / kPi, 1e-6f);
  }
  EXPECT_EQ(t.evalPerSr(vec3(0, 0, 1), vec3(0.6f, 0, -0.8f)), Rgb(0.0f));  // below the surface
  for (float c : {1.0f, 0.5f, 0.05f}) {
    const Rgb a = t.albedo(c);
    EXPECT_NEAR(a.r, 0.8f, 1e-4f);
    EXPECT_NEAR(a.g, 0.5f, 1e-4f);
  }
  const MeasuredBrdf::AlbedoPeak peak = t.maxAlbedo(32);
  EXPECT_NEAR(peak.albedo, 0.8f, 1e-4f);
  EXPECT_EQ(peak.channel, 0);
}

// A GGX lobe (α = 0.3): interpolated values against the analytic BRDF at random directions, and the
// directional albedo against the same quadrature of the analytic BRDF.
TEST_F(MeasuredBrdfTest, GgxTableMatchesTheAnalyticLobe) {
  const MeasuredBrdf t = tableOf(&ggx03, "ggx.binary");
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  double sumSq = 0.0, sumSqNearest = 0.0;
  int counted = 0;
  for (int n = 0; n < 4000; ++n) {
    const vec3 wi = hemisphere(u(rng), u(rng)), wo = hemisphere(u(rng), u(rng));
    if (wi.z < 0.1f || wo.z < 0.1f) continue;  // Smith's G and 1/cos vary fastest at grazing angles
    const float exact = ggx03(wi, wo).g;
    const float relative = t.evalPerSr(wi, wo).g / exact - 1.0f;
    const float relativeNearest = t.nearestSample(wi, wo).g / exact - 1.0f;
    EXPECT_LT(std::abs(relative), 0.05f) << wi.x << " " << wi.y << " " << wi.z << " / " << wo.x << " " << wo.y << " " << wo.z;
    sumSq += relative * relative;
    sumSqNearest += relativeNearest * relativeNearest;
    ++counted;
  }
  const double rms = std::sqrt(sumSq / counted), rmsNearest = std::sqrt(sumSqNearest / counted);
  EXPECT_LT(rms, 0.01);
  EXPECT_LT(rms, 0.5 * rmsNearest);  // interpolation beats MERL's nearest-below lookup
  for (float c : {1.0f, 0.7f, 0.3f}) {
    // The analytic lobe's albedo by the same cosine-weighted midpoint quadrature.
    const vec3 wi(std::sqrt(1.0f - c * c), 0.0f, c);
    double exact = 0.0;
    const int n = 96, m = 4 * n;
    for (int a = 0; a < n; ++a) {
      const double uu = (a + 0.5) / n;
      for (int b = 0; b < m; ++b) {
        const double phi = 2.0 * kPi * (b + 0.5) / m;
        const vec3 wo(float(std::sqrt(uu) * std::cos(phi)), float(std::sqrt(uu) * std::sin(phi)), float(std::sqrt(1 - uu)));
        exact += ggx03(wi, wo).r;
      }
    }
    exact *= kPi / (double(n) * m);
    EXPECT_NEAR(t.albedo(c).r, exact, 0.01 * exact) << c;
    EXPECT_LE(t.albedo(c).r, 1.0f);
  }
}

// The car paint keeps its sharp coat highlight (α = 0.04: the table's θh samples are 0.011°, 0.044°, …
// apart near the highlight) and conserves energy at every incident angle.
TEST_F(MeasuredBrdfTest, CarPaintTableKeepsItsHighlightAndEnergy) {
  const MeasuredBrdf t = tableOf(&carPaint, "paint.binary");
  for (float theta : {0.2f, 0.7f, 1.2f}) {
    for (float dh : {0.0f, 0.01f, 0.03f, 0.08f}) {
      // θh = dh off the mirror direction, in the plane of incidence.
      const vec3 wi(std::sin(theta), 0.0f, std::cos(theta));
      const vec3 wo(-std::sin(theta - 2.0f * dh), 0.0f, std::cos(theta - 2.0f * dh));
      const Rgb exact = carPaint(wi, wo);
      const Rgb table = t.evalPerSr(wi, wo);
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(table[ch], exact[ch], 0.03f * exact[ch]) << theta << " " << dh;
    }
  }
  const MeasuredBrdf::AlbedoPeak peak = t.maxAlbedo(192);
  EXPECT_LE(peak.albedo, 1.0f);
  EXPECT_GT(peak.albedo, 0.2f);
}

TEST_F(MeasuredBrdfTest, NearestSampleIsMerlsLookup) {
  const MeasuredBrdf t = tableOf(&ggx03, "ggx.binary");
  for (const auto& [i, j, k] : {std::tuple{0, 0, 0}, {1, 30, 45}, {45, 60, 170}, {89, 89, 179}, {10, 5, 90}}) {
    HalfDiffAngles a = MeasuredBrdf::sampleAngles(i, j, k);
    // Just above the sample (MERL's index is the floor of the table coordinate).
    const float h = (float(i) + 0.25f) / 90.0f;
    a.thetaHalfRad = h * h * kPi / 2.0f;
    a.thetaDiffRad = (float(j) + 0.25f) / 90.0f * kPi / 2.0f;
    a.phiDiffRad = (float(k) + 0.25f) / 180.0f * kPi;
    vec3 wi, wo;
    directionsOf(a, wi, wo);
    if (wi.z <= 0.0f || wo.z <= 0.0f) continue;
    EXPECT_EQ(t.nearestSample(wi, wo), t.sample(i, j, k)) << i << " " << j << " " << k;
  }
}

TEST_F(MeasuredBrdfTest, EnergyAboveOneIsReported) {
  const MeasuredBrdf t = tableOf([](const vec3&, const vec3&) { return Rgb(0.2f, 1.3f, 0.2f) / kPi; }, "hot.binary");
  const MeasuredBrdf::AlbedoPeak peak = t.maxAlbedo(32);
  EXPECT_NEAR(peak.albedo, 1.3f, 1e-3f);
  EXPECT_EQ(peak.channel, 1);
}

TEST_F(MeasuredBrdfTest, BadFilesAreInputErrorsNamingTheProblem) {
  const std::filesystem::path good = dir_ / "good.binary";
  writeMerlBrdf(good, [](const HalfDiffAngles&) { return Rgb(0.1f); });
  const std::string bytes = readInputFile(good, "test");
  auto errorOf = [&](const std::string& content) {
    const std::filesystem::path f = dir_ / "bad.binary";
    writeFileAtomic(f, content);
    try {
      readMerlBrdf(f);
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().file, f.string());
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto contains = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  EXPECT_TRUE(contains(errorOf(bytes.substr(0, 8)), "too short for a MERL BRDF header"));
  std::string dims = bytes;
  const int32_t wrong = 360;
  std::memcpy(dims.data() + 8, &wrong, 4);
  EXPECT_TRUE(contains(errorOf(dims), "declares 90 × 90 × 360 samples"));
  EXPECT_TRUE(contains(errorOf(bytes.substr(0, bytes.size() - 8)), "(the file is cut off)"));
  std::string nan = bytes;
  const double nanValue = std::numeric_limits<double>::quiet_NaN();
  // Green channel, sample (1, 2, 3).
  std::memcpy(nan.data() + 12 + (MeasuredBrdf::kSamples + MeasuredBrdf::sampleIndex(1, 2, 3)) * 8, &nanValue, 8);
  const std::string nanError = errorOf(nan);
  EXPECT_TRUE(contains(nanError, "green sample at θh = 0.01111°, θd = 2°, φd = 3° (index 1, 2, 3) is NaN")) << nanError;
  std::string negative = bytes;
  const double minusOne = -1.0;
  std::memcpy(negative.data() + 12 + MeasuredBrdf::sampleIndex(89, 0, 0) * 8, &minusOne, 8);
  EXPECT_TRUE(contains(errorOf(negative), "red sample at θh = 88"));
  EXPECT_TRUE(contains(errorOf(negative), "is -1; a BRDF is finite and ≥ 0"));
  // Below the surface (θh 88°, θd 89°: both directions under the horizon) no sample was measured: a negative
  // marker there reads as 0.
  ASSERT_FALSE(MeasuredBrdf::validSamples()[MeasuredBrdf::sampleIndex(89, 89, 0)]);
  std::string unmeasured = bytes;
  std::memcpy(unmeasured.data() + 12 + MeasuredBrdf::sampleIndex(89, 89, 0) * 8, &minusOne, 8);
  EXPECT_EQ(errorOf(unmeasured), "no error");
  EXPECT_EQ(readMerlBrdf(dir_ / "bad.binary").sample(89, 89, 0).r, 0.0f);
  EXPECT_THROW(readMerlBrdf(dir_ / "missing.binary"), InputError);
}

}  // namespace
}  // namespace fly::sdb
