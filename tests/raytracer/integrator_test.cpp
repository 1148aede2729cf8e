// Irradiance against exact answers: every estimate must lie within 4 of its reported standard
// errors of the exact value, and that standard error must be small enough for the comparison to mean
// something.
#include "raytracer/integrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "base/clear_pane.h"
#include "base/log.h"
#include "raytracer/sampler.h"
#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

// A TraceRdb built by hand.
struct SceneBuilder {
  rdb::TraceRdb rdb;

  uint32_t material(const Rgb& diffuse, const Rgb& emissionCdM2 = Rgb(0.0f), bool doubleSided = false) {
    rdb::TraceMaterial m;
    m.diffuse = diffuse;
    m.emissionCdM2 = emissionCdM2;
    m.doubleSided = doubleSided;
    return add(m);
  }
  uint32_t add(const rdb::TraceMaterial& m) {
    rdb.materials.push_back(m);
    return static_cast<uint32_t>(rdb.materials.size() - 1);
  }
  void triangle(const vec3& a, const vec3& b, const vec3& c, uint32_t mat) {
    const auto first = static_cast<uint32_t>(rdb.positionsM.size());
    rdb.positionsM.insert(rdb.positionsM.end(), {a, b, c});
    const vec3 n = glm::normalize(glm::cross(b - a, c - a));
    rdb.normals.insert(rdb.normals.end(), {n, n, n});
    rdb.indices.insert(rdb.indices.end(), {first, first + 1, first + 2});
    rdb.triangleMaterial.push_back(mat);
    if (maxComponent(rdb.materials[mat].emissionCdM2) > 0.0f) {
      rdb.emissiveTriangles.push_back(static_cast<uint32_t>(rdb.triangleCount() - 1));
    }
  }
  // Counter-clockwise seen from the front.
  void quad(const vec3& a, const vec3& b, const vec3& c, const vec3& d, uint32_t mat) {
    triangle(a, b, c, mat);
    triangle(a, c, d, mat);
  }
  // y = 0 from −half to half, facing +Y.
  void ground(float halfM, uint32_t mat) { plane(0.0f, halfM, true, mat); }
  // y = yM from −half to half, facing +Y (up) or −Y.
  void plane(float yM, float halfM, bool up, uint32_t mat) {
    const vec3 a(-halfM, yM, -halfM);
    const vec3 b(-halfM, yM, halfM);
    const vec3 c(halfM, yM, halfM);
    const vec3 d(halfM, yM, -halfM);
    if (up) {
      quad(a, b, c, d, mat);
    } else {
      quad(a, d, c, b, mat);
    }
  }
  void box(const vec3& lo, const vec3& hi, bool inward, uint32_t mat) {
    const vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                       {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 4, 7, 3},
                             {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}};
    for (const auto& f : faces) {
      if (inward) {
        quad(c[f[0]], c[f[3]], c[f[2]], c[f[1]], mat);
      } else {
        quad(c[f[0]], c[f[1]], c[f[2]], c[f[3]], mat);
      }
    }
  }
  void uniformSky(const Rgb& radianceCdM2, uint32_t resolution = 16) {
    rdb.sky.resolution = resolution;
    rdb.sky.radianceCdM2.assign(size_t{resolution} * resolution, radianceCdM2);
  }
  void sun(float elevationDeg, float azimuthDeg, const Rgb& normalLux) {
    const auto e = static_cast<float>(degToRad(elevationDeg));
    const auto a = static_cast<float>(degToRad(azimuthDeg));
    rdb.hasSun = true;
    rdb.sun.directionWorld = vec3(std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a));
    rdb.sun.normalIlluminanceLux = normalLux;
  }
};

struct Sensors {
  std::vector<vec3> points;
  std::vector<vec3> normals;
  std::vector<Rgb> exact;
  void add(const vec3& p, const vec3& n, const Rgb& e) {
    points.push_back(p);
    normals.push_back(glm::normalize(n));
    exact.push_back(e);
  }
};

// The tests estimate each point's error from 64 replicates: with the default 8, the 4σ bound of expectAgrees
// (t-distributed with 7 degrees of freedom) would fail by chance on 1 point in 200.
constexpr uint32_t kTestReplicates = 64;

EstimateResult run(const rdb::TraceRdb& rdb, const Sensors& s, uint32_t samples,
                   SamplerKind kind = SamplerKind::kSobol, uint32_t threads = 0, uint64_t seed = 0,
                   uint32_t replicates = kTestReplicates, const IntegratorSettings& integratorSettings = {}) {
  const EmbreeScene scene(rdb);
  const Integrator integrator(rdb, scene, integratorSettings);
  EstimateSettings settings;
  settings.firstPassSamples = std::max(std::min(samples, 16u), replicates);
  settings.maxSamples = samples;
  settings.sampler = kind;
  settings.threads = threads;
  settings.seed = seed;
  settings.replicates = replicates;
  return estimateIrradiance(integrator, s.points, s.normals, settings);
}

EstimateResult run(const rdb::TraceRdb& rdb, const Sensors& s, uint32_t samples,
                   const IntegratorSettings& integratorSettings) {
  return run(rdb, s, samples, SamplerKind::kSobol, 0, 0, kTestReplicates, integratorSettings);
}

// |mean − exact| < 4 σ + 10⁻⁵ exact per channel, and σ ≤ maxRelStdError · exact (so that the test can fail).
void expectAgrees(const char* what, const EstimateResult& r, const Sensors& s, float maxRelStdError) {
  for (size_t i = 0; i < s.points.size(); ++i) {
    const IrradianceEstimate& e = r.points[i];
    std::cout << "[ estimate ] " << what << " #" << i << ": " << e.meanLux.g << " ± " << e.stdErrorLux.g
              << " lux (exact " << s.exact[i].g << ", error "
              << (e.meanLux.g - s.exact[i].g) / e.stdErrorLux.g << " σ, " << e.samples << " samples)\n";
    for (int c = 0; c < 3; ++c) {
      const float exact = s.exact[i][c];
      EXPECT_LE(std::abs(e.meanLux[c] - exact), 4.0f * e.stdErrorLux[c] + 1e-5f * exact + 1e-6f)
          << what << " point " << i << " channel " << c << ": " << e.meanLux[c] << " ± " << e.stdErrorLux[c]
          << ", exact " << exact;
      EXPECT_LE(e.stdErrorLux[c], maxRelStdError * exact + 1e-6f)
          << what << " point " << i << " channel " << c;
    }
  }
}

constexpr float kHugeGroundHalfM = 5000.0f;

TEST(Integrator, PointLightOverPlaneIsICosOverDSquared) {
  SceneBuilder b;
  b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
  rdb::TracePunctualLight light;
  light.positionM = vec3(0.5f, 2.0f, -0.25f);
  light.intensity = Rgb(100.0f, 50.0f, 25.0f);
  b.rdb.punctualLights.push_back(light);
  Sensors s;
  for (const vec3& p : {vec3(0.5f, 0, -0.25f), vec3(0, 0, 0), vec3(3, 0, -2), vec3(-40, 0, 15)}) {
    const vec3 toLight = light.positionM - p;
    const float d = glm::length(toLight);
    s.add(p, vec3(0, 1, 0), light.intensity * (toLight.y / d) / (d * d));
  }
  // A tilted sensor: cos θ from its own normal.
  const vec3 p(1, 0, 1);
  const vec3 n = glm::normalize(vec3(-1, 1, -1));
  const vec3 toLight = light.positionM - p;
  const float d = glm::length(toLight);
  s.add(p, n, light.intensity * glm::dot(n, toLight / d) / (d * d));
  expectAgrees("point light", run(b.rdb, s, 64), s, 1e-5f);
}

TEST(Integrator, SpotRangeDirectionalAndGoniometricLightsFollowKhrLightsPunctual) {
  const vec3 up(0, 1, 0);
  auto single = [](const rdb::TracePunctualLight& light, rdb::TraceGoniometricTable table = {}) {
    SceneBuilder b;
    b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
    b.rdb.punctualLights.push_back(light);
    if (!table.candelaCd.empty()) b.rdb.goniometricTables.push_back(table);
    return b;
  };
  {
    // Spot straight down from 2 m, inner 20°, outer 30°: at 25° off axis the factor is t² with
    // t = (cos 25° − cos 30°) / (cos 20° − cos 30°); at 10° it is 1, at 35° it is 0.
    rdb::TracePunctualLight spot;
    spot.type = rdb::PunctualType::kSpot;
    spot.positionM = vec3(0, 2, 0);
    spot.directionWorld = vec3(0, -1, 0);
    spot.cosInner = std::cos(static_cast<float>(degToRad(20.0)));
    spot.cosOuter = std::cos(static_cast<float>(degToRad(30.0)));
    spot.intensity = Rgb(1000.0f);
    const SceneBuilder b = single(spot);
    Sensors s;
    for (double angleDeg : {10.0, 25.0, 35.0}) {
      const auto a = static_cast<float>(degToRad(angleDeg));
      const float d = 2.0f / std::cos(a);
      const float t = std::clamp((std::cos(a) - spot.cosOuter) / (spot.cosInner - spot.cosOuter), 0.0f, 1.0f);
      s.add(vec3(2.0f * std::tan(a), 0, 0), up, spot.intensity * (t * t * std::cos(a) / (d * d)));
    }
    expectAgrees("spot", run(b.rdb, s, 64), s, 1e-5f);
  }
  {
    // Range 10 m at 5 m: the window is 1 − (5/10)⁴; beyond the range, nothing.
    rdb::TracePunctualLight point;
    point.positionM = vec3(0, 5, 0);
    point.intensity = Rgb(400.0f);
    point.rangeM = 10.0f;
    const SceneBuilder b = single(point);
    Sensors s;
    s.add(vec3(0, 0, 0), up, point.intensity * ((1.0f - 0.0625f) / 25.0f));
    s.add(vec3(20, 0, 0), up, Rgb(0.0f));
    expectAgrees("range", run(b.rdb, s, 64), s, 1e-5f);
  }
  {
    // Directional: lux on a surface facing it, times cos θ.
    rdb::TracePunctualLight sunLike;
    sunLike.type = rdb::PunctualType::kDirectional;
    sunLike.directionWorld = glm::normalize(vec3(1, -2, 0));
    sunLike.intensity = Rgb(1000.0f, 900.0f, 800.0f);
    const SceneBuilder b = single(sunLike);
    Sensors s;
    s.add(vec3(100, 0, 100), up, sunLike.intensity * (2.0f / std::sqrt(5.0f)));
    s.add(vec3(0, 1, 0), vec3(0, -1, 0), Rgb(0.0f));  // facing the ground
    expectAgrees("directional", run(b.rdb, s, 64), s, 1e-5f);
  }
  {
    // Goniometric with a table that grows linearly in γ from 0 to 180° (C-independent): straight below (γ =
    // 0) it is 0 cd, at γ = 45° (from the downward axis) a quarter of the maximum.
    rdb::TraceGoniometricTable table;
    table.gammaSteps = 5;
    table.cSteps = 4;
    for (uint32_t c = 0; c < 4; ++c) {
      for (uint32_t g = 0; g < 5; ++g) table.candelaCd.push_back(static_cast<float>(g) * 0.25f);
    }
    rdb::TracePunctualLight gonio;
    gonio.type = rdb::PunctualType::kGoniometric;
    gonio.positionM = vec3(0, 2, 0);
    gonio.directionWorld = vec3(0, -1, 0);
    gonio.cAxisWorld = vec3(1, 0, 0);
    gonio.intensity = Rgb(800.0f);
    const SceneBuilder b = single(gonio, table);
    Sensors s;
    const float d = 2.0f * std::sqrt(2.0f);
    s.add(vec3(0, 0, 2), up, gonio.intensity * (0.25f * std::cos(kPiF / 4.0f) / (d * d)));
    s.add(vec3(0.0f, 0.0f, 0.0f), up, Rgb(0.0f));
    expectAgrees("goniometric", run(b.rdb, s, 64), s, 1e-5f);
  }
}

