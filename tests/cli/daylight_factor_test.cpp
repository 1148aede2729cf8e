// The daylight factor against closed forms under the CIE overcast sky L(θ) = Lz·(1 + 2 cos θ)/3: the sky's
// unobstructed horizontal illuminance (7π/9)·Lz, an unobstructed sensor at 100 %, and sensors under a square
// roof opening in a black box, whose daylight factor is the sky-luminance-weighted view factor of the
// opening, integrated here independently of the tracer and its sky table.
#include "cli/daylight_factor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "base/math.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::cli {
namespace {

constexpr double kLz = 3000.0;  // cd/m²

// A closed box [−1, 1]³ of inward-facing black walls whose roof (y = 1) has a hole |x|, |z| < 0.5.
rdb::TraceRdb blackBoxWithRoofOpening() {
  rdb::TraceRdbBuilder b;
  const uint32_t black = b.material(Rgb(0.0f));
  const vec3 lo(-1.0f);
  b.grid(lo, vec3(2, 0, 0), vec3(0, 2, 0), 2, black);
  b.grid(lo + vec3(0, 0, 2), vec3(0, 2, 0), vec3(2, 0, 0), 2, black);
  b.grid(lo, vec3(0, 2, 0), vec3(0, 0, 2), 2, black);
  b.grid(lo + vec3(2, 0, 0), vec3(0, 0, 2), vec3(0, 2, 0), 2, black);
  b.grid(lo, vec3(0, 0, 2), vec3(2, 0, 0), 2, black);
  b.grid(vec3(-1, 1, -1), vec3(2, 0, 0), vec3(0, 0, 0.5f), 2, black);
  b.grid(vec3(-1, 1, 0.5f), vec3(2, 0, 0), vec3(0, 0, 0.5f), 2, black);
  b.grid(vec3(-1, 1, -0.5f), vec3(0.5f, 0, 0), vec3(0, 0, 1), 1, black);
  b.grid(vec3(0.5f, 1, -0.5f), vec3(0.5f, 0, 0), vec3(0, 0, 1), 1, black);
  b.rdb.boundsM = Bounds3{vec3(-1.0f), vec3(1.0f)};
  b.rdb.sky = overcastSky(64, kLz);
  return b.rdb;
}

// The daylight factor (fraction) at `p` facing up under the opening |x|, |z| < 0.5 at y = 1, by the midpoint
// rule over the opening: E = ∫ L(θ) cos θ dω = ∫ L(θ) h² / r⁴ dA (cos θ = h / r, dω = cos θ dA / r²), over
// the closed form E_outside = (7π/9)·Lz.
double openingDaylightFactor(const dvec3& p) {
  constexpr int kSteps = 800;
  const double h = 1.0 - p.y;
  const double dA = 1.0 / (double(kSteps) * kSteps);
  double e = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    for (int k = 0; k < kSteps; ++k) {
      const double dx = -0.5 + (i + 0.5) / kSteps - p.x, dz = -0.5 + (k + 0.5) / kSteps - p.z;
      const double r2 = dx * dx + dz * dz + h * h;
      const double cosTheta = h / std::sqrt(r2);
      e += kLz * (1.0 + 2.0 * cosTheta) / 3.0 * h * h / (r2 * r2) * dA;
    }
  }
  return e / (7.0 * kPi / 9.0 * kLz);
}

TEST(DaylightFactor, OvercastSkyHorizontalIlluminanceIsSevenNinthsPiLz) {
  // Closed form: 2π Lz ∫₀¹ (1 + 2μ)/3 μ dμ = 2π Lz (1/2 + 2/3)/3 = (7π/9) Lz; the table's value differs by
  // Lz·π/(9N²) (cli/daylight_factor.h).
  for (const uint32_t n : {8u, 64u, 256u}) {
    const double e = unobstructedHorizontalLux(overcastSky(n, kLz));
    EXPECT_NEAR(e, 7.0 * kPi / 9.0 * kLz, kLz * kPi / (9.0 * n * n) * 1.01 + 1e-9 * kLz) << n;
  }
  EXPECT_NEAR(overcastZenithLuminanceCdM2(kOvercastHorizontalLux) * 7.0 * kPi / 9.0, kOvercastHorizontalLux,
              1e-9);
  // The zenith is three times as bright as the horizon: the top and bottom rows of cells, at their centres'
  // μ = 1 − 1/128 and 1/128, have (1 + 2μ)/3 of Lz.
  const rdb::TraceSky sky = overcastSky(64, kLz);
  EXPECT_NEAR(sky.radianceCdM2.front().r, kLz * (1.0 + 2.0 * (1.0 - 1.0 / 128)) / 3.0, 1e-3);
  EXPECT_NEAR(sky.radianceCdM2.back().r, kLz * (1.0 + 2.0 / 128) / 3.0, 1e-3);
}

