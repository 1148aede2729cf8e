// A closed sphere of Lambertian albedo ρ with a point light of intensity I at its centre: the classic test of
// interreflection (pbrt-v4's "unit sphere, Kd = 0.5, point light at the centre"), whose answer the bounce
// settings decide. Every wall point sees the whole inside, so with the wall's radiosity uniform the
// irradiance on the wall is E = E_direct + ρ Ē with Ē = 4πI / ((1 − ρ) A) the mean irradiance of an enclosure
// that absorbs the fraction 1 − ρ of what reaches it (A the wall's area); on a true sphere E = I / (R² (1 − ρ)).
// The settings are the ones `fly illuminance` and `fly bake` resolve with no flags and no bake section
// (cli::estimateSettings, cli::integratorSettings): the default must be the unbiased answer.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "base/color.h"
#include "base/error.h"
#include "cli/bake_options.h"
#include "raytracer/bounce_cap_bias.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/measured_brdf.h"
#include "sdb/scene.h"

namespace fly::cli {
namespace {

constexpr float kRadiusM = 2.0f;
constexpr float kIntensityCd = 100.0f;
constexpr uint32_t kRings = 48;     // latitude bands
constexpr uint32_t kSegments = 96;  // longitude steps

// A UV sphere of radius kRadiusM around the origin whose front faces (counter-clockwise) look inwards, with a
// single-sided material of albedo rho, and a point light at the centre. `measured`: the albedo is a measured
// table of the constant ρ/π instead (base/brdf_table.h), over analytic parameters of another albedo (0.2)
// that it must replace.
sdb::Scene closedSphere(float rho, bool measured = false) {
  sdb::Scene scene;
  sdb::Material m;
  m.name = "wall";
  m.diffuseColor = Rgb(measured ? 0.2f : rho);
  m.reflectionColor = Rgb(0.0f);
  if (measured) {
    m.measuredBrdf = std::make_shared<const sdb::MeasuredBrdf>(
        std::vector<Rgb>(sdb::MeasuredBrdf::kSamples, Rgb(rho / float(M_PI))));
  }
  const sdb::MaterialId material = scene.addMaterial(m).id;

  // The facets are flat (each triangle its own vertices with the facet's normal), so the surface that shades
  // is the polyhedron the exact answer describes: smooth shading normals on a tessellated sphere would shade
  // a slightly different, not energy-conserving surface whose loss (≈ 0.015 % a reflection here) ρ = 0.99
  // multiplies a hundredfold.
  std::vector<vec3> grid;
  for (uint32_t i = 0; i <= kRings; ++i) {
    const float theta = float(M_PI) * float(i) / float(kRings);
    for (uint32_t j = 0; j <= kSegments; ++j) {
      const float phi = 2.0f * float(M_PI) * float(j) / float(kSegments);
      grid.push_back(kRadiusM * vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
    }
  }
  sdb::Mesh mesh;
  mesh.name = "sphere";
  mesh.material = material;
  const auto facet = [&](uint32_t a, uint32_t b, uint32_t c) {
    const vec3 n = glm::normalize(glm::cross(grid[b] - grid[a], grid[c] - grid[a]));
    for (uint32_t v : {a, b, c}) {
      mesh.indices.push_back(uint32_t(mesh.positions.size()));
      mesh.positions.push_back(grid[v]);
      mesh.normals.push_back(n);
    }
  };
  const uint32_t row = kSegments + 1;
  for (uint32_t i = 0; i < kRings; ++i) {
    for (uint32_t j = 0; j < kSegments; ++j) {
      const uint32_t a = i * row + j, b = a + 1, c = a + row, d = c + 1;
      // (a, b, c) is counter-clockwise seen from outside; reversed, it faces the centre.
      if (i > 0) facet(a, c, b);
      if (i + 1 < kRings) facet(b, c, d);
    }
  }
  sdb::Node node;
  node.name = "sphere";
  node.meshes.push_back(scene.addMesh(mesh).id);
  scene.addNode(node);

  sdb::Light light;
  light.name = "bulb";
  light.intensity = kIntensityCd;
  sdb::Node lightNode;
  lightNode.name = "bulb";
  lightNode.light = scene.addLight(light).id;
  scene.addNode(lightNode);
  return scene;
}

struct Sensors {
  std::vector<vec3> positionsM;
  std::vector<vec3> normals;
  std::vector<double> directLux;  // I cos θ / d² from the centre
};

// Sensors at the centroids of triangles spread over the sphere, facing inwards along their facet normal.
Sensors wallSensors(const rdb::TraceRdb& rdb, uint32_t count) {
  Sensors s;
  const size_t triangles = rdb.triangleCount();
  for (uint32_t k = 0; k < count; ++k) {
    const size_t t = (2 * k + 1) * triangles / (2 * count);
    const vec3 a = rdb.positionsM[rdb.indices[3 * t]], b = rdb.positionsM[rdb.indices[3 * t + 1]],
               c = rdb.positionsM[rdb.indices[3 * t + 2]];
    const vec3 p = (a + b + c) / 3.0f;
    const vec3 n = glm::normalize(glm::cross(b - a, c - a));
    s.positionsM.push_back(p);
    s.normals.push_back(n);
    const double d = glm::length(p);
    s.directLux.push_back(kIntensityCd * glm::dot(n, -p / float(d)) / (d * d));
  }
  return s;
}

// Ē = 4πI / ((1 − ρ) A): every lumen the light emits reaches the wall, which absorbs 1 − ρ of all it receives.
double meanWallLux(const rdb::TraceRdb& rdb, float rho) {
  double areaM2 = 0.0;
  for (size_t t = 0; t < rdb.triangleCount(); ++t) {
    const vec3 a = rdb.positionsM[rdb.indices[3 * t]], b = rdb.positionsM[rdb.indices[3 * t + 1]],
               c = rdb.positionsM[rdb.indices[3 * t + 2]];
    areaM2 += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  return 4.0 * M_PI * kIntensityCd / ((1.0 - rho) * areaM2);
}

void expectUnbiasedAndHonestByDefault(float rho, bool measured = false) {
  const sdb::Scene scene = closedSphere(rho, measured);
  const rdb::TraceRdb rdb = rdb::buildTraceRdb(scene);
  const raytracer::EmbreeScene embree(rdb);
  const SamplingOptions noFlags;
  const raytracer::IntegratorSettings integratorDefaults = integratorSettings(noFlags, scene.bakeSettings());
  EXPECT_EQ(integratorDefaults.maxBounces, raytracer::kPathLengthGuard);
  const raytracer::Integrator integrator(rdb, embree, integratorDefaults);
  const Sensors sensors = wallSensors(rdb, 16);
  const std::vector<float> magnitudesM(sensors.positionsM.size(), kRadiusM);
  const raytracer::EstimateResult result = raytracer::estimateIrradiance(
      integrator, sensors.positionsM, sensors.normals, estimateSettings(noFlags, scene.bakeSettings()), magnitudesM);

  const double indirectLux = rho * meanWallLux(rdb, rho);
  double sumZ2 = 0.0, sumRel = 0.0;
  for (size_t i = 0; i < result.points.size(); ++i) {
    const double exact = sensors.directLux[i] + indirectLux;
    const double mean = luminance(result.points[i].meanLux);
    const double sigma = luminance(result.points[i].stdErrorLux);
    SCOPED_TRACE("albedo " + std::to_string(rho) + ", sensor " + std::to_string(i) + ": exact " +
                 std::to_string(exact) + " lx, got " + std::to_string(mean) + " ± " + std::to_string(sigma));
    EXPECT_NEAR(mean, exact, 0.03 * exact);
    EXPECT_NEAR(mean, exact, 5.0 * sigma);
    sumZ2 += (mean - exact) * (mean - exact) / (sigma * sigma);
    sumRel += (mean - exact) / exact;
  }
  const double meanRel = sumRel / double(result.points.size());
  // Honest errors: the spread of the estimates around the exact answer is what the reported standard errors
  // say (the RMS of z = (mean − exact)/σ over 16 sensors lies in [0.6, 1.4] with 99 % probability for honest
  // errors; the bounds leave room for the tessellation's ≈ 0.1 % and the moderated variance).
  const double rmsZ = std::sqrt(sumZ2 / double(result.points.size()));
  EXPECT_GT(rmsZ, 0.3) << "reported errors far larger than the actual ones; mean deviation " << meanRel;
  EXPECT_LT(rmsZ, 2.0) << "reported errors far smaller than the actual ones; mean deviation " << meanRel;
}

TEST(ClosedSphere, AlbedoHalfIsExactWithDefaultSettings) { expectUnbiasedAndHonestByDefault(0.5f); }
TEST(ClosedSphere, AlbedoNinetyPercentIsExactWithDefaultSettings) { expectUnbiasedAndHonestByDefault(0.9f); }
TEST(ClosedSphere, AlbedoNinetyNinePercentIsExactWithDefaultSettings) { expectUnbiasedAndHonestByDefault(0.99f); }
// The same through a measured table: lowered from the SDB, sampled by its tabulated lobe.
TEST(ClosedSphere, MeasuredTableOfAlbedoEightyPercentIsExactWithDefaultSettings) {
  expectUnbiasedAndHonestByDefault(0.8f, true);
}

// Russian roulette as a weight window (raytracer/integrator.h): on the sphere every wall vertex's light sample
// is the same, so throughput roulette's (window 1) variance is all from the number of bounces a path
// survives; below the window w the survivors carry the throughput w instead of 1, and the variance falls by
// about 1/w² (16 at w = 0.25; 12–15 measured over these sensors with one-sample estimates of 512 samples).
// Plain Monte Carlo with one replicate, so that a point's squared standard error times its samples is its
// variance per sample; both estimates unbiased.
TEST(ClosedSphere, WeightWindowCutsTheVariancePerSample) {
  constexpr float kRho = 0.9f;
  constexpr uint32_t kSamples = 512;
  const sdb::Scene scene = closedSphere(kRho);
  const rdb::TraceRdb rdb = rdb::buildTraceRdb(scene);
  const raytracer::EmbreeScene embree(rdb);
  const Sensors sensors = wallSensors(rdb, 16);
  const std::vector<float> magnitudesM(sensors.positionsM.size(), kRadiusM);
  const double indirectLux = kRho * meanWallLux(rdb, kRho);
  raytracer::EstimateSettings estimate;
  estimate.sampler = raytracer::SamplerKind::kRandom;
  estimate.replicates = 1;
  estimate.firstPassSamples = kSamples;
  estimate.maxSamples = kSamples;
  estimate.threads = 2;
  // Mean over the sensors of the relative variance per sample.
  const auto relativeVariance = [&](float window) {
    raytracer::IntegratorSettings settings;
    settings.rouletteWindow = window;
    const raytracer::Integrator integrator(rdb, embree, settings);
    const raytracer::EstimateResult result =
        raytracer::estimateIrradiance(integrator, sensors.positionsM, sensors.normals, estimate, magnitudesM);
    double sum = 0.0;
    for (size_t i = 0; i < result.points.size(); ++i) {
      const double exact = sensors.directLux[i] + indirectLux;
      const double mean = luminance(result.points[i].meanLux);
      const double sigma = luminance(result.points[i].stdErrorLux);
      SCOPED_TRACE("window " + std::to_string(window) + ", sensor " + std::to_string(i) + ": exact " +
                   std::to_string(exact) + " lx, got " + std::to_string(mean) + " ± " + std::to_string(sigma));
      EXPECT_NEAR(mean, exact, 4.5 * sigma + 0.002 * exact);
      sum += double(kSamples) * sigma * sigma / (exact * exact);
    }
    return sum / double(result.points.size());
  };
  const double throughputRoulette = relativeVariance(1.0f);
  const double window = relativeVariance(raytracer::kRouletteWindow);
  EXPECT_GT(throughputRoulette, 0.3);  // a relative standard deviation of ≈ 0.9 per sample (integrator.h)
  EXPECT_GT(throughputRoulette / window, 8.0)
      << "relative variance per sample " << throughputRoulette << " at window 1, " << window << " at "
      << raytracer::kRouletteWindow;
  EXPECT_THROW(raytracer::Integrator(rdb, embree, raytracer::IntegratorSettings{.rouletteWindow = 0.0f}),
               std::invalid_argument);
}

// A cap of K reflections keeps Σ_{k=0..K} ρ^k of the light on a sphere's wall and removes the fraction
// ρ^(K+1) (39 % at ρ = 0.9, K = 8): the bias estimate must find it.
TEST(ClosedSphere, BounceCapBiasIsEstimated) {
  constexpr float kRho = 0.9f;
  constexpr uint32_t kCap = 8;
  const sdb::Scene scene = closedSphere(kRho);
  const rdb::TraceRdb rdb = rdb::buildTraceRdb(scene);
  const raytracer::EmbreeScene embree(rdb);
  SamplingOptions capped;
  capped.maxBounces = kCap;
  const raytracer::BounceCapBias onSurfaces = raytracer::estimateBounceCapBiasOnSurfaces(
      rdb, embree, integratorSettings(capped, scene.bakeSettings()));
  const double exact = std::pow(double(kRho), double(kCap + 1));
  EXPECT_EQ(onSurfaces.maxBounces, kCap);
  EXPECT_EQ(onSurfaces.points, raytracer::kBounceCapPilotPoints);
  EXPECT_GT(onSurfaces.missingRelStdError, 0.0);
  EXPECT_NEAR(onSurfaces.missingRel, exact, 4.0 * onSurfaces.missingRelStdError + 0.01);
  // Every wall point loses the same share: the largest is that share plus the points' own noise.
  EXPECT_GE(onSurfaces.missingRelMax, exact - 0.01);
  EXPECT_LE(onSurfaces.missingRelMax, exact + 0.2);

  const Sensors sensors = wallSensors(rdb, 16);
  const raytracer::BounceCapBias atSensors = raytracer::estimateBounceCapBias(
      rdb, embree, integratorSettings(capped, scene.bakeSettings()), sensors.positionsM, sensors.normals,
      std::vector<float>(16, kRadiusM));
  EXPECT_EQ(atSensors.points, 16u);
  EXPECT_NEAR(atSensors.missingRel, exact, 4.0 * atSensors.missingRelStdError + 0.01);

  // A cap that cuts nothing: direct light alone on a sphere of albedo 0 … reflects nothing either way.
  const sdb::Scene black = closedSphere(0.0f);
  const rdb::TraceRdb blackRdb = rdb::buildTraceRdb(black);
  const raytracer::EmbreeScene blackEmbree(blackRdb);
  const raytracer::BounceCapBias none =
      raytracer::estimateBounceCapBiasOnSurfaces(blackRdb, blackEmbree, integratorSettings(capped, black.bakeSettings()));
  EXPECT_EQ(none.missingRel, 0.0);
}

TEST(ClosedSphere, CapsBeyondTheGuardAreRefused) {
  SamplingOptions o;
  o.maxBounces = raytracer::kPathLengthGuard + 1;
  EXPECT_THROW(integratorSettings(o, sdb::BakeSettings{}), UsageError);
}

}  // namespace
}  // namespace fly::cli