TEST(Integrator, UniformSkyOverPlaneIsPiL) {
  SceneBuilder b;
  b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
  const Rgb sky(1000.0f, 2000.0f, 3000.0f);
  b.uniformSky(sky);
  Sensors s;
  s.add(vec3(0, 0, 0), vec3(0, 1, 0), kPiF * sky);
  s.add(vec3(4000.0f, 0, -3000.0f), vec3(0, 1, 0), kPiF * sky);
  // Tilted by α (the sky is black below the horizon): E = π L (1 + cos α) / 2.
  for (float alphaDeg : {30.0f, 90.0f, 150.0f}) {
    const auto a = static_cast<float>(degToRad(alphaDeg));
    s.add(vec3(1, 1, 1), vec3(std::sin(a), std::cos(a), 0), kPiF * sky * (1.0f + std::cos(a)) / 2.0f);
  }
  expectAgrees("uniform sky", run(b.rdb, s, 1024), s, 0.05f);
}

// A non-uniform sky table: each equal-area cell (i, j) spans φ ∈ [2π i/res, 2π (i+1)/res) and
// μ = cos θ ∈ [1 − (j+1)/res, 1 − j/res] (TraceSky). Facing up, E = Σ L_ij ∫_cell μ dω = Σ L_ij (π / res)
// (μ_hi² − μ_lo²) exactly; facing +x or +z (vertical sensors, no ground), E = Σ L_ij ∫_cell max(0, d · n) dω
// by fine midpoint quadrature: these check the table's orientation in φ = atan2(d.z, d.x).
TEST(Integrator, TabulatedSkyIsImportanceSampledInWorldDirections) {
  SceneBuilder b;
  constexpr uint32_t kRes = 8;
  b.rdb.sky.resolution = kRes;
  RandomSampler values(17);
  for (uint32_t c = 0; c < kRes * kRes; ++c) {
    values.startSample(c);
    const float u = values.next1D();
    // A wide dynamic range, and one bright cell, as a sky around the sun has.
    b.rdb.sky.radianceCdM2.push_back(Rgb(100.0f * u * u, 50.0f * u, 20.0f) * (c == 10 ? 200.0f : 1.0f));
  }
  dvec3 up(0.0);
  dvec3 alongX(0.0);
  dvec3 alongZ(0.0);
  constexpr int kSub = 64;
  for (uint32_t j = 0; j < kRes; ++j) {
    const double muHi = 1.0 - static_cast<double>(j) / kRes;
    const double muLo = 1.0 - static_cast<double>(j + 1) / kRes;
    for (uint32_t i = 0; i < kRes; ++i) {
      const dvec3 radiance(b.rdb.sky.radianceCdM2[j * kRes + i]);
      double cellX = 0.0;
      double cellZ = 0.0;
      for (int a = 0; a < kSub; ++a) {
        const double phi = 2.0 * kPi * (i + (a + 0.5) / kSub) / kRes;
        for (int c = 0; c < kSub; ++c) {
          const double mu = muLo + (muHi - muLo) * (c + 0.5) / kSub;
          cellX += std::max(0.0, std::sqrt(1.0 - mu * mu) * std::cos(phi));
          cellZ += std::max(0.0, std::sqrt(1.0 - mu * mu) * std::sin(phi));
        }
      }
      const double subCellSolidAngle = 2.0 * kPi / (kRes * kRes) / (kSub * kSub);
      up += radiance * ((kPi / kRes) * (muHi * muHi - muLo * muLo));
      alongX += radiance * (cellX * subCellSolidAngle);
      alongZ += radiance * (cellZ * subCellSolidAngle);
    }
  }
  Sensors s;
  s.add(vec3(0.0f), vec3(0, 1, 0), Rgb(up));
  s.add(vec3(0.0f), vec3(1, 0, 0), Rgb(alongX));
  s.add(vec3(0.0f), vec3(0, 0, 1), Rgb(alongZ));
  expectAgrees("sky table", run(b.rdb, s, 4096), s, 0.02f);
}

// Lambert's formula for a polygon of uniform radiance L seen from p with normal n (Lambert 1760; Arvo,
// "Analytic methods for simulated light transport", 1995, eq. 3.6): E = (L / 2) |Σ_i γ_i n · (r_i × r_{i+1})
// / |r_i × r_{i+1}||, with r_i the unit vectors to the vertices and γ_i the angle between r_i and r_{i+1};
// valid when the polygon lies wholly above the sensor's horizon.
float lambertPolygon(const vec3& p, const vec3& n, const std::vector<vec3>& polygon, float radiance) {
  double sum = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const dvec3 a = glm::normalize(dvec3(polygon[i]) - dvec3(p));
    const dvec3 c = glm::normalize(dvec3(polygon[(i + 1) % polygon.size()]) - dvec3(p));
    const double gamma = std::acos(std::clamp(glm::dot(a, c), -1.0, 1.0));
    sum += gamma * glm::dot(dvec3(n), glm::normalize(glm::cross(a, c)));
  }
  return static_cast<float>(0.5 * std::abs(sum) * radiance);
}

TEST(Integrator, RectangularEmitterFollowsLambertsPolygonFormula) {
  SceneBuilder b;
  const float radiance = 50.0f;
  // 2 m × 1 m at 1 m height, facing down.
  const std::vector<vec3> rect = {vec3(-1, 1, -0.5f), vec3(1, 1, -0.5f), vec3(1, 1, 0.5f), vec3(-1, 1, 0.5f)};
  b.quad(rect[0], rect[1], rect[2], rect[3], b.material(Rgb(0.0f), Rgb(radiance)));
  ASSERT_LT(glm::cross(rect[1] - rect[0], rect[2] - rect[0]).y, 0.0f);
  Sensors s;
  for (const auto& [p, n] :
       {std::pair{vec3(0, 0, 0), vec3(0, 1, 0)}, std::pair{vec3(0.7f, 0, 0.3f), vec3(0, 1, 0)},
        std::pair{vec3(2, 0, 1), vec3(0, 1, 0)}, std::pair{vec3(0, 0.5f, 0), vec3(0.2f, 1, 0.1f)}}) {
    s.add(p, n, Rgb(lambertPolygon(p, glm::normalize(n), rect, radiance)));
  }
  expectAgrees("rectangle", run(b.rdb, s, 1024), s, 0.01f);
}

// The same rectangle turned to face up: seen from below, its back emits only when it is double-sided (glTF).
TEST(Integrator, EmitterBackFaceEmitsOnlyWhenDoubleSided) {
  const float radiance = 50.0f;
  const std::vector<vec3> rect = {vec3(-1, 1, -0.5f), vec3(-1, 1, 0.5f), vec3(1, 1, 0.5f), vec3(1, 1, -0.5f)};
  for (bool doubleSided : {false, true}) {
    SceneBuilder b;
    b.quad(rect[0], rect[1], rect[2], rect[3], b.material(Rgb(0.0f), Rgb(radiance), doubleSided));
    ASSERT_GT(glm::cross(rect[1] - rect[0], rect[2] - rect[0]).y, 0.0f);
    Sensors s;
    const vec3 p(0.3f, 0.0f, 0.1f);
    s.add(p, vec3(0, 1, 0), Rgb(doubleSided ? lambertPolygon(p, vec3(0, 1, 0), rect, radiance) : 0.0f));
    expectAgrees(doubleSided ? "double-sided emitter" : "one-sided emitter's back", run(b.rdb, s, 1024), s,
                 0.01f);
  }
}