TEST(DaylightFactor, UnobstructedPointIsHundredPercentAndOpeningMatchesViewFactor) {
  const rdb::TraceRdb rdb = blackBoxWithRoofOpening();
  const raytracer::EmbreeScene embree(rdb);
  const raytracer::Integrator integrator(rdb, embree, {});
  // Above the roof (nothing above it), under the opening's centre, and off its axis.
  const std::vector<vec3> points = {vec3(0.0f, 1.5f, 0.0f), vec3(0.0f, -0.5f, 0.0f), vec3(0.6f, -0.2f, 0.3f),
                                    vec3(-0.8f, 0.5f, -0.7f)};
  const std::vector<vec3> normals(points.size(), vec3(0.0f, 1.0f, 0.0f));
  raytracer::EstimateSettings settings;
  settings.firstPassSamples = 1024;
  settings.maxSamples = 4096;
  settings.replicates = 8;
  const raytracer::EstimateResult result =
      raytracer::estimateIrradiance(integrator, points, normals, settings);
  const double outside = unobstructedHorizontalLux(rdb.sky);
  for (size_t i = 0; i < points.size(); ++i) {
    const double df = luminance(result.points[i].meanLux) / outside;
    const double se = luminance(result.points[i].stdErrorLux) / outside;
    const double expected = i == 0 ? 1.0 : openingDaylightFactor(dvec3(points[i]));
    std::printf("sensor %zu: DF %.3f %% ± %.3f %%, closed form %.3f %%\n", i, 100 * df, 100 * se, 100 * expected);
    // 4 standard errors, and 0.2 % of the value for the sky table's 2.2° cells at the opening's edges.
    EXPECT_NEAR(df, expected, 4.0 * se + 2e-3 * expected)
        << "sensor " << i << ": DF " << 100 * df << " % ± " << 100 * se << " %, expected " << 100 * expected
        << " %";
    EXPECT_GT(se, 0.0) << i;
  }
  // The integral's value 1.5 m straight below the 1 m × 1 m opening: 15.51 %.
  EXPECT_NEAR(openingDaylightFactor(dvec3(0.0, -0.5, 0.0)), 0.1551, 5e-4);
}

TEST(DaylightFactor, SummaryGivesMeanMinAndUniformity) {
  const std::vector<double> df = {2.0, 4.0, 6.0};
  const std::vector<double> se = {0.3, 0.4, 0.0};
  const DaylightFactorSummary s = summarizeDaylightFactors(df, se);
  EXPECT_DOUBLE_EQ(s.meanPercent, 4.0);
  EXPECT_DOUBLE_EQ(s.minPercent, 2.0);
  EXPECT_DOUBLE_EQ(s.uniformity, 0.5);
  EXPECT_DOUBLE_EQ(s.meanStdErrorPercent, 0.5 / 3.0);
  const std::vector<double> dark = {0.0, 0.0};
  EXPECT_EQ(summarizeDaylightFactors(dark, dark).uniformity, 0.0);
  EXPECT_THROW(summarizeDaylightFactors({}, {}), std::invalid_argument);
}

TEST(DaylightFactor, KeepSkyOnlyRemovesLampsSunAndEmission) {
  rdb::TraceRdbBuilder b;
  const uint32_t lamp = b.material(Rgb(0.5f), Rgb(100.0f));
  b.grid(vec3(0.0f), vec3(1, 0, 0), vec3(0, 0, 1), 1, lamp);
  b.rdb.punctualLights.push_back({});
  b.rdb.hasSun = true;
  keepSkyOnly(b.rdb);
  EXPECT_TRUE(b.rdb.punctualLights.empty());
  EXPECT_TRUE(b.rdb.emissiveTriangles.empty());
  EXPECT_FALSE(b.rdb.hasSun);
  EXPECT_EQ(maxComponent(b.rdb.materials[lamp].emissionCdM2), 0.0f);
}

}  // namespace
}  // namespace fly::cli
