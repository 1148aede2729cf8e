// The vertex baker against exact answers: each vertex's estimate must lie within 4 of its
// reported standard errors of the exact hat-weighted one-ring average, with that error small enough for the
// comparison to mean something.
#include "raytracer/baker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <thread>
#include <vector>

#include "raytracer/sampler.h"
#include "raytracer/warp.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::raytracer {
namespace {

using MeshBuilder = rdb::TraceRdbBuilder;

// Tests estimate each vertex's error from 64 replicates (as integrator_test.cpp: with 8, a 4σ bound fails by
// chance on about 1 vertex in 200).
constexpr uint32_t kTestReplicates = 64;

VertexLightMaps bake(const rdb::TraceRdb& rdb, uint32_t samples, uint32_t replicates = kTestReplicates,
                     uint32_t threads = 0, const BakeProgress& progress = {}) {
  const EmbreeScene scene(rdb);
  BakeSettings settings;
  settings.estimate.firstPassSamples = std::max(replicates, 8u);
  settings.estimate.maxSamples = samples;
  settings.estimate.replicates = replicates;
  settings.estimate.threads = threads;
  return bakeVertexLightMaps(rdb, scene, settings, progress);
}

// The hat-weighted one-ring average ∫ b_v f dA / ∫ b_v dA of every vertex by the midpoint rule on n²
// sub-triangles of each triangle.
template <class F>
std::vector<double> hatAverages(const rdb::TraceRdb& rdb, F f, uint32_t n = 200) {
  std::vector<double> weighted(rdb.positionsM.size(), 0.0);
  std::vector<double> weights(rdb.positionsM.size(), 0.0);
  for (size_t t = 0; t < rdb.triangleCount(); ++t) {
    const uint32_t* idx = &rdb.indices[3 * t];
    const vec3 a = rdb.positionsM[idx[0]];
    const vec3 e1 = rdb.positionsM[idx[1]] - a;
    const vec3 e2 = rdb.positionsM[idx[2]] - a;
    const double subArea = 0.5 * glm::length(glm::cross(e1, e2)) / (static_cast<double>(n) * n);
    // Sub-triangle centroids in (b1, b2), upward and downward ones.
    for (uint32_t i = 0; i < n; ++i) {
      for (uint32_t j = 0; i + j < n; ++j) {
        for (int down = 0; down < 2 && (down == 0 || i + j + 1 < n); ++down) {
          const double b1 = (i + (down ? 2.0 : 1.0) / 3.0) / n;
          const double b2 = (j + (down ? 2.0 : 1.0) / 3.0) / n;
          const double b[3] = {1.0 - b1 - b2, b1, b2};
          const double value = f(a + static_cast<float>(b1) * e1 + static_cast<float>(b2) * e2);
          for (int k = 0; k < 3; ++k) {
            weighted[idx[k]] += b[k] * value * subArea;
            weights[idx[k]] += b[k] * subArea;
          }
        }
      }
    }
  }
  for (size_t v = 0; v < weighted.size(); ++v) weighted[v] /= weights[v];
  return weighted;
}

// |mean − exact| < 4 σ + 10⁻⁵ exact per channel, and σ ≤ maxRelStdError · exact.
void expectAgrees(const char* what, const std::vector<Rgb>& mean, const std::vector<Rgb>& stdError,
                  const std::vector<Rgb>& exact, float maxRelStdError) {
  double worst = 0.0;
  for (size_t v = 0; v < mean.size(); ++v) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(std::abs(mean[v][c] - exact[v][c]), 4.0f * stdError[v][c] + 1e-5f * exact[v][c] + 1e-6f)
          << what << " vertex " << v << " channel " << c << ": " << mean[v][c] << " ± " << stdError[v][c]
          << ", exact " << exact[v][c];
      EXPECT_LE(stdError[v][c], maxRelStdError * exact[v][c] + 1e-6f) << what << " vertex " << v;
      if (stdError[v][c] > 0.0f)
        worst = std::max(worst, std::abs(mean[v][c] - exact[v][c]) / double{stdError[v][c]});
    }
  }
  std::cout << "[ baker    ] " << what << ": " << mean.size() << " vertices, worst error " << worst << " σ\n";
}

void expectAllFinite(const VertexLightMaps& maps) {
  for (const std::vector<Rgb>* values :
       {&maps.frontLux, &maps.frontStdErrorLux, &maps.backLux, &maps.backStdErrorLux}) {
    for (const Rgb& x : *values) {
      EXPECT_TRUE(std::isfinite(x.r) && std::isfinite(x.g) && std::isfinite(x.b));
      EXPECT_TRUE(x.r >= 0.0f && x.g >= 0.0f && x.b >= 0.0f);
    }
  }
}

TEST(Baker, UniformSkyOverPlaneIsPiLAtEveryVertex) {
  MeshBuilder b;
  b.ground(10.0f, 6, b.material(Rgb(0.5f)));
  const Rgb sky(1.0f, 2.0f, 3.0f);
  b.uniformSky(sky);
  const VertexLightMaps maps = bake(b.rdb, 1024);
  expectAllFinite(maps);
  expectAgrees("sky", maps.frontLux, maps.frontStdErrorLux,
               std::vector<Rgb>(b.rdb.positionsM.size(), kPiF * sky), 0.01f);
  for (const Rgb& back : maps.backLux) EXPECT_EQ(back, Rgb(0.0f));
  EXPECT_EQ(maps.unfilledVertices, 0u);
}