TEST(Integrator, DiskEmitterAboveDifferentialAreaIsPiLR2OverR2PlusH2) {
  SceneBuilder b;
  const float radiance = 100.0f;
  const float radiusM = 1.0f;
  const float heightM = 2.0f;
  const uint32_t mat = b.material(Rgb(0.0f), Rgb(radiance));
  // A fan of 512 triangles facing down, inscribed in the disk.
  constexpr int kSegments = 512;
  std::vector<vec3> rim;
  for (int i = 0; i < kSegments; ++i) {
    const float phi = 2.0f * kPiF * static_cast<float>(i) / kSegments;
    rim.emplace_back(radiusM * std::cos(phi), heightM, radiusM * std::sin(phi));
  }
  for (int i = 0; i < kSegments; ++i) b.triangle(vec3(0, heightM, 0), rim[i], rim[(i + 1) % kSegments], mat);
  ASSERT_LT(glm::cross(rim[0] - vec3(0, heightM, 0), rim[1] - vec3(0, heightM, 0)).y, 0.0f);
  const float disk = kPiF * radiance * radiusM * radiusM / (radiusM * radiusM + heightM * heightM);
  // The inscribed polygon receives slightly less; allow for it.
  const float polygon = lambertPolygon(vec3(0.0f), vec3(0, 1, 0), rim, radiance);
  ASSERT_LT(std::abs(polygon - disk), 1e-4f * disk);
  Sensors s;
  s.add(vec3(0.0f), vec3(0, 1, 0), Rgb(disk));
  expectAgrees("disk", run(b.rdb, s, 4096), s, 0.005f);
}

// A closed box whose inward walls all have albedo ρ and emit L: L_i = L / (1 − ρ) everywhere, E = π L / (1 −
// ρ).
TEST(Integrator, WhiteFurnaceConvergesUpToAlbedo099) {
  for (const auto& [albedo, samples, maxRel] :
       {std::tuple{0.5f, 4096u, 0.01f}, std::tuple{0.9f, 4096u, 0.02f}, std::tuple{0.99f, 8192u, 0.02f}}) {
    SceneBuilder b;
    const Rgb emission(1.0f, 2.0f, 0.5f);
    b.box(vec3(-1.0f), vec3(1.0f), true, b.material(Rgb(albedo), emission));
    Sensors s;
    const Rgb exact = kPiF * emission / (1.0f - albedo);
    s.add(vec3(0.0f), vec3(0, 1, 0), exact);
    s.add(vec3(0.3f, -0.5f, 0.8f), vec3(-1, 2, 0.5f), exact);
    s.add(vec3(0.2f, -1.0f, 0.1f), vec3(0, 1, 0), exact);  // on the floor
    const EstimateResult r = run(b.rdb, s, samples);
    std::cout << "[ furnace  ] albedo " << albedo << ": " << r.rays << " rays in " << r.seconds
              << " s = " << static_cast<double>(r.rays) / r.seconds / 1e6 << " Mrays/s\n";
    expectAgrees("furnace", r, s, maxRel);
  }
}

// In the furnace, light reflected k times contributes π L ρ^k: with at most B bounces, E = π L Σ_{k≤B} ρ^k.
TEST(Integrator, MaxBouncesCountsReflections) {
  SceneBuilder b;
  const float albedo = 0.8f;
  b.box(vec3(-1.0f), vec3(1.0f), true, b.material(Rgb(albedo), Rgb(1.0f)));
  const EmbreeScene scene(b.rdb);
  Sensors s;
  s.add(vec3(0.1f, 0.2f, -0.3f), vec3(0, 1, 0), Rgb(0.0f));
  for (uint32_t bounces : {0u, 1u, 3u}) {
    const Integrator integrator(b.rdb, scene, IntegratorSettings{bounces});
    EstimateSettings settings;
    settings.firstPassSamples = kTestReplicates;
    settings.replicates = kTestReplicates;
    settings.maxSamples = 2048;
    float sum = 0.0f;
    for (uint32_t k = 0; k <= bounces; ++k) sum += std::pow(albedo, static_cast<float>(k));
    s.exact[0] = Rgb(kPiF * sum);
    expectAgrees("max bounces", estimateIrradiance(integrator, s.points, s.normals, settings), s, 0.01f);
  }
}

TEST(Integrator, AlbedoOneEndsAtThePathLengthGuard) {
  SceneBuilder b;
  b.box(vec3(-1.0f), vec3(1.0f), true, b.material(Rgb(1.0f), Rgb(1.0f)));
  Sensors s;
  s.add(vec3(0.0f), vec3(0, 1, 0), Rgb(0.0f));
  const EstimateResult r = run(b.rdb, s, 2, SamplerKind::kSobol, 0, 0, 1);
  // Each path runs to the guard and gathers about π L per vertex.
  EXPECT_TRUE(isFinite(r.points[0].meanLux));
  EXPECT_GT(r.points[0].meanLux.g, 0.5f * kPiF * static_cast<float>(kPathLengthGuard));
}

TEST(Integrator, SunDiscAtHalfDegreeZenithAndBelowHorizon) {
  const Rgb normalLux(100000.0f, 95000.0f, 90000.0f);
  const vec3 up(0, 1, 0);
  {
    // The disc (half-angle 0.27°) lies wholly above the horizon at 0.5°: ∫ over it of cos θ = (n · s) π sin²
    // θ_s exactly, so E = E_n sin 0.5°. Sensors near the origin and 5.7 km out on the 10 km ground.
    SceneBuilder b;
    b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
    b.sun(0.5f, 30.0f, normalLux);
    Sensors s;
    const Rgb exact = normalLux * static_cast<float>(std::sin(degToRad(0.5)));
    for (const vec3& p : {vec3(0.0f), vec3(4000.0f, 0, -4000.0f), vec3(-4999.0f, 0, 4999.0f)})
      s.add(p, up, exact);
    expectAgrees("sun 0.5°", run(b.rdb, s, 256), s, 0.01f);
  }
  {
    SceneBuilder b;
    b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
    b.sun(90.0f, 0.0f, normalLux);
    Sensors s;
    s.add(vec3(0.0f), up, normalLux);
    s.add(vec3(3000.0f, 0, 1000.0f), up, normalLux);
    expectAgrees("sun zenith", run(b.rdb, s, 256), s, 0.001f);
  }
  {
    // 2° below the horizon: nothing on the ground, nor on a sensor above it turned towards the sun (the
    // ground is in the way).
    SceneBuilder b;
    b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
    b.sun(-2.0f, 0.0f, normalLux);
    Sensors s;
    s.add(vec3(0.0f), up, Rgb(0.0f));
    s.add(vec3(0, 1, 0), b.rdb.sun.directionWorld, Rgb(0.0f));
    expectAgrees("sun below horizon", run(b.rdb, s, 64), s, 0.0f);
  }
}

TEST(Integrator, ReportedStandardErrorIsHonest) {
  // 200 sensors at random tilts under a uniform sky over black ground, E = π L (1 + cos α) / 2: the RMS of
  // (mean − exact) and the mean reported standard error agree within a factor of 2 at every sample count, for
  // plain Monte Carlo with either error estimate and for Sobol' with replicates (8 plain, or 2 moderated by
  // the pooled variance: the default).
  SceneBuilder b;
  b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
  const Rgb sky(1000.0f);
  b.uniformSky(sky);
  Sensors s;
  RandomSampler tilts(99);
  for (uint32_t i = 0; i < 200; ++i) {
    tilts.startSample(i);
    const vec3 n = sampleUniformSphere(tilts.next2D());
    s.add(vec3(0.01f * static_cast<float>(i), 1.0f, 0.0f), n, kPiF * sky * (1.0f + n.y) / 2.0f);
  }
  for (const auto& [kind, replicates] :
       {std::pair{SamplerKind::kRandom, 1u}, std::pair{SamplerKind::kRandom, 8u},
        std::pair{SamplerKind::kRandom, 2u}, std::pair{SamplerKind::kSobol, 8u},
        std::pair{SamplerKind::kSobol, 2u}, std::pair{SamplerKind::kSobol, 1u}}) {
    for (uint32_t samples : {16u, 64u, 256u, 1024u}) {
      const EstimateResult r = run(b.rdb, s, samples, kind, 0, 0, replicates);
      double squaredError = 0.0;
      double stdError = 0.0;
      for (size_t i = 0; i < s.points.size(); ++i) {
        squaredError += std::pow(luminance(r.points[i].meanLux) - luminance(s.exact[i]), 2.0);
        stdError += luminance(r.points[i].stdErrorLux);
      }
      const double rms = std::sqrt(squaredError / static_cast<double>(s.points.size()));
      const double meanStdError = stdError / static_cast<double>(s.points.size());
      std::cout << "[ honesty  ] " << (kind == SamplerKind::kRandom ? "random" : "sobol ") << " replicates "
                << replicates << ", " << samples << " samples: RMS error " << rms
                << " lux, mean reported std. error " << meanStdError << " lux, ratio " << rms / meanStdError
                << "\n";
      if (kind == SamplerKind::kSobol && replicates == 1) {
        // The per-sample variance of Sobol' points only bounds their error from above.
        EXPECT_LT(rms / meanStdError, 2.0);
      } else {
        EXPECT_GT(rms / meanStdError, 0.5);
        EXPECT_LT(rms / meanStdError, 2.0);
      }
    }
  }
}

TEST(Integrator, DeterministicAcrossThreadCounts) {
  SceneBuilder b;
  b.box(vec3(-1.0f), vec3(1.0f), true, b.material(Rgb(0.9f), Rgb(1.0f)));
  b.uniformSky(Rgb(5.0f));
  Sensors s;
  for (int i = 0; i < 37; ++i) {
    const float x = -0.9f + 0.05f * static_cast<float>(i);
    s.add(vec3(x, 0.1f * x, -0.5f * x), vec3(x, 1, 0.3f), Rgb(0.0f));
  }
  for (SamplerKind kind : {SamplerKind::kSobol, SamplerKind::kRandom}) {
    const EstimateResult one = run(b.rdb, s, 64, kind, 1, 5);
    const EstimateResult two = run(b.rdb, s, 64, kind, 2, 5);
    ASSERT_EQ(one.points.size(), two.points.size());
    EXPECT_EQ(one.rays, two.rays);
    for (size_t i = 0; i < one.points.size(); ++i) {
      EXPECT_EQ(std::memcmp(&one.points[i], &two.points[i], sizeof(IrradianceEstimate)), 0) << "point " << i;
    }
  }
}

TEST(Integrator, RobustOnDegenerateTrianglesEdgesAnd10KmGroundWith1MmBox) {
  SceneBuilder b;
  const uint32_t black = b.material(Rgb(0.0f));
  b.ground(kHugeGroundHalfM, black);
  b.box(vec3(-0.0005f, 0.0f, -0.0005f), vec3(0.0005f, 0.001f, 0.0005f), false, b.material(Rgb(0.5f)));
  // Degenerate triangles, emissive and not: a point, a line, a repeated vertex.
  const uint32_t glowing = b.material(Rgb(0.5f), Rgb(10.0f));
  const auto degenerate = [&](const vec3& a, const vec3& c, const vec3& d, uint32_t mat) {
    const auto first = static_cast<uint32_t>(b.rdb.positionsM.size());
    b.rdb.positionsM.insert(b.rdb.positionsM.end(), {a, c, d});
    b.rdb.normals.insert(b.rdb.normals.end(), 3, vec3(0, 1, 0));
    b.rdb.indices.insert(b.rdb.indices.end(), {first, first + 1, first + 2});
    b.rdb.triangleMaterial.push_back(mat);
    if (mat == glowing) b.rdb.emissiveTriangles.push_back(static_cast<uint32_t>(b.rdb.triangleCount() - 1));
  };
  degenerate(vec3(1, 1, 1), vec3(1, 1, 1), vec3(1, 1, 1), glowing);
  degenerate(vec3(0, 0.5f, 0), vec3(1, 0.5f, 0), vec3(2, 0.5f, 0), glowing);
  degenerate(vec3(0, 0.2f, 0), vec3(0, 0.2f, 0), vec3(1, 0.3f, 0), black);
  const Rgb sky(2000.0f);
  b.uniformSky(sky);
  b.sun(40.0f, 10.0f, Rgb(80000.0f));
  rdb::TracePunctualLight light;
  light.positionM = vec3(0.2f, 3.0f, 0.1f);
  light.intensity = Rgb(500.0f);
  b.rdb.punctualLights.push_back(light);

  // Where nothing but the sky, the sun and the light are seen, E is exact: π L + E_n sin 40° + I cos θ / d².
  auto exact = [&](const vec3& p) {
    const vec3 toLight = light.positionM - p;
    const float d = glm::length(toLight);
    return kPiF * sky + b.rdb.sun.normalIlluminanceLux * static_cast<float>(std::sin(degToRad(40.0))) +
           light.intensity * (toLight.y / d / (d * d));
  };
  Sensors s;
  const vec3 up(0, 1, 0);
  s.add(vec3(0.0f, 0.001f, 0.0f), up, exact(vec3(0.0f, 0.001f, 0.0f)));              // the 1 mm box's top
  s.add(vec3(0.0005f, 0.001f, 0.0005f), up, exact(vec3(0.0005f, 0.001f, 0.0005f)));  // its corner
  s.add(vec3(4000.0f, 0, 4000.0f), up, exact(vec3(4000.0f, 0, 4000.0f)));    // the ground's diagonal edge
  s.add(vec3(5000.0f, 0, -5000.0f), up, exact(vec3(5000.0f, 0, -5000.0f)));  // its corner vertex
  const EstimateResult r = run(b.rdb, s, 1024);
  expectAgrees("robust", r, s, 0.01f);

  // Beside the box and on its sides: not exact, but finite.
  Sensors near;
  near.add(vec3(0.0006f, 0, 0), up, Rgb(0.0f));
  near.add(vec3(0.0005f, 0.0005f, 0), vec3(1, 0, 0), Rgb(0.0f));
  near.add(vec3(1, 0.5f, 0), up, Rgb(0.0f));  // on the degenerate line
  for (const IrradianceEstimate& e : run(b.rdb, near, 256).points) {
    EXPECT_TRUE(isFinite(e.meanLux) && isFinite(e.stdErrorLux));
    EXPECT_GE(std::min({e.meanLux.r, e.meanLux.g, e.meanLux.b}), 0.0f);
  }
}

// A 10 km ground tilted by 7° about the z axis, through the origin, under a uniform sky (black below the
// horizon): a sensor on it facing along its normal sees the sky over E = π L (1 + cos 7°) / 2, and nothing of
// the ground, whose own plane bounds the hemisphere — provided rays leave it by the ground's magnitude, not
// the sensor's (surfaceMagnitudesM).
TEST(Integrator, SensorsOnTiltedTerrainUseTheSurfaceMagnitude) {
  SceneBuilder b;
  const auto tilt = static_cast<float>(degToRad(7.0));
  const vec3 slope(std::cos(tilt), std::sin(tilt), 0.0f);  // up the hill along x
  const vec3 across(0, 0, 1);
  const float h = kHugeGroundHalfM;
  b.quad(-h * slope - h * across, -h * slope + h * across, h * slope + h * across, h * slope - h * across,
         b.material(Rgb(0.0f)));
  const Rgb sky(1000.0f);
  b.uniformSky(sky);
  const vec3 n = glm::normalize(glm::cross(across, slope));
  ASSERT_GT(n.y, 0.0f);
  Sensors s;
  std::vector<float> magnitudes;
  const EmbreeScene scene(b.rdb);
  for (float along : {0.0f, 0.37f, 12.5f, 800.0f}) {
    s.add(along * slope + 0.3f * across, n, kPiF * sky * (1.0f + std::cos(tilt)) / 2.0f);
    magnitudes.push_back(scene.triangleMagnitudeM(0));
  }
  const Integrator integrator(b.rdb, scene);
  EstimateSettings settings;
  settings.firstPassSamples = kTestReplicates;
  settings.replicates = kTestReplicates;
  settings.maxSamples = 1024;
  expectAgrees("tilted terrain", estimateIrradiance(integrator, s.points, s.normals, settings, magnitudes), s,
               0.02f);
}

// Thin clear glass as the SDB's clear-glass preset lowers it: white Fresnel reflection, full transmission.
rdb::TraceMaterial clearGlass(bool doubleSided) {
  rdb::TraceMaterial m;
  m.diffuse = Rgb(0.0f);
  m.reflection = Rgb(1.0f);
  m.transmission = Rgb(1.0f);
  m.ior = 1.52f;
  m.reflectionGlossiness = 0.0f;
  m.transmissionGlossiness = 0.0f;
  m.doubleSided = doubleSided;
  return m;
}

// Schlick's Fresnel term.
double schlick(double cosTheta, double ior) {
  const double f0 = std::pow((ior - 1.0) / (ior + 1.0), 2.0);
  return f0 + (1.0 - f0) * std::pow(1.0 - cosTheta, 5.0);
}

// The transmittance of clearGlass() at |cos θ| (base/clear_pane.h: a lossless pane of two Fresnel faces).
double paneTransmittance(double cosTheta) {
  static const ClearPane pane(static_cast<float>(schlick(1.0, 1.52)), Rgb(1.0f), Rgb(1.0f));
  return pane.at(static_cast<float>(cosTheta)).g;
}

// The sun at elevation e through a horizontal clear pane above a black floor: E = E_n sin e T(sin e), the
// pane's transmittance at the angle the light crosses it, whichever face it shows the floor (a one-sided
// pane's back face transmits too). A uniform sky through one pane: E = 2π L ∫₀¹ T(μ) μ dμ; through two
// parallel double-sided panes, with the light reflected between them: E = 2π L ∫₀¹ T² / (1 − R²) μ dμ,
// R = F(μ) (each pane reflects Schlick's F as a mirror). The sensor's own rays that pass the panes and escape
// must add neither the sun nor the sky's light-sampled share again.
TEST(Integrator, SunAndSkyPassClearGlassWithThePanesTransmittance) {
  const float elevationDeg = 50.0f;
  const Rgb normalLux(100000.0f, 90000.0f, 80000.0f);
  const Rgb sky(1000.0f, 2000.0f, 3000.0f);
  const double sinE = std::sin(degToRad(elevationDeg));
  const auto transmittance = static_cast<float>(paneTransmittance(sinE));
  for (const auto& [doubleSided, faceUp] :
       {std::pair{true, false}, std::pair{false, false}, std::pair{false, true}}) {
    SceneBuilder b;
    b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
    b.plane(1.0f, kHugeGroundHalfM, faceUp, b.add(clearGlass(doubleSided)));
    b.sun(elevationDeg, 20.0f, normalLux);
    Sensors s;
    s.add(vec3(0.0f), vec3(0, 1, 0), normalLux * static_cast<float>(sinE) * transmittance);
    s.add(vec3(3.0f, 0.0f, -2.0f), vec3(0, 1, 0), normalLux * static_cast<float>(sinE) * transmittance);
    expectAgrees("sun through a pane", run(b.rdb, s, 256), s, 1e-3f);
  }
  for (int panes : {1, 2}) {
    SceneBuilder b;
    b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
    const uint32_t glass = b.add(clearGlass(true));
    b.plane(1.0f, kHugeGroundHalfM, false, glass);
    if (panes == 2) b.plane(1.5f, kHugeGroundHalfM, true, glass);
    b.uniformSky(sky);
    double integral = 0.0;  // 2 ∫₀¹ T(μ)ⁿ / (1 − R(μ)²)ⁿ⁻¹ μ dμ by the midpoint rule
    constexpr int kSteps = 100000;
    for (int i = 0; i < kSteps; ++i) {
      const double mu = (i + 0.5) / kSteps;
      const double f = schlick(mu, 1.52);
      const double t = paneTransmittance(mu);
      integral += 2.0 * (panes == 1 ? t : t * t / (1.0 - f * f)) * mu / kSteps;
    }
    Sensors s;
    s.add(vec3(0.0f), vec3(0, 1, 0), kPiF * sky * static_cast<float>(integral));
    expectAgrees(panes == 1 ? "sky through a pane" : "sky through two panes", run(b.rdb, s, 1024), s, 0.02f);
    if (panes == 1) {
      // Direct light only: the pane is no reflection, so the sky seen through it still counts in full.
      const EmbreeScene scene(b.rdb);
      const Integrator directOnly(b.rdb, scene, IntegratorSettings{0});
      EstimateSettings settings;
      settings.firstPassSamples = kTestReplicates;
      settings.replicates = kTestReplicates;
      settings.maxSamples = 1024;
      expectAgrees("sky through a pane, direct only",
                   estimateIrradiance(directOnly, s.points, s.normals, settings), s, 0.02f);
    }
  }
}