// FLY §3's sunlight mode: the bake keeps the sun's direct part E_sunDirect apart. Under the sun alone (black
// sky, nothing else to reflect light back), every sample is the sensor's sun sample: E_sunDirect = E =
// E_n cos θ at every vertex (a uniform disc's ∫ cos over its cone is cos θ at its centre times its solid
// angle's projected area, exactly), and E − E_sunDirect = 0 exactly.
TEST(Baker, UnderTheSunAloneEveryVertexIsSunDirect) {
  MeshBuilder b;
  b.ground(3.0f, 6, b.material(Rgb(0.5f)));
  const vec3 towardsSun = glm::normalize(vec3(0.5f, 0.8f, -0.3f));
  const Rgb normalLux(90000.0f, 80000.0f, 60000.0f);
  b.sun(towardsSun, normalLux);
  const VertexLightMaps maps = bake(b.rdb, 256);
  ASSERT_TRUE(maps.hasSunDirect());
  ASSERT_EQ(maps.frontSunDirectLux.size(), b.rdb.positionsM.size());
  expectAgrees("sun alone", maps.frontSunDirectLux, maps.frontSunDirectStdErrorLux,
               std::vector<Rgb>(b.rdb.positionsM.size(), normalLux * towardsSun.y), 0.001f);
  for (size_t v = 0; v < maps.frontLux.size(); ++v) {
    EXPECT_EQ(maps.frontLux[v], maps.frontSunDirectLux[v]) << "vertex " << v;
    EXPECT_EQ(maps.frontStdErrorLux[v], maps.frontSunDirectStdErrorLux[v]) << "vertex " << v;
  }
  ASSERT_FALSE(maps.history.empty());
  EXPECT_GT(maps.history.back().sunDirectRelativeErrorP95, 0.0f);
  EXPECT_LT(maps.history.back().sunDirectRelativeErrorP95, 1e-3f);

  // Without a sun (or with one below the horizon, which has no illuminance) nothing extra is kept.
  MeshBuilder night;
  night.ground(3.0f, 2, night.material(Rgb(0.5f)));
  night.uniformSky(Rgb(1.0f));
  EXPECT_FALSE(bake(night.rdb, 16, 8).hasSunDirect());
  night.sun(vec3(0.3f, -0.2f, 0.1f), Rgb(0.0f));
  const VertexLightMaps belowHorizon = bake(night.rdb, 16, 8);
  EXPECT_FALSE(belowHorizon.hasSunDirect());
  EXPECT_TRUE(belowHorizon.frontSunDirectStdErrorLux.empty() && belowHorizon.backSunDirectLux.empty());
}