// A closed black room 4 × 3 × 4 m with a 1 m² window of clear glass (36 panes), in its ceiling (a skylight)
// or in its wall x = 2 (1 m above the floor), under a uniform sky L. Inside, E = ∫_window L T(θ_w) max(0, n ·
// ω) cos θ_w / r² dA over the window points whose direction ω from the sensor is above the horizon (θ_w at
// the pane, T its transmittance there), by midpoint quadrature over the pane; on the roof, E = π L. Sky
// portals (IntegratorSettings::skyPortals) send a quarter of the sky samples from inside through the pane
// instead of the 1–2 % of the hemisphere it covers: both estimators are exact, and the portals' standard
// error inside is several times smaller.
TEST(Integrator, SkyPortalsThroughWindowsAreExactAndLowerTheError) {
  for (const bool skylight : {true, false}) {
    SceneBuilder b;
    const uint32_t black = b.material(Rgb(0.0f));
    const float h = 3.0f;
    // The quad (o, o + u, o + u + v, o + v), facing u × v (into the room), with the
    // window's square [w0, w0 + 1]² in (u, v) units left open.
    auto holed = [&](const vec3& o, const vec3& u, const vec3& v, float uLen, float vLen, const vec2& w0,
                     bool hole) {
      auto rect = [&](float u0, float u1, float v0, float v1) {
        if (u1 <= u0 || v1 <= v0) return;
        b.quad(o + u0 * u + v0 * v, o + u1 * u + v0 * v, o + u1 * u + v1 * v, o + u0 * u + v1 * v, black);
      };
      if (!hole) return rect(0, uLen, 0, vLen);
      rect(0, uLen, 0, w0.y);
      rect(0, uLen, w0.y + 1, vLen);
      rect(0, w0.x, w0.y, w0.y + 1);
      rect(w0.x + 1, uLen, w0.y, w0.y + 1);
    };
    holed(vec3(-2, 0, -2), vec3(0, 0, 1), vec3(1, 0, 0), 4, 4, vec2(0.0f), false);           // floor, up
    holed(vec3(-2, h, -2), vec3(1, 0, 0), vec3(0, 0, 1), 4, 4, vec2(1.5f), skylight);        // ceiling
    holed(vec3(-2, 0, -2), vec3(1, 0, 0), vec3(0, 1, 0), 4, h, vec2(0.0f), false);           // z = −2
    holed(vec3(2, 0, 2), vec3(-1, 0, 0), vec3(0, 1, 0), 4, h, vec2(0.0f), false);            // z = 2
    holed(vec3(-2, 0, 2), vec3(0, 0, -1), vec3(0, 1, 0), 4, h, vec2(0.0f), false);           // x = −2
    holed(vec3(2, 0, -2), vec3(0, 0, 1), vec3(0, 1, 0), 4, h, vec2(1.5f, 1.0f), !skylight);  // x = 2
    const vec3 w0 = skylight ? vec3(-0.5f, h, -0.5f) : vec3(2, 1, -0.5f);
    const vec3 wu = skylight ? vec3(1, 0, 0) : vec3(0, 0, 1);
    const vec3 wv = skylight ? vec3(0, 0, 1) : vec3(0, 1, 0);
    // The pane as 6 × 6 quads (72 triangles, more than kPanesWithoutGrid: the portal's grid is used).
    const uint32_t glass = b.add(clearGlass(true));
    constexpr int kDivisions = 6;
    for (int i = 0; i < kDivisions; ++i) {
      for (int k = 0; k < kDivisions; ++k) {
        const vec3 c =
            w0 + (static_cast<float>(i) / kDivisions) * wu + (static_cast<float>(k) / kDivisions) * wv;
        b.quad(c, c + wu / float(kDivisions), c + (wu + wv) / float(kDivisions), c + wv / float(kDivisions),
               glass);
      }
    }
    const Rgb sky(1000.0f, 2000.0f, 3000.0f);
    b.uniformSky(sky);

    auto throughWindow = [&](const vec3& p, const vec3& n) {
      constexpr int kSteps = 400;
      const dvec3 windowNormal = glm::normalize(glm::cross(dvec3(wu), dvec3(wv)));
      double e = 0.0;
      for (int i = 0; i < kSteps; ++i) {
        for (int k = 0; k < kSteps; ++k) {
          const dvec3 y = dvec3(w0) + (i + 0.5) / kSteps * dvec3(wu) + (k + 0.5) / kSteps * dvec3(wv);
          const dvec3 w = y - dvec3(p);
          const double r2 = glm::dot(w, w);
          const dvec3 omega = w / std::sqrt(r2);
          if (omega.y <= 0.0) continue;
          const double cosWindow = std::abs(glm::dot(omega, windowNormal));
          e += paneTransmittance(cosWindow) * std::max(0.0, glm::dot(dvec3(n), omega)) * cosWindow / r2;
        }
      }
      return sky * static_cast<float>(e / (kSteps * kSteps));
    };
    Sensors s;
    const vec3 tilted = glm::normalize(skylight ? vec3(-0.3f, 1.0f, 0.2f) : vec3(1.0f, 0.3f, 0.2f));
    s.add(vec3(0.0f), vec3(0, 1, 0), throughWindow(vec3(0.0f), vec3(0, 1, 0)));
    s.add(vec3(-1.0f, 1.0f, 0.5f), tilted, throughWindow(vec3(-1.0f, 1.0f, 0.5f), tilted));
    s.add(vec3(1.5f, h, 1.5f), vec3(0, 1, 0), kPiF * sky);  // on the roof

    IntegratorSettings tableOnly;
    tableOnly.skyPortals = false;
    const char* what = skylight ? "skylight" : "wall window";
    const EstimateResult withPortals = run(b.rdb, s, 4096);
    const EstimateResult withoutPortals = run(b.rdb, s, 4096, tableOnly);
    expectAgrees((std::string(what) + ", portals").c_str(), withPortals, s, 0.02f);
    expectAgrees((std::string(what) + ", table only").c_str(), withoutPortals, s, 0.08f);
    for (size_t i = 0; i < 2; ++i) {
      EXPECT_LT(3.0f * withPortals.points[i].stdErrorLux.g, withoutPortals.points[i].stdErrorLux.g)
          << what << " sensor " << i;
    }
    // Above a skylight the roof is outside the window's plane and samples the table alone: the same estimate
    // with and without portals. (Beside a wall window it is within the room's depth behind the window, the
    // region the portal serves, and spends a quarter of its samples on the window: exact still.)
    if (skylight) {
      EXPECT_EQ(withPortals.points[2].meanLux.g, withoutPortals.points[2].meanLux.g) << what;
    }
  }
}

// A closed room 4 × 3 × 4 m with an open hole of 1.5 × 1 m in its wall x = 2 (no glass), under a uniform sky
// L, with the hole declared as a portal (TraceRdb::portalCornersM, two triangles) or not. The declared portal
// sends a quarter of the sky samples from inside through the hole: both estimators are exact. With black
// walls, E = ∫_hole L max(0, n · ω) cos θ_h / r² dA over the hole's points whose direction ω from the sensor is
// above the horizon, by midpoint quadrature over the hole; with grey walls (albedo 0.5, light reflected
// inside) the two estimates agree within 4 combined standard errors. Inside, the portal's standard error is
// several times smaller.
TEST(Integrator, DeclaredPortalsOverOpenHolesAreExactAndLowerTheError) {
  const float h = 3.0f;
  const vec3 h0(2, 1, -0.75f);  // the hole: h0 + a·hu + b·hv, a, b ∈ [0, 1]
  const vec3 hu(0, 0, 1.5f);
  const vec3 hv(0, 1, 0);
  const Rgb sky(1000.0f, 2000.0f, 3000.0f);
  auto room = [&](const Rgb& albedo) {
    SceneBuilder b;
    const uint32_t walls = b.material(albedo);
    // Inward-facing quads (o, o + u, o + u + v, o + v).
    auto rect = [&](const vec3& o, const vec3& u, const vec3& v) { b.quad(o, o + u, o + u + v, o + v, walls); };
    rect(vec3(-2, 0, -2), vec3(0, 0, 4), vec3(4, 0, 0));  // floor
    rect(vec3(-2, h, -2), vec3(4, 0, 0), vec3(0, 0, 4));  // ceiling
    rect(vec3(-2, 0, -2), vec3(4, 0, 0), vec3(0, h, 0));  // z = −2
    rect(vec3(2, 0, 2), vec3(-4, 0, 0), vec3(0, h, 0));   // z = 2
    rect(vec3(-2, 0, 2), vec3(0, 0, -4), vec3(0, h, 0));  // x = −2
    // The wall x = 2 around the hole.
    rect(vec3(2, 0, -2), vec3(0, 0, 4), vec3(0, 1, 0));
    rect(vec3(2, 2, -2), vec3(0, 0, 4), vec3(0, h - 2, 0));
    rect(vec3(2, 1, -2), vec3(0, 0, 1.25f), vec3(0, 1, 0));
    rect(vec3(2, 1, 0.75f), vec3(0, 0, 1.25f), vec3(0, 1, 0));
    b.uniformSky(sky);
    return b;
  };
  auto declarePortal = [&](SceneBuilder& b) {
    b.rdb.portalCornersM = {h0, h0 + hu, h0 + hu + hv, h0, h0 + hu + hv, h0 + hv};
  };
  auto throughHole = [&](const vec3& p, const vec3& n) {
    constexpr int kSteps = 400;
    double e = 0.0;
    for (int i = 0; i < kSteps; ++i) {
      for (int k = 0; k < kSteps; ++k) {
        const dvec3 y = dvec3(h0) + (i + 0.5) / kSteps * dvec3(hu) + (k + 0.5) / kSteps * dvec3(hv);
        const dvec3 w = y - dvec3(p);
        const double r2 = glm::dot(w, w);
        const dvec3 omega = w / std::sqrt(r2);
        if (omega.y <= 0.0) continue;
        e += std::max(0.0, glm::dot(dvec3(n), omega)) * std::abs(omega.x) / r2;
      }
    }
    return sky * static_cast<float>(e * glm::length(hu) * glm::length(hv) / (kSteps * kSteps));
  };
  Sensors s;
  const vec3 tilted = glm::normalize(vec3(1.0f, 0.3f, 0.2f));
  s.add(vec3(0.0f), vec3(0, 1, 0), throughHole(vec3(0.0f), vec3(0, 1, 0)));
  s.add(vec3(-1.0f, 1.0f, 0.5f), tilted, throughHole(vec3(-1.0f, 1.0f, 0.5f), tilted));
  s.add(vec3(-1.99f, 1.5f, 0.0f), vec3(1, 0, 0), throughHole(vec3(-1.99f, 1.5f, 0.0f), vec3(1, 0, 0)));

  SceneBuilder black = room(Rgb(0.0f));
  const EstimateResult blackWithout = run(black.rdb, s, 8192);
  declarePortal(black);
  const EstimateResult blackWith = run(black.rdb, s, 8192);
  expectAgrees("open hole, black walls, declared portal", blackWith, s, 0.02f);
  expectAgrees("open hole, black walls, no portal", blackWithout, s, 0.1f);

  SceneBuilder grey = room(Rgb(0.5f));
  const EstimateResult greyWithout = run(grey.rdb, s, 8192);
  declarePortal(grey);
  const EstimateResult greyWith = run(grey.rdb, s, 8192);
  IntegratorSettings portalsOff;
  portalsOff.skyPortals = false;
  const EstimateResult greyOff = run(grey.rdb, s, 8192, portalsOff);
  for (size_t i = 0; i < s.points.size(); ++i) {
    const IrradianceEstimate& a = greyWith.points[i];
    const IrradianceEstimate& b = greyWithout.points[i];
    std::cout << "[ estimate ] open hole, grey walls #" << i << ": " << a.meanLux.g << " ± " << a.stdErrorLux.g
              << " lux with the portal, " << b.meanLux.g << " ± " << b.stdErrorLux.g << " without\n";
    for (int c = 0; c < 3; ++c) {
      const float combined = std::sqrt(a.stdErrorLux[c] * a.stdErrorLux[c] + b.stdErrorLux[c] * b.stdErrorLux[c]);
      EXPECT_LE(std::abs(a.meanLux[c] - b.meanLux[c]), 4.0f * combined) << "point " << i << " channel " << c;
      EXPECT_LE(a.stdErrorLux[c], 0.02f * a.meanLux[c]) << "point " << i << " channel " << c;
    }
    EXPECT_LT(2.0f * a.stdErrorLux.g, b.stdErrorLux.g) << "grey walls, point " << i;
    EXPECT_LT(3.0f * blackWith.points[i].stdErrorLux.g, blackWithout.points[i].stdErrorLux.g)
        << "black walls, point " << i;
    // With portals off the declared one is ignored: the estimator without it, sample for sample.
    EXPECT_EQ(greyOff.points[i].meanLux.g, b.meanLux.g) << "point " << i;
  }
}

// A portal declared where there is no opening between an interior and the sky (over an open ground: both its
// sides see the sky alike) is dropped with a warning that says why: the estimate is the one without portals.
TEST(Integrator, DeclaredPortalsInTheOpenAreDroppedWithAWarning) {
  SceneBuilder b;
  b.ground(kHugeGroundHalfM, b.material(Rgb(0.5f)));
  b.uniformSky(Rgb(1000.0f));
  Sensors s;
  s.add(vec3(0.0f), vec3(0, 1, 0), Rgb(1000.0f * kPiF));
  IntegratorSettings portalsOff;
  portalsOff.skyPortals = false;
  const EstimateResult without = run(b.rdb, s, 1024, portalsOff);
  const vec3 c(1, 1, 0);  // a 1 m square standing at x = 1, facing ±X
  b.rdb.portalCornersM = {c, c + vec3(0, 0, 1), c + vec3(0, 1, 1), c, c + vec3(0, 1, 1), c + vec3(0, 1, 0)};
  std::vector<std::string> warnings;
  const log::Sink previous =
      log::setSink([&](log::Level, std::string_view m) { warnings.emplace_back(m); });
  const EstimateResult with = run(b.rdb, s, 1024);
  log::setSink(previous);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("the declared sky portal in the plane through (1.000, 1.500, 0.500) m is not used"),
            std::string::npos)
      << warnings[0];
  EXPECT_EQ(with.points[0].meanLux.g, without.points[0].meanLux.g);
  expectAgrees("sky over a ground, portal in the open", with, s, 0.02f);
}

// The same black room with its wall window (x = 2, y ∈ [1, 2]), outside a ground that emits L_g upwards
// (y = −0.01, 2 km across) under a uniform sky L_s. Inside, above the sill, E = ∫_window L(ω) T(θ_w) max(0,
// n · ω) cos θ_w / r² dA, with L(ω) the sky's above the horizon and the ground's below it where the ray
// through the window point lands on the ground: the window shows the bright ground as well as the sky. The
// ground's light is found by emitter sampling (its two huge triangles, seen through the window from a few
// % of their area) and by the continuation, which sends a share of its samples through the portal
// (IntegratorSettings::portalContinuation, portalContinuationShare): both settings are exact, and with the
// portals' continuation the error at the sensors that look down through the window is several times smaller.
TEST(Integrator, ContinuationsThroughPortalsFindTheGroundOutsideAndStayExact) {
  SceneBuilder b;
  const uint32_t black = b.material(Rgb(0.0f));
  const float h = 3.0f;
  // Floor, ceiling and the walls z = ±2 and x = −2, facing in.
  b.quad(vec3(-2, 0, -2), vec3(-2, 0, 2), vec3(2, 0, 2), vec3(2, 0, -2), black);
  b.quad(vec3(-2, h, -2), vec3(2, h, -2), vec3(2, h, 2), vec3(-2, h, 2), black);
  b.quad(vec3(-2, 0, -2), vec3(2, 0, -2), vec3(2, h, -2), vec3(-2, h, -2), black);
  b.quad(vec3(2, 0, 2), vec3(-2, 0, 2), vec3(-2, h, 2), vec3(2, h, 2), black);
  b.quad(vec3(-2, 0, 2), vec3(-2, 0, -2), vec3(-2, h, -2), vec3(-2, h, 2), black);
  // Wall x = 2 facing −X around the window z ∈ [−0.5, 0.5], y ∈ [1, 2].
  auto wall = [&](float z0, float z1, float y0, float y1) {
    b.quad(vec3(2, y0, z0), vec3(2, y0, z1), vec3(2, y1, z1), vec3(2, y1, z0), black);
  };
  wall(-2, -0.5f, 0, h);
  wall(0.5f, 2, 0, h);
  wall(-0.5f, 0.5f, 0, 1);
  wall(-0.5f, 0.5f, 2, h);
  const uint32_t glass = b.add(clearGlass(true));
  b.quad(vec3(2, 1, -0.5f), vec3(2, 2, -0.5f), vec3(2, 2, 0.5f), vec3(2, 1, 0.5f), glass);
  const float groundHalfM = 1000.0f;
  const float groundY = -0.01f;
  const Rgb groundL(3000.0f, 2000.0f, 1000.0f);
  b.plane(groundY, groundHalfM, true, b.material(Rgb(0.0f), groundL));
  const Rgb skyL(1000.0f, 2000.0f, 3000.0f);
  b.uniformSky(skyL);

  auto throughWindow = [&](const vec3& p, const vec3& n) {
    constexpr int kSteps = 400;
    dvec3 e(0.0);
    for (int i = 0; i < kSteps; ++i) {
      for (int k = 0; k < kSteps; ++k) {
        const dvec3 y(2.0, 1.0 + (i + 0.5) / kSteps, -0.5 + (k + 0.5) / kSteps);
        const dvec3 w = y - dvec3(p);
        const double r2 = glm::dot(w, w);
        const dvec3 omega = w / std::sqrt(r2);
        const double cosN = glm::dot(dvec3(n), omega);
        if (cosN <= 0.0) continue;
        dvec3 radiance(0.0);
        if (omega.y > 0.0) {
          radiance = dvec3(skyL);
        } else if (omega.y < 0.0) {
          const dvec3 land = dvec3(p) + ((double(groundY) - p.y) / omega.y) * omega;
          if (std::abs(land.x) <= groundHalfM && std::abs(land.z) <= groundHalfM) radiance = dvec3(groundL);
        }
        const double cosWindow = std::abs(omega.x);
        e += radiance * (paneTransmittance(cosWindow) * cosN * cosWindow / r2);
      }
    }
    return Rgb(e / double(kSteps * kSteps));
  };
  Sensors s;
  const vec3 down = glm::normalize(vec3(0.4f, -1.0f, 0.1f));
  const vec3 towards = glm::normalize(vec3(1.0f, -0.2f, 0.1f));
  s.add(vec3(0.0f, 2.9f, 0.0f), down, throughWindow(vec3(0.0f, 2.9f, 0.0f), down));
  s.add(vec3(-1.0f, 2.2f, 0.5f), towards, throughWindow(vec3(-1.0f, 2.2f, 0.5f), towards));

  IntegratorSettings cosineOnly;
  cosineOnly.portalContinuation = false;
  const EstimateResult withPortals = run(b.rdb, s, 4096);
  const EstimateResult cosine = run(b.rdb, s, 4096, cosineOnly);
  expectAgrees("continuation through the portal", withPortals, s, 0.02f);
  expectAgrees("cosine continuation", cosine, s, 0.1f);
  for (size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_LT(2.0f * withPortals.points[i].stdErrorLux.r, cosine.points[i].stdErrorLux.r) << "sensor " << i;
  }
}