// With a sky, a roof that casts a shadow and surfaces that reflect (the sun's light among them): E_sunDirect
// on the ground is the hat-weighted average of E_n cos θ over its sunlit part (quadrature), and
// E − E_sunDirect agrees with an independent bake's E (another seed) minus that exact E_sunDirect — the rest,
// sky and all interreflections, from the same samples as E.
TEST(Baker, SunDirectIsTheSunsShareAndTheRestIsEverythingElse) {
  MeshBuilder b;
  const uint32_t grey = b.material(Rgb(0.5f));
  b.ground(2.0f, 10, grey);
  // The roof: y = 1 over x ∈ [−2, 0], facing down.
  b.grid(vec3(-2.0f, 1.0f, -2.0f), vec3(2.0f, 0, 0), vec3(0, 0, 4.0f), 2, grey);
  const Rgb skyCdM2(2000.0f);
  b.uniformSky(skyCdM2);
  const vec3 towardsSun = glm::normalize(vec3(-0.6f, 1.0f, 0.2f));
  const Rgb normalLux(50000.0f);
  b.sun(towardsSun, normalLux);
  const auto lit = [&](const vec3& p) {
    const float t = (1.0f - p.y) / towardsSun.y;
    const vec3 q = p + t * towardsSun;
    return !(q.x >= -2.0f && q.x <= 0.0f && q.z >= -2.0f && q.z <= 2.0f);
  };
  const std::vector<double> sunAverage = hatAverages(
      b.rdb, [&](const vec3& p) { return lit(p) ? double{towardsSun.y} : 0.0; }, 100);
  const uint32_t groundVertices = b.rdb.meshes[0].vertexCount;

  const EmbreeScene scene(b.rdb);
  auto run = [&](uint64_t seed) {
    BakeSettings settings;
    settings.estimate.firstPassSamples = kTestReplicates;
    settings.estimate.maxSamples = 1024;
    settings.estimate.replicates = kTestReplicates;
    settings.estimate.seed = seed;
    return bakeVertexLightMaps(b.rdb, scene, settings);
  };
  const VertexLightMaps maps = run(1);
  const VertexLightMaps other = run(7777777);
  ASSERT_TRUE(maps.hasSunDirect());
  std::vector<Rgb> exactSun, sun, sunError;
  for (uint32_t v = 0; v < groundVertices; ++v) {
    exactSun.push_back(normalLux * float(sunAverage[v]));
    sun.push_back(maps.frontSunDirectLux[v]);
    sunError.push_back(maps.frontSunDirectStdErrorLux[v]);
  }
  // Shaded vertices have E_sunDirect = 0 exactly, with no error to compare against.
  expectAgrees("sun direct, ground", sun, sunError, exactSun, 0.2f);
  double worst = 0.0, restSum = 0.0;
  size_t shaded = 0, partly = 0;
  for (uint32_t v = 0; v < groundVertices; ++v) {
    shaded += sunAverage[v] == 0.0;
    partly += sunAverage[v] > 0.0 && sunAverage[v] < towardsSun.y * (1 - 1e-3);
    const Rgb rest = maps.frontLux[v] - maps.frontSunDirectLux[v];
    const Rgb restElsewhere = other.frontLux[v] - exactSun[v];
    // The error of a difference is at most the sum of the errors (whatever their correlation).
    const Rgb bound =
        maps.frontStdErrorLux[v] + maps.frontSunDirectStdErrorLux[v] + other.frontStdErrorLux[v];
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(std::abs(rest[c] - restElsewhere[c]), 4.0f * bound[c] + 1e-5f * other.frontLux[v][c])
          << "vertex " << v << " channel " << c << ": rest " << rest[c] << ", independent "
          << restElsewhere[c];
      EXPECT_GE(rest[c], -1e-3f * maps.frontLux[v][c]) << "vertex " << v;
      if (bound[c] > 0.0f) worst = std::max(worst, double(std::abs(rest[c] - restElsewhere[c]) / bound[c]));
    }
    restSum += luminance(rest);
  }
  std::cout << "[ baker    ] sun and rest: " << groundVertices << " ground vertices (" << shaded
            << " shaded, " << partly << " on the shadow edge), mean rest " << restSum / groundVertices
            << " lx, worst |rest − independent| " << worst << " × the summed errors\n";
  EXPECT_GT(shaded, 5u);
  EXPECT_GT(partly, 5u);
  // The rest holds the sky (π L unshaded) and the sun's interreflections: well above 0 everywhere.
  for (uint32_t v = 0; v < groundVertices; ++v)
    EXPECT_GT(luminance(maps.frontLux[v] - maps.frontSunDirectLux[v]), 0.1f * kPiF * luminance(skyCdM2));
}

// E(x) = I cos θ / d² = I h / d³, averaged over each one-ring with the hat weight by quadrature.
void expectPointLightOverPlane(const char* what, MeshBuilder& b) {
  const vec3 light(0.3f, 0.7f, -0.2f);
  const Rgb intensity(10.0f, 20.0f, 5.0f);
  b.pointLight(light, intensity);
  const std::vector<double> average = hatAverages(b.rdb, [&](const vec3& x) {
    const double d = glm::length(dvec3(light) - dvec3(x));
    return double{light.y - x.y} / (d * d * d);
  });
  std::vector<Rgb> exact;
  for (double a : average) exact.push_back(intensity * static_cast<float>(a));
  const VertexLightMaps maps = bake(b.rdb, 4096);
  expectAllFinite(maps);
  expectAgrees(what, maps.frontLux, maps.frontStdErrorLux, exact, 0.01f);
  // The one-ring average differs from the value at the vertex (E is not linear): the test can tell them
  // apart.
  const vec3 centre = b.rdb.positionsM[12];
  const double atCentre = light.y / std::pow(glm::length(light - centre), 3.0f);
  EXPECT_GT(std::abs(average[12] - atCentre), 10.0 * maps.frontStdErrorLux[12].g / intensity.g);
}

TEST(Baker, PointLightOverPlaneIsTheHatWeightedOneRingAverage) {
  MeshBuilder b;
  b.ground(2.0f, 4, b.material(Rgb(0.0f)));
  expectPointLightOverPlane("point light", b);
}

// The same on rings of unequal triangles wound either way: the baker orders each ring around its vertex and
// each triangle's corners by their turning sense (baker.cpp), which must not change the density it samples.
TEST(Baker, PointLightOverAnIrregularMixedWindingPlaneIsTheHatWeightedOneRingAverage) {
  MeshBuilder b;
  b.ground(2.0f, 4, b.material(Rgb(0.0f)));
  // Inner vertices moved by up to 0.15 m within their 1 m cells, the rim kept: no triangle folds over.
  for (vec3& p : b.rdb.positionsM) {
    if (std::abs(p.x) < 1.99f && std::abs(p.z) < 1.99f) {
      p.x += 0.15f * std::sin(7.0f * p.z + 1.0f);
      p.z += 0.12f * std::cos(5.0f * p.x + 2.0f);
    }
  }
  for (size_t t = 1; t < b.rdb.triangleCount(); t += 2)
    std::swap(b.rdb.indices[3 * t + 1], b.rdb.indices[3 * t + 2]);
  expectPointLightOverPlane("irregular point light", b);
}