// A mirror floor (uniform reflection r) under a rectangle that emits L downwards: a sensor facing down sees
// the rectangle's mirror image, E = r × Lambert's formula for the image; one facing up sees the rectangle
// itself. Light sampling cannot find the image; the mirror's sampled paths must.
TEST(Integrator, MirrorFloorShowsTheEmittersImage) {
  SceneBuilder b;
  rdb::TraceMaterial mirror;
  mirror.diffuse = Rgb(0.0f);
  mirror.reflection = Rgb(0.9f, 0.8f, 0.7f);
  mirror.fresnel = false;
  mirror.reflectionGlossiness = 0.0f;
  b.ground(kHugeGroundHalfM, b.add(mirror));
  const float radiance = 50.0f;
  const std::vector<vec3> rect = {vec3(-1, 2, -0.5f), vec3(1, 2, -0.5f), vec3(1, 2, 0.5f), vec3(-1, 2, 0.5f)};
  b.quad(rect[0], rect[1], rect[2], rect[3], b.material(Rgb(0.0f), Rgb(radiance)));
  std::vector<vec3> image;
  for (const vec3& c : rect) image.emplace_back(c.x, -c.y, c.z);
  Sensors s;
  const vec3 p(0.3f, 0.5f, 0.1f);
  s.add(p, vec3(0, -1, 0), mirror.reflection * lambertPolygon(p, vec3(0, -1, 0), image, radiance));
  s.add(p, vec3(0, 1, 0), Rgb(lambertPolygon(p, vec3(0, 1, 0), rect, radiance)));
  expectAgrees("mirror image", run(b.rdb, s, 16384), s, 0.03f);
}

// The sun reflected by a vertical mirror wall onto the floor: E = E_n sin e (1 + r), the direct sun and its
// image at the same elevation.
//   With caustics (a sun disc of 10° half-angle, so that the floor's sampled rays find its image often
//   enough): exact. The sun is added where a ray leaving a mirror reaches its disc, and only there.
//   Without (the default): the mirror is sampled for the sun as a GGX lobe of glossiness
//   kRegularizedGlossiness, which blurs the image but keeps nearly all its light on the floor: within 3 %
//   (the lobe's shadowing and the part of it that misses the floor), and with a small error for the real
//   sun's 0.27° disc too, which the caustic paths almost never find.
TEST(Integrator, MirrorReflectsTheSunExactlyWithCausticsAndBlurredWithout) {
  SceneBuilder b;
  b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
  rdb::TraceMaterial mirror;
  mirror.diffuse = Rgb(0.0f);
  mirror.reflection = Rgb(0.8f);
  mirror.fresnel = false;
  mirror.reflectionGlossiness = 0.0f;
  // x = 2, facing −x, 20 m wide and 10 m high.
  b.quad(vec3(2, 0, -10), vec3(2, 0, 10), vec3(2, 10, 10), vec3(2, 10, -10), b.add(mirror));
  ASSERT_LT(glm::cross(vec3(0, 0, 20), vec3(0, 10, 20)).x, 0.0f);
  const float elevationDeg = 40.0f;
  b.sun(elevationDeg, 180.0f, Rgb(100000.0f));  // in −x: its light falls towards the mirror
  Sensors s;
  s.add(vec3(0.0f), vec3(0, 1, 0),
        b.rdb.sun.normalIlluminanceLux * static_cast<float>(std::sin(degToRad(elevationDeg)) * 1.8));
  IntegratorSettings caustics;
  caustics.caustics = true;
  b.rdb.sun.halfAngleRad = static_cast<float>(degToRad(10.0));
  expectAgrees("mirrored sun", run(b.rdb, s, 16384, caustics), s, 0.05f);
  for (double halfAngleDeg : {10.0, 0.267}) {
    b.rdb.sun.halfAngleRad = static_cast<float>(degToRad(halfAngleDeg));
    const EstimateResult r = run(b.rdb, s, 16384, IntegratorSettings{});
    for (int c = 0; c < 3; ++c) {
      const float exact = s.exact[0][c];
      const float mean = r.points[0].meanLux[c];
      const float sigma = r.points[0].stdErrorLux[c];
      EXPECT_LE(std::abs(mean - exact), 4.0f * sigma + 0.03f * exact) << halfAngleDeg << "° channel " << c;
      EXPECT_LE(sigma, 0.02f * exact) << halfAngleDeg << "° channel " << c;
    }
  }
}

// A closed box whose inward walls mix a uniform mirror (r = 0.5) with diffuse (0.8 × (1 − r)) and emit L:
// albedo ρ = 0.5 + 0.4 = 0.9 at every angle, so L_i = L / (1 − ρ) everywhere and E = π L / (1 − ρ).
TEST(Integrator, WhiteFurnaceWithMirrorAndDiffuseWalls) {
  SceneBuilder b;
  rdb::TraceMaterial walls;
  walls.reflection = Rgb(0.5f);
  walls.fresnel = false;
  walls.reflectionGlossiness = 0.0f;
  walls.diffuse = Rgb(0.4f);  // the energy rule at normal incidence: (1 − 0.5) × 0.8
  walls.emissionCdM2 = Rgb(1.0f, 2.0f, 0.5f);
  b.box(vec3(-1.0f), vec3(1.0f), true, b.add(walls));
  Sensors s;
  const Rgb exact = kPiF * walls.emissionCdM2 / (1.0f - 0.9f);
  s.add(vec3(0.0f), vec3(0, 1, 0), exact);
  s.add(vec3(0.3f, -0.5f, 0.8f), vec3(-1, 2, 0.5f), exact);
  s.add(vec3(0.2f, -1.0f, 0.1f), vec3(0, 1, 0), exact);  // on the floor
  expectAgrees("mirror-diffuse furnace", run(b.rdb, s, 4096), s, 0.02f);
}

// Many point lights over a black floor, E = Σ I cos θ / d². Up to kAllPunctualLights every light is
// evaluated (no variance at all); with 100, one is chosen per sample by flux: the estimate is unbiased and
// its reported standard error honest (the RMS of (mean − exact) / σ over the sensors is near 1).
TEST(Integrator, ManyPointLightsAreChosenByFlux) {
  for (uint32_t lightCount : {kAllPunctualLights, 100u}) {
    SceneBuilder b;
    b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
    RandomSampler random(23);
    for (uint32_t i = 0; i < lightCount; ++i) {
      random.startSample(i);
      const vec2 xz = random.next2D();
      const vec2 hi = random.next2D();
      rdb::TracePunctualLight light;
      light.positionM = vec3(20.0f * xz.x - 10.0f, 1.0f + 3.0f * hi.x, 20.0f * xz.y - 10.0f);
      light.intensity = Rgb(10.0f + 990.0f * hi.y * hi.y) * Rgb(1.0f, 0.8f + 0.2f * hi.x, 0.6f + 0.4f * xz.x);
      b.rdb.punctualLights.push_back(light);
    }
    Sensors s;
    for (uint32_t i = 0; i < 60; ++i) {
      random.startSample(1000 + i);
      const vec2 u = random.next2D();
      const vec3 p(24.0f * u.x - 12.0f, 0.0f, 24.0f * u.y - 12.0f);
      Rgb e(0.0f);
      for (const rdb::TracePunctualLight& light : b.rdb.punctualLights) {
        const vec3 toLight = light.positionM - p;
        const float d = glm::length(toLight);
        e += light.intensity * (toLight.y / d / (d * d));
      }
      s.add(p, vec3(0, 1, 0), e);
    }
    const EstimateResult r = run(b.rdb, s, 4096);
    if (lightCount == kAllPunctualLights) {
      expectAgrees("all point lights", r, s, 1e-5f);
      continue;
    }
    expectAgrees("100 point lights", r, s, 0.1f);
    double z2 = 0.0;
    for (size_t i = 0; i < s.points.size(); ++i) {
      z2 += std::pow((r.points[i].meanLux.g - s.exact[i].g) / r.points[i].stdErrorLux.g, 2.0);
    }
    const double rmsZ = std::sqrt(z2 / static_cast<double>(s.points.size()));
    std::cout << "[ honesty  ] 100 point lights: RMS of (mean − exact) / σ = " << rmsZ << "\n";
    EXPECT_GT(rmsZ, 0.5);
    EXPECT_LT(rmsZ, 2.0);
  }
}

TEST(Integrator, StopsAtTargetErrorAndTimeLimit) {
  SceneBuilder b;
  b.ground(kHugeGroundHalfM, b.material(Rgb(0.0f)));
  b.uniformSky(Rgb(1000.0f));
  Sensors s;
  for (int i = 0; i < 8; ++i) s.add(vec3(static_cast<float>(i), 1, 0), vec3(1, 0.5f, 0), Rgb(0.0f));
  const EmbreeScene scene(b.rdb);
  const Integrator integrator(b.rdb, scene);
  EstimateSettings settings;
  settings.maxSamples = 1u << 20;
  settings.targetRelativeError = 0.01f;
  const EstimateResult r = estimateIrradiance(integrator, s.points, s.normals, settings);
  EXPECT_LE(r.relativeErrorP95, 0.01f);
  EXPECT_LT(r.samplesPerPoint, settings.maxSamples);
  settings.targetRelativeError = 0.0f;
  settings.timeLimitS = 0.05;
  const EstimateResult timed = estimateIrradiance(integrator, s.points, s.normals, settings);
  EXPECT_LT(timed.samplesPerPoint, settings.maxSamples);
  EXPECT_LT(timed.seconds, 1.0);
}


// Under a time limit that a doubling of the samples no longer fits, the last pass is shortened rather than the
// time left unused: given 1.25 × the time of the first two passes (n samples each, 2n in all), a third pass
// of 2n would end at about twice that, one of n/2 or fewer (whole per replicate) fits, and the estimate ends
// between 2n and 4n samples. The passes' times are measured, so an attempt whose machine slowed down or sped
// up by more than the margins may end at 2n or 4n; one of three attempts must show the shortened pass.
TEST(Integrator, ATimeLimitThatADoublingDoesNotFitGetsAShorterLastPass) {
  SceneBuilder b;
  b.ground(kHugeGroundHalfM, b.material(Rgb(0.5f)));
  b.uniformSky(Rgb(1000.0f));
  Sensors s;
  for (int i = 0; i < 4096; ++i) s.add(vec3(0.01f * static_cast<float>(i), 1, 0), vec3(0, 1, 0), Rgb(0.0f));
  const EmbreeScene scene(b.rdb);
  const Integrator integrator(b.rdb, scene);
  EstimateSettings settings;
  settings.firstPassSamples = 64;
  settings.maxSamples = 128;
  settings.threads = 1;
  bool shortened = false;
  for (int attempt = 0; attempt < 3 && !shortened; ++attempt) {
    settings.maxSamples = 128;
    settings.timeLimitS = std::numeric_limits<double>::infinity();
    const EstimateResult twoPasses = estimateIrradiance(integrator, s.points, s.normals, settings);
    ASSERT_EQ(twoPasses.samplesPerPoint, 128u);
    settings.maxSamples = 1u << 20;
    settings.timeLimitS = 1.25 * twoPasses.seconds;
    const EstimateResult timed = estimateIrradiance(integrator, s.points, s.normals, settings);
    EXPECT_EQ(timed.samplesPerPoint % timed.replicates, 0u);
    for (const IrradianceEstimate& e : timed.points) EXPECT_TRUE(std::isfinite(e.meanLux.g) && e.meanLux.g > 0.0f);
    std::cout << "[ time limit ] " << settings.timeLimitS << " s: " << timed.samplesPerPoint << " samples in "
              << timed.seconds << " s\n";
    shortened = timed.samplesPerPoint > 128u && timed.samplesPerPoint < 256u;
  }
  EXPECT_TRUE(shortened);
}