TEST(Baker, TwoSidedQuadIsLitOnTheSideOfTheLight) {
  const Rgb lux(100.0f, 200.0f, 50.0f);
  const vec3 towardsLight = glm::normalize(vec3(0.3f, 1.0f, 0.2f));
  const float cosTheta = towardsLight.y;
  for (float side : {1.0f, -1.0f}) {
    MeshBuilder b;
    b.ground(1.0f, 2, b.material(Rgb(0.5f)), true);
    b.directionalLight(side * towardsLight, lux);
    const VertexLightMaps maps = bake(b.rdb, 256);
    expectAllFinite(maps);
    const std::vector<Rgb> lit(b.rdb.positionsM.size(), lux * cosTheta);
    const std::vector<Rgb> dark(b.rdb.positionsM.size(), Rgb(0.0f));
    expectAgrees(side > 0 ? "lit from above, front" : "lit from below, front", maps.frontLux,
                 maps.frontStdErrorLux, side > 0 ? lit : dark, 1e-4f);
    expectAgrees(side > 0 ? "lit from above, back" : "lit from below, back", maps.backLux,
                 maps.backStdErrorLux, side > 0 ? dark : lit, 1e-4f);
  }
}

// The vertex normals choose the front: here −Y, against the triangles' winding (+Y), so that a light from
// below lights the front. A NaN vertex normal makes the interpolated normal NaN; the geometric normal on the
// side of the vertex normal replaces it.
TEST(Baker, VertexNormalsChooseTheFrontAndBadOnesFallBack) {
  const Rgb lux(100.0f);
  const vec3 towardsLight = glm::normalize(vec3(0.3f, -1.0f, 0.2f));
  MeshBuilder b;
  b.ground(1.0f, 2, b.material(Rgb(0.5f)));
  for (vec3& n : b.rdb.normals) n = vec3(0, -1, 0);
  b.rdb.normals[0] = vec3(std::nanf(""));
  b.directionalLight(towardsLight, lux);
  const VertexLightMaps maps = bake(b.rdb, 64, 8);
  expectAllFinite(maps);
  expectAgrees("lit from below, normals down", maps.frontLux, maps.frontStdErrorLux,
               std::vector<Rgb>(b.rdb.positionsM.size(), lux * -towardsLight.y), 1e-4f);
}

// A closed box of albedo ρ whose walls emit L: every vertex sees E = π L / (1 − ρ).
TEST(Baker, WhiteFurnaceBoxIsPiLOverOneMinusAlbedo) {
  MeshBuilder b;
  const float albedo = 0.5f;
  const Rgb emission(1.0f, 2.0f, 0.5f);
  const uint32_t mat = b.material(Rgb(albedo), emission);
  const vec3 lo(-1.0f);
  const vec3 x(2, 0, 0);
  const vec3 y(0, 2, 0);
  const vec3 z(0, 0, 2);
  // Inward-facing walls.
  b.grid(lo, x, y, 2, mat);
  b.grid(lo + z, y, x, 2, mat);
  b.grid(lo, y, z, 2, mat);
  b.grid(lo + x, z, y, 2, mat);
  b.grid(lo, z, x, 2, mat);
  b.grid(lo + y, x, z, 2, mat);
  const VertexLightMaps maps = bake(b.rdb, 4096);
  expectAllFinite(maps);
  expectAgrees("furnace", maps.frontLux, maps.frontStdErrorLux,
               std::vector<Rgb>(b.rdb.positionsM.size(), kPiF * emission / (1.0f - albedo)), 0.01f);
}

// Over the vertices of a plane under sky and point light, the RMS of the actual errors must match the RMS of
// the reported standard errors, with 8 plain replicates and with the default 2, moderated by the pooled
// variance (progressive.h). (Not their mean: the errors near the light are far larger than the rest, and the
// RMS of unequal σ exceeds their mean, here about 2×.) With 1024 samples: at 64 (8 per replicate) the
// replicate means of this skewed integrand (I h / d³ near the light) are too few and the ratio is about 1.35
// over seeds, at 1024 about 1.1.
TEST(Baker, ReportedStandardErrorIsHonest) {
  MeshBuilder b;
  b.ground(2.0f, 8, b.material(Rgb(0.0f)));
  const vec3 light(0.3f, 0.5f, -0.2f);
  const float intensity = 10.0f;
  const float sky = 1.0f;
  b.pointLight(light, Rgb(intensity));
  b.uniformSky(Rgb(sky));
  const std::vector<double> average = hatAverages(
      b.rdb,
      [&](const vec3& p) {
        const double d = glm::length(dvec3(light) - dvec3(p));
        return double{light.y - p.y} / (d * d * d);
      },
      100);
  for (uint32_t replicates : {8u, 0u}) {  // 0: automatic, 2 for these 81 vertices
    const VertexLightMaps maps = bake(b.rdb, 1024, replicates);
    EXPECT_EQ(maps.replicates, replicates == 0 ? 2u : replicates);
    double squaredError = 0.0;
    double reported = 0.0;  // Σ σ²
    for (size_t v = 0; v < average.size(); ++v) {
      const double exact = intensity * average[v] + kPi * sky;
      squaredError += (maps.frontLux[v].g - exact) * (maps.frontLux[v].g - exact);
      reported += maps.frontStdErrorLux[v].g * maps.frontStdErrorLux[v].g;
    }
    const double ratio = std::sqrt(squaredError / reported);
    std::cout << "[ baker    ] " << replicates << " replicates: RMS error / RMS reported error = " << ratio
              << " over " << average.size() << " vertices\n";
    EXPECT_GE(ratio, 0.5) << replicates;
    EXPECT_LE(ratio, 2.0) << replicates;
  }
}