// Reflection fog: a floor of fog distance D and fog colour c under an emissive ceiling of radiance L at
// height H (both 10 km wide, as infinite planes), seen by a sensor facing down. The floor's irradiance is
// E = π L, so the fog's radiance is L_fog = c E / π = c L, and a ray reflected at μ = cos θ from the normal
// meets the ceiling at d = H / μ: t(μ) = min(μ0 / μ, 1), μ0 = H / D. For a mirror of uniform reflection r the
// sensor receives E_s = 2π r L ∫₀¹ (1 − t (1 − c)) μ dμ = π r L (1 − (1 − c)(2 μ0 − μ0²)), μ0 ≤ 1.
TEST(Integrator, ReflectionFogOfAMirrorUnderAnEmissiveCeilingFollowsTheClosedForm) {
  const float ceilingM = 2.0f;
  const float radiance = 100.0f;
  const Rgb fogColor(0.2f, 0.5f, 0.8f);
  for (const float fogDistanceM : {4.0f, 2.5f, 1.0f, std::numeric_limits<float>::infinity()}) {
    SceneBuilder b;
    rdb::TraceMaterial mirror;
    mirror.diffuse = Rgb(0.0f);
    mirror.reflection = Rgb(0.9f);
    mirror.fresnel = false;
    mirror.reflectionGlossiness = 0.0f;
    mirror.reflectionFogDistanceM = fogDistanceM;
    mirror.reflectionFogColor = fogColor;
    b.ground(kHugeGroundHalfM, b.add(mirror));
    b.plane(ceilingM, kHugeGroundHalfM, false, b.material(Rgb(0.0f), Rgb(radiance)));
    const float mu0 = std::min(ceilingM / fogDistanceM, 1.0f);
    Sensors s;
    s.add(vec3(0.3f, 1.0f, -0.2f), vec3(0, -1, 0),
          kPiF * mirror.reflection * radiance * (Rgb(1.0f) - (Rgb(1.0f) - fogColor) * (2.0f * mu0 - mu0 * mu0)));
    expectAgrees("fogged mirror under a ceiling", run(b.rdb, s, 4096), s, 0.02f);
  }
}

// The same floor under a uniform sky of radiance L and nothing else: every reflected ray meets nothing (t =
// 1), so the mirror shows the fog alone: E_s = r π c E / π with E = π L, i.e. π r c L.
TEST(Integrator, ReflectionFogOfAMirrorUnderTheSkyIsTheFogColourTimesTheIrradiance) {
  SceneBuilder b;
  rdb::TraceMaterial mirror;
  mirror.diffuse = Rgb(0.0f);
  mirror.reflection = Rgb(0.8f);
  mirror.fresnel = false;
  mirror.reflectionGlossiness = 0.0f;
  mirror.reflectionFogDistanceM = 50.0f;
  mirror.reflectionFogColor = Rgb(0.1f, 0.4f, 0.9f);
  b.ground(kHugeGroundHalfM, b.add(mirror));
  const float skyRadiance = 1000.0f;
  b.uniformSky(Rgb(skyRadiance));
  Sensors s;
  s.add(vec3(0, 1.5f, 0), vec3(0, -1, 0), kPiF * mirror.reflection * mirror.reflectionFogColor * skyRadiance);
  expectAgrees("fogged mirror under the sky", run(b.rdb, s, 1024), s, 0.01f);
}

// A point light of intensity I at height H above a fogged mirror floor and a sensor facing down at height h
// below it: the mirror's reflected rays meet nothing (t = 1), and the sensor sees the floor as a Lambertian
// surface of radiance r c E(ρ) / π, E(ρ) = I H / (ρ² + H²)^{3/2}: E_s = r c I H h² · 2 ∫₀^∞ ρ / ((ρ² + H²)^{3/2}
// (ρ² + h²)²) dρ, integrated numerically (the fog's virtual vertex samples the point light). With caustics on,
// the light's own image in the mirror (a point, which no path meets) is left out, as without fog; by default
// the mirror's regularised lobe shows it blurred, faded by 1 − t(3 m) (IntegratorSettings::caustics).
TEST(Integrator, ReflectionFogGathersAPointLightsIrradianceAtTheMirror) {
  SceneBuilder b;
  rdb::TraceMaterial mirror;
  mirror.diffuse = Rgb(0.0f);
  mirror.reflection = Rgb(0.7f);
  mirror.fresnel = false;
  mirror.reflectionGlossiness = 0.0f;
  mirror.reflectionFogDistanceM = 10.0f;
  mirror.reflectionFogColor = Rgb(0.3f, 0.6f, 0.9f);
  b.ground(kHugeGroundHalfM, b.add(mirror));
  rdb::TracePunctualLight light;
  const double lightM = 3.0;
  const double sensorM = 1.0;
  light.positionM = vec3(0.0f, float(lightM), 0.0f);
  light.intensity = Rgb(1000.0f);
  b.rdb.punctualLights.push_back(light);
  // ρ = u / (1 − u) maps [0, 1) onto [0, ∞); midpoint rule in u.
  double integral = 0.0;
  const int steps = 1 << 20;
  for (int i = 0; i < steps; ++i) {
    const double u = (i + 0.5) / steps;
    const double rho = u / (1.0 - u);
    const double dRho = 1.0 / ((1.0 - u) * (1.0 - u)) / steps;
    integral += rho / (std::pow(rho * rho + lightM * lightM, 1.5) * std::pow(rho * rho + sensorM * sensorM, 2.0)) *
                dRho;
  }
  const float geometric = float(lightM * sensorM * sensorM * 2.0 * integral);
  Sensors s;
  s.add(vec3(0.0f, float(sensorM), 0.0f), vec3(0, -1, 0),
        mirror.reflection * mirror.reflectionFogColor * light.intensity * geometric);
  IntegratorSettings exact;
  exact.caustics = true;
  expectAgrees("fogged mirror under a point light", run(b.rdb, s, 4096, exact), s, 0.01f);
}

// A glossy floor with a diffuse base (uniform reflection r = 0.6, glossiness 0.5, D(0) = 0.2) and fog under
// the emissive ceiling: its light sampling of the ceiling fades the reflection lobe by 1 − t(d) while its
// diffuse lobe keeps all, and its sampled reflections choose between the ceiling and the fog. Against a
// quadrature of the Bsdf: E_s = 2π ∫ L_o(μo) μo dμo, L_o = L ∫ (f − t(μi)(1 − c) f_r) μi dωi, f_r the lobe of
// the same material without its diffuse base.
TEST(Integrator, ReflectionFogOfAGlossyFloorAgreesWithAQuadratureOfItsBsdf) {
  const float ceilingM = 2.0f;
  const float radiance = 100.0f;
  const float fogDistanceM = 3.0f;
  const Rgb fogColor(0.1f, 0.5f, 0.9f);
  rdb::TraceMaterial floor;
  floor.diffuse = Rgb(0.2f);
  floor.reflection = Rgb(0.6f);
  floor.fresnel = false;
  floor.reflectionGlossiness = 0.5f;
  floor.reflectionFogDistanceM = fogDistanceM;
  floor.reflectionFogColor = fogColor;
  rdb::TraceMaterial lobeOnly = floor;
  lobeOnly.diffuse = Rgb(0.0f);
  const Bsdf all(floor, true);
  const Bsdf reflection(lobeOnly, true);
  const float mu0 = ceilingM / fogDistanceM;
  const int outer = 64;
  const int inner = 384;
  const int azimuths = 384;
  Rgb sensorLux(0.0f);
  for (int o = 0; o < outer; ++o) {
    const float muO = (float(o) + 0.5f) / float(outer);
    const vec3 wo(std::sqrt(1.0f - muO * muO), 0.0f, muO);
    Rgb outgoing(0.0f);
    for (int i = 0; i < inner; ++i) {
      const float muI = (float(i) + 0.5f) / float(inner);
      const float t = std::min(mu0 / muI, 1.0f);
      const float sinI = std::sqrt(1.0f - muI * muI);
      for (int a = 0; a < azimuths; ++a) {
        const float phi = 2.0f * kPiF * (float(a) + 0.5f) / float(azimuths);
        const vec3 wi(sinI * std::cos(phi), sinI * std::sin(phi), muI);
        outgoing += (all.eval(wo, wi) - t * (Rgb(1.0f) - fogColor) * reflection.eval(wo, wi)) * muI;
      }
    }
    outgoing *= radiance * (1.0f / float(inner)) * (2.0f * kPiF / float(azimuths));
    sensorLux += outgoing * muO;
  }
  sensorLux *= 2.0f * kPiF / float(outer);
  SceneBuilder b;
  b.ground(kHugeGroundHalfM, b.add(floor));
  b.plane(ceilingM, kHugeGroundHalfM, false, b.material(Rgb(0.0f), Rgb(radiance)));
  Sensors s;
  s.add(vec3(0.3f, 1.0f, -0.2f), vec3(0, -1, 0), sensorLux);
  expectAgrees("fogged glossy floor under a ceiling", run(b.rdb, s, 4096), s, 0.02f);
}

}  // namespace
}  // namespace fly::raytracer