// Black ground lit by a point light (smooth: the Sobol' nets gain a lot) and by a directional light that a
// black roof shades from part of it (a step across some one-rings: a small gain). Exact: the hat-weighted
// average of I h / d³ + E cos θ · [the ray towards the directional light misses the roof].
struct ShadowEdgeScene {
  MeshBuilder b;
  std::vector<double> average;  // per vertex, lux
  uint32_t groundVertices = 0;
  std::vector<bool> edge;  // per ground vertex: its one-ring average is neither fully lit nor fully shaded
};

ShadowEdgeScene shadowEdgeScene() {
  ShadowEdgeScene s;
  MeshBuilder& b = s.b;
  const uint32_t black = b.material(Rgb(0.0f));
  b.ground(2.0f, 12, black);
  // The roof: y = 1 over x ∈ [−2, 0], facing down.
  b.grid(vec3(-2.0f, 1.0f, -2.0f), vec3(2.0f, 0, 0), vec3(0, 0, 4.0f), 2, black);
  const vec3 light(1.2f, 0.6f, 0.1f);
  const float intensity = 5.0f;
  b.pointLight(light, Rgb(intensity));
  const vec3 towardsSun = glm::normalize(vec3(0.6f, 1.0f, 0.2f));
  const float sunLux = 10.0f;
  b.directionalLight(towardsSun, Rgb(sunLux));
  const auto lit = [&](const vec3& p) {
    const float t = (1.0f - p.y) / towardsSun.y;
    const vec3 q = p + t * towardsSun;
    return !(q.x >= -2.0f && q.x <= 0.0f && q.z >= -2.0f && q.z <= 2.0f);
  };
  s.average = hatAverages(
      b.rdb,
      [&](const vec3& p) {
        const double d = glm::length(dvec3(light) - dvec3(p));
        return intensity * double{light.y - p.y} / (d * d * d) +
               (lit(p) ? sunLux * double{towardsSun.y} : 0.0);
      },
      100);
  s.groundVertices = b.rdb.meshes[0].vertexCount;
  const std::vector<double> litFraction = hatAverages(
      b.rdb, [&](const vec3& p) { return lit(p) ? 1.0 : 0.0; }, 100);
  s.edge.resize(s.groundVertices);
  for (uint32_t v = 0; v < s.groundVertices; ++v)
    s.edge[v] = litFraction[v] > 1e-3 && litFraction[v] < 1 - 1e-3;
  return s;
}

// The default settings' error on a shadow edge, where the vertices gain unequally from the Sobol' nets (the
// pooled variance assumes they gain alike). Along the whole curve (16 … 1024 samples, 4 seeds each) the RMS
// of the actual errors over the ground's vertices matches the RMS of the reported ones within a factor of 2,
// both over all of them and over the shadow edge's alone.
TEST(Baker, DefaultErrorIsHonestOnShadowEdges) {
  const ShadowEdgeScene s = shadowEdgeScene();
  const EmbreeScene scene(s.b.rdb);
  for (uint32_t samples : {16u, 64u, 256u, 1024u}) {
    double squaredError[2] = {0.0, 0.0};  // all ground vertices, shadow edge
    double reported[2] = {0.0, 0.0};
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      BakeSettings settings;  // the defaults, but for the sample count and seed
      settings.estimate.maxSamples = samples;
      settings.estimate.seed = seed * 100000;
      const VertexLightMaps maps = bakeVertexLightMaps(s.b.rdb, scene, settings);
      EXPECT_EQ(maps.replicates, 2u);
      for (uint32_t v = 0; v < s.groundVertices; ++v) {
        const double e2 = std::pow(maps.frontLux[v].g - s.average[v], 2.0);
        const double s2 = std::pow(maps.frontStdErrorLux[v].g, 2.0);
        squaredError[0] += e2;
        reported[0] += s2;
        if (s.edge[v]) {
          squaredError[1] += e2;
          reported[1] += s2;
        }
      }
    }
    for (int part = 0; part < 2; ++part) {
      const double ratio = std::sqrt(squaredError[part] / reported[part]);
      std::cout << "[ baker    ] default replicates, " << samples << " samples, "
                << (part == 0 ? "all vertices" : "shadow edge")
                << ": RMS error / RMS reported error = " << ratio << "\n";
      EXPECT_GE(ratio, 0.5) << samples << " samples, part " << part;
      EXPECT_LE(ratio, 2.0) << samples << " samples, part " << part;
    }
  }
}

// With `fly bake`'s allocation by error (progressive.h), the ground's vertices far from the shadow edge and
// the light skip passes, and the estimates stay unbiased and honest against the exact answers: over 8 seeds
// at 1024 samples, the mean of the normalised errors (E − exact) / σ of the vertices that skipped is within
// 4 of its standard errors of 0, and the RMS of the actual errors matches the reported one, over the
// vertices that skipped and over all.
TEST(Baker, AllocationByErrorStaysUnbiasedAndHonest) {
  const ShadowEdgeScene s = shadowEdgeScene();
  const EmbreeScene scene(s.b.rdb);
  double sumZ = 0.0, sumZ2 = 0.0;
  double squaredError[2] = {0.0, 0.0};  // vertices that skipped, all
  double reported[2] = {0.0, 0.0};
  size_t skipped = 0, edgeSkipped = 0, edgeVertices = 0;
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    BakeSettings settings;
    settings.estimate.maxSamples = 1024;
    settings.estimate.seed = seed * 100000;
    settings.estimate.allocationFraction = kBakeAllocationFraction;
    const VertexLightMaps maps = bakeVertexLightMaps(s.b.rdb, scene, settings);
    ASSERT_EQ(maps.samplesPerVertex, 1024u);
    for (uint32_t v = 0; v < s.groundVertices; ++v) {
      const double error = maps.frontLux[v].g - s.average[v];
      const double sigma = maps.frontStdErrorLux[v].g;
      const bool skip = maps.frontSamples[v] < maps.samplesPerVertex;
      edgeVertices += s.edge[v] ? 1 : 0;
      edgeSkipped += s.edge[v] && skip ? 1 : 0;
      for (int part = skip ? 0 : 1; part < 2; ++part) {
        squaredError[part] += error * error;
        reported[part] += sigma * sigma;
      }
      if (!skip) continue;
      ASSERT_GT(sigma, 0.0) << "vertex " << v;
      sumZ += error / sigma;
      sumZ2 += (error / sigma) * (error / sigma);
      ++skipped;
    }
  }
  const double n = double(skipped);
  const double meanZ = sumZ / n;
  const double standardError = std::sqrt((sumZ2 / n - meanZ * meanZ) / (n - 1.0));
  std::cout << "[ baker    ] allocation by error: " << skipped << " of " << 8 * s.groundVertices
            << " ground vertices skipped (" << edgeSkipped << " of " << edgeVertices
            << " on the shadow edge); mean normalised error " << meanZ << " ± " << standardError << "\n";
  EXPECT_GT(skipped, 8u * s.groundVertices / 4);
  EXPECT_LT(double(edgeSkipped), 0.5 * double(edgeVertices));
  EXPECT_LT(std::abs(meanZ), 4.0 * standardError);
  for (int part = 0; part < 2; ++part) {
    const double ratio = std::sqrt(squaredError[part] / reported[part]);
    std::cout << "[ baker    ] allocation by error, " << (part == 0 ? "vertices that skipped" : "all vertices")
              << ": RMS error / RMS reported error = " << ratio << "\n";
    EXPECT_GE(ratio, 0.67) << "part " << part;
    EXPECT_LE(ratio, 1.5) << "part " << part;
  }
}

TEST(Baker, DeterministicAcrossThreadCounts) {
  MeshBuilder b;
  b.ground(2.0f, 6, b.material(Rgb(0.5f)), true);
  b.grid(vec3(-1, 0.5f, -1), vec3(2, 0, 0), vec3(0, 0, 2), 3, b.material(Rgb(0.7f)));  // a roof facing down
  b.uniformSky(Rgb(1.0f));
  b.pointLight(vec3(0.2f, 0.3f, 0.1f), Rgb(5.0f));
  b.sun(vec3(0.5f, 0.6f, 0.2f), Rgb(100.0f));
  const VertexLightMaps one = bake(b.rdb, 64, 8, 1);
  const VertexLightMaps two = bake(b.rdb, 64, 8, 2);
  EXPECT_EQ(one.frontLux, two.frontLux);
  EXPECT_EQ(one.frontStdErrorLux, two.frontStdErrorLux);
  EXPECT_EQ(one.backLux, two.backLux);
  EXPECT_EQ(one.backStdErrorLux, two.backStdErrorLux);
  ASSERT_TRUE(one.hasSunDirect());
  EXPECT_EQ(one.frontSunDirectLux, two.frontSunDirectLux);
  EXPECT_EQ(one.frontSunDirectStdErrorLux, two.frontSunDirectStdErrorLux);
  EXPECT_EQ(one.backSunDirectLux, two.backSunDirectLux);
  EXPECT_EQ(one.rays, two.rays);
}

TEST(Baker, HistoryHasOneRowPerPassAndProgressCanStop) {
  MeshBuilder b;
  b.ground(2.0f, 4, b.material(Rgb(0.5f)));
  b.uniformSky(Rgb(1.0f));
  b.pointLight(vec3(0.2f, 0.3f, 0.1f), Rgb(5.0f));
  uint32_t calls = 0;
  const VertexLightMaps maps =
      bake(b.rdb, 1024, 8, 0, [&](const ConvergencePoint& latest, uint32_t maxSamples) {
        EXPECT_EQ(maxSamples, 1024u);
        EXPECT_GT(latest.raysPerSecond, 0.0);
        ++calls;
        return true;
      });
  // Passes of 8, 8, 16, …, 512 samples: totals 8, 16, …, 1024.
  ASSERT_EQ(maps.history.size(), 8u);
  EXPECT_EQ(calls, 8u);
  EXPECT_EQ(maps.samplesPerVertex, 1024u);
  for (size_t i = 0; i < maps.history.size(); ++i) {
    std::cout << "[ history  ] " << maps.history[i].samples << " samples, " << maps.history[i].seconds
              << " s, p95 " << maps.history[i].relativeErrorP95 << "\n";
    EXPECT_EQ(maps.history[i].samples, 8u << i);
    if (i > 0) {
      EXPECT_GE(maps.history[i].seconds, maps.history[i - 1].seconds);
    }
  }
  // The error falls at least as 1/√N over 128× the samples (in expectation; with a wide margin).
  EXPECT_LT(maps.history.back().relativeErrorP95, maps.history.front().relativeErrorP95 / 4.0f);

  const VertexLightMaps stopped =
      bake(b.rdb, 1024, 8, 0, [](const ConvergencePoint& latest, uint32_t) { return latest.samples < 16; });
  EXPECT_EQ(stopped.history.size(), 2u);
  EXPECT_EQ(stopped.samplesPerVertex, 16u);
}

// A vertex only on a degenerate triangle takes its neighbours' value; vertices that have none (unused, or on
// a lone degenerate triangle) are 0 and counted.
TEST(Baker, VerticesWithoutAOneRingAreFilledOrCounted) {
  MeshBuilder b;
  const uint32_t mat = b.material(Rgb(0.0f));
  b.ground(1.0f, 1, mat);  // vertices 0 … 3
  const Rgb sky(1.0f);
  b.uniformSky(sky);
  auto vertex = [&](const vec3& p) {
    b.rdb.positionsM.push_back(p);
    b.rdb.normals.push_back(vec3(0, 1, 0));
    return static_cast<uint32_t>(b.rdb.positionsM.size() - 1);
  };
  // Collinear with the ground's edge from vertex 0 to 1: zero area.
  const uint32_t onEdge = vertex(0.5f * (b.rdb.positionsM[0] + b.rdb.positionsM[1]));
  b.rdb.indices.insert(b.rdb.indices.end(), {0, onEdge, 1});
  b.rdb.triangleMaterial.push_back(mat);
  vertex(vec3(5, 0, 5));  // unused
  const uint32_t d0 = vertex(vec3(3, 0, 3));
  const uint32_t d1 = vertex(vec3(3, 0, 3));
  const uint32_t d2 = vertex(vec3(3, 0, 4));
  b.rdb.indices.insert(b.rdb.indices.end(), {d0, d1, d2});
  b.rdb.triangleMaterial.push_back(mat);
  const uint32_t nan = vertex(vec3(std::nanf(""), 0, 0));
  b.rdb.indices.insert(b.rdb.indices.end(), {nan, 2, 3});
  b.rdb.triangleMaterial.push_back(mat);

  const VertexLightMaps maps = bake(b.rdb, 64, 8);
  expectAllFinite(maps);
  EXPECT_EQ(maps.unfilledVertices, 4u);
  EXPECT_NEAR(maps.frontLux[onEdge].g, kPiF * sky.g, 0.05f * kPiF);
  EXPECT_GT(maps.frontLux[nan].g, 0.0f);  // from vertices 2 and 3
  for (uint32_t v : {onEdge + 1, d0, d1, d2}) EXPECT_EQ(maps.frontLux[v], Rgb(0.0f));
}

// Release only: vertices/s and rays/s of the baker on a 10k-triangle plane under sun and sky, and the raw
// Embree rays/s of occlusion and intersection rays from the same plane, both on one thread.
TEST(Baker, PerformanceOn10kTrianglePlane) {
  MeshBuilder b;
  b.ground(50.0f, 71, b.material(Rgb(0.3f)));
  b.uniformSky(Rgb(1000.0f), 64);
  b.rdb.hasSun = true;
  b.rdb.sun.directionWorld = glm::normalize(vec3(0.3f, 0.8f, 0.2f));
  b.rdb.sun.normalIlluminanceLux = Rgb(80000.0f);
  const VertexLightMaps maps = bake(b.rdb, 256, 8, 1);
  const double vertices = static_cast<double>(b.rdb.positionsM.size());
  const double bakerRays = static_cast<double>(maps.rays) / maps.seconds;
  std::cout << "[ perf     ] baker: " << b.rdb.triangleCount() << " triangles, " << vertices << " vertices × "
            << maps.samplesPerVertex << " samples in " << maps.seconds << " s: " << vertices / maps.seconds
            << " vertices/s, " << bakerRays / 1e6 << " Mrays/s\n";

  const EmbreeScene scene(b.rdb);
  const uint32_t threads = 1;
  const uint64_t raysPerThread = maps.rays / threads + 1;
  std::atomic<uint64_t> hits{0};
  const auto start = std::chrono::steady_clock::now();
  {
    std::vector<std::jthread> pool;
    for (uint32_t t = 0; t < threads; ++t) {
      pool.emplace_back([&, t] {
        RandomSampler sampler(t);
        uint64_t threadHits = 0;
        for (uint64_t i = 0; i < raysPerThread; i += 2) {
          sampler.startSample(static_cast<uint32_t>(i));
          const vec2 xz = 100.0f * sampler.next2D() - vec2(50.0f);
          const vec3 p = offsetRayOrigin(vec3(xz.x, 0.0f, xz.y), vec3(0, 1, 0), 50.0f);
          const vec3 d = sampleCosineHemisphere(sampler.next2D());
          threadHits += scene.occluded(p, vec3(d.x, d.z, d.y), std::numeric_limits<float>::infinity());
          threadHits +=
              scene.intersect(p, vec3(d.x, d.z, d.y), std::numeric_limits<float>::infinity()).has_value();
        }
        hits += threadHits;
      });
    }
  }
  const double rawSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double rawRays = static_cast<double>(raysPerThread + raysPerThread % 2) * threads / rawSeconds;
  std::cout << "[ perf     ] raw Embree: " << rawRays / 1e6 << " Mrays/s (" << hits
            << " hits); baker / raw = " << bakerRays / rawRays << "\n";
  EXPECT_EQ(hits, 0u);
}

// Tiles with vertices of their own are welded for baking: the coincident corners of neighbouring tiles get
// one estimate (no patchwork), and under a uniform sky it is the exact π L.
TEST(Baker, CoincidentVerticesOfTilesShareOneEstimate) {
  MeshBuilder b;
  b.tiles(vec3(-1, 0, -1), vec3(0, 0, 2), vec3(2, 0, 0), 4, b.material(Rgb(0.5f)));
  const float radiance = 1000.0f;
  b.uniformSky(Rgb(radiance));
  const VertexLightMaps maps = bake(b.rdb, 256);
  size_t shared = 0;
  for (size_t v = 0; v < b.rdb.positionsM.size(); ++v) {
    EXPECT_NEAR(maps.frontLux[v].g, kPiF * radiance, 4.0f * maps.frontStdErrorLux[v].g + 1e-3f * radiance);
    for (size_t w = 0; w < v; ++w) {
      if (b.rdb.positionsM[w] != b.rdb.positionsM[v]) continue;
      ++shared;
      EXPECT_EQ(maps.frontLux[v], maps.frontLux[w]) << v << " and " << w;
      EXPECT_EQ(maps.frontStdErrorLux[v], maps.frontStdErrorLux[w]);
    }
  }
  EXPECT_EQ(shared, 9u * 6u + 12u);  // pairs: 9 inner positions of 4 corners, 12 edge ones of 2
}

// The spread of the sun's direct samples over a vertex's ring (VertexLightMaps::frontSunDirectSpreadLux) is
// the standard deviation of E_sunDirect over the ring under the hat weight: with E_sunDirect = S on the lit
// part and 0 in the roof's shadow, S √(f (1 − f)) for the ring's hat-weighted lit share f (quadrature). 0 on
// rings wholly lit or wholly shaded; largest, S/2, where the shadow's edge halves the ring.
TEST(Baker, SunDirectSpreadIsTheSunsVariationOverTheRing) {
  MeshBuilder b;
  const uint32_t grey = b.material(Rgb(0.5f));
  b.ground(2.0f, 10, grey);
  b.grid(vec3(-2.0f, 1.0f, -2.0f), vec3(2.0f, 0, 0), vec3(0, 0, 4.0f), 2, grey);  // roof over x ∈ [−2, 0]
  const vec3 towardsSun = glm::normalize(vec3(-0.6f, 1.0f, 0.2f));
  const float normalLux = 50000.0f;
  b.sun(towardsSun, Rgb(normalLux));
  const auto lit = [&](const vec3& p) {
    const float t = (1.0f - p.y) / towardsSun.y;
    const vec3 q = p + t * towardsSun;
    return !(q.x >= -2.0f && q.x <= 0.0f && q.z >= -2.0f && q.z <= 2.0f);
  };
  const std::vector<double> f = hatAverages(b.rdb, [&](const vec3& p) { return lit(p) ? 1.0 : 0.0; }, 100);
  const VertexLightMaps maps = bake(b.rdb, 1024, 8);
  ASSERT_EQ(maps.frontSunDirectSpreadLux.size(), b.rdb.positionsM.size());
  const double sunLux = double(normalLux) * double(towardsSun.y);
  size_t edges = 0;
  for (uint32_t v = 0; v < b.rdb.meshes[0].vertexCount; ++v) {
    const double exact = sunLux * std::sqrt(std::max(0.0, f[v] * (1.0 - f[v])));
    const double spread = maps.frontSunDirectSpreadLux[v].g;
    // A standard deviation from 1024 samples: within ~3 % (1/√(2n)); 10 %, plus what sampling the sun's
    // disc adds where the ring is wholly lit (cos θ over the disc: 0.15 % of S).
    EXPECT_NEAR(spread, exact, 0.1 * exact + 3e-3 * sunLux) << "vertex " << v << ", lit share " << f[v];
    edges += f[v] > 0.05 && f[v] < 0.95 ? 1 : 0;
  }
  EXPECT_GE(edges, 5u);  // the comparison covers rings that the shadow's edge crosses
}

}  // namespace
}  // namespace fly::raytracer
