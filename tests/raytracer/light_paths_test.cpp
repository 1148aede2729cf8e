// Light paths from the sun (raytracer/light_paths.h) and their combination with the gathering estimator in
// the baker: an exact answer on a floor, agreement with the gathering estimator where the sun's light is
// reflected (a box lit through a roof window, white walls included), honest reported errors, and
// determinism across thread counts.
#include "raytracer/light_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <tuple>
#include <utility>
#include <vector>

#include "raytracer/baker.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb_builder.h"
#include "roof_window_box.h"

namespace fly::raytracer {
namespace {

using MeshBuilder = rdb::TraceRdbBuilder;

const vec3 kTowardsSun = glm::normalize(vec3(0.3f, 0.8f, 0.2f));
const Rgb kNormalLux(1000.0f, 800.0f, 600.0f);

LightPathMaps trace(const rdb::TraceRdb& rdb, uint32_t pathsPerBatch, uint32_t batches, uint64_t seed = 0,
                    uint32_t threads = 0) {
  const EmbreeScene scene(rdb);
  const Integrator integrator(rdb, scene);
  LightPathSettings settings;
  settings.pathsPerBatch = pathsPerBatch;
  settings.batches = batches;
  settings.seed = seed;
  settings.threads = threads;
  return SunLightPaths(rdb, scene, integrator).trace(settings);
}

// A closed box [−1, 1]³ of inward-facing walls of albedo `albedo`, 4 × 4 quads a face, with a 1 m × 1 m
// hole in the middle of its roof; the sun shines through it onto the floor, whose sunlit patch lights the
// walls and the ceiling. No sky. floorGlossiness ≥ 0: the floor also reflects 30 % (uniform, no Fresnel) by
// a GGX lobe of that glossiness (0: a mirror).
// glass: the hole holds a pane of clear glass (the light paths then start through it too).
MeshBuilder roofWindowBox(float albedo, float floorGlossiness = -1.0f, bool glass = false) {
  MeshBuilder b;
  const uint32_t mat = b.material(Rgb(albedo));
  uint32_t floor = mat;
  if (floorGlossiness >= 0.0f) {
    floor = b.material(Rgb(albedo));
    rdb::TraceMaterial& m = b.rdb.materials[floor];
    m.reflection = Rgb(0.3f);
    m.fresnel = false;
    m.reflectionGlossiness = floorGlossiness;
    m.diffuse = (1.0f - 0.3f) * m.diffuseColor;  // the energy rule's D(0)
  }
  test::addRoofWindowBox(b, mat, floor, glass ? test::clearPaneMaterial(b) : test::kNoPane);
  b.sun(kTowardsSun, kNormalLux);
  return b;
}

// Gathering by path sampling alone (IntegratorSettings::litPatches off): with lit patches its error at the
// ceiling by the roof window's edge is 4× smaller, and the light paths' own error there, estimated from 16
// batches, then proves too small (a vertex 4.3 of their σ from a 4096-sample reference; docs/lit-patches.md).
VertexLightMaps bake(const rdb::TraceRdb& rdb, uint32_t samples, bool lightPaths, uint64_t seed = 0,
                     uint32_t threads = 0, uint32_t pathsPerBatch = 1u << 15) {
  const EmbreeScene scene(rdb);
  BakeSettings settings;
  settings.integrator.litPatches = false;
  settings.estimate.firstPassSamples = 64;
  settings.estimate.maxSamples = samples;
  settings.estimate.replicates = 64;
  settings.estimate.seed = seed;
  settings.estimate.threads = threads;
  settings.lightPaths.enabled = lightPaths;
  settings.lightPaths.paths.pathsPerBatch = pathsPerBatch;
  settings.lightPaths.paths.batches = 16;
  settings.lightPaths.pilotPathsPerBatch = 1u << 13;
  return bakeVertexLightMaps(rdb, scene, settings);
}

// The floor alone under the sun: every vertex's hat-weighted one-ring irradiance is E_n cos θ exactly, all
// of it direct; nothing is reflected back, and the back of a two-sided floor gets nothing.
TEST(LightPaths, FloorUnderTheSunIsNormalIlluminanceTimesCosine) {
  for (const bool twoSided : {false, true}) {
    MeshBuilder b;
    b.ground(2.0f, 8, b.material(Rgb(0.5f)), twoSided);
    b.sun(kTowardsSun, kNormalLux);
    const LightPathMaps maps = trace(b.rdb, 1u << 13, 32);
    const Rgb exact = kNormalLux * kTowardsSun.y;
    double worst = 0.0;
    for (size_t v = 0; v < b.rdb.positionsM.size(); ++v) {
      for (int c = 0; c < 3; ++c) {
        const float mean = maps.frontDirectLux[v][c];
        const float se = maps.frontDirectStdErrorLux[v][c];
        EXPECT_LE(std::abs(mean - exact[c]), 4.0f * se + 1e-4f * exact[c])
            << "vertex " << v << " channel " << c;
        EXPECT_LE(se, 0.02f * exact[c]) << "vertex " << v;
        EXPECT_GT(se, 0.0f) << "vertex " << v;  // the batches differ: the error is measured
        worst = std::max(worst, double(std::abs(mean - exact[c]) / se));
        EXPECT_EQ(maps.frontReflectedLux[v][c], 0.0f);
        EXPECT_EQ(maps.backDirectLux[v][c], 0.0f);
        EXPECT_EQ(maps.backReflectedLux[v][c], 0.0f);
      }
    }
    std::cout << "[ lightpath] floor" << (twoSided ? " (two-sided)" : "") << ": worst error " << worst
              << " σ\n";
  }
}

// Light paths against the gathering estimator (which the baker tests check against exact answers) in the
// box lit through its roof window: per vertex, the sun's direct and reflected light of the light paths
// against the gathering bake, within 4.5 combined standard errors.
// With white walls (albedo 0.9, many bounces: a furnace-like cavity that the window's sun feeds) too, and
// with a glossy and a mirror floor, whose sun reflection both estimators regularise alike (light_paths.h).
TEST(LightPaths, RoofWindowBoxAgreesWithGathering) {
  for (const auto& [albedo, floorGlossiness, glass] : {std::tuple{0.5f, -1.0f, false},
                                                       {0.9f, -1.0f, false},
                                                       {0.5f, 0.1f, false},
                                                       {0.5f, 0.0f, false},
                                                       {0.5f, -1.0f, true}}) {
    SCOPED_TRACE(floorGlossiness);
    SCOPED_TRACE(glass ? "glass" : "open");
    const MeshBuilder b = roofWindowBox(albedo, floorGlossiness, glass);
    const LightPathMaps paths = trace(b.rdb, 1u << 16, 16, 5);
    const VertexLightMaps gathered = bake(b.rdb, 2048, false, 11);
    double worst = 0.0;
    double sumSquares = 0.0;
    size_t count = 0;
    double reflectedOnWalls = 0.0;
    for (size_t v = 0; v < b.rdb.positionsM.size(); ++v) {
      const Rgb lp = paths.frontDirectLux[v] + paths.frontReflectedLux[v];
      const Rgb lpSe = glm::sqrt(paths.frontDirectStdErrorLux[v] * paths.frontDirectStdErrorLux[v] +
                                 paths.frontReflectedStdErrorLux[v] * paths.frontReflectedStdErrorLux[v]);
      for (int c = 0; c < 3; ++c) {
        const float se = std::hypot(lpSe[c], gathered.frontStdErrorLux[v][c]);
        const float diff = lp[c] - gathered.frontLux[v][c];
        EXPECT_LE(std::abs(diff), 4.5f * se + 1e-3f)
            << "albedo " << albedo << " vertex " << v << " channel " << c << ": light paths " << lp[c]
            << ", gathering " << gathered.frontLux[v][c];
        if (se > 0.0f) {
          worst = std::max(worst, double(std::abs(diff) / se));
          sumSquares += double(diff / se) * double(diff / se);
          ++count;
        }
      }
      // The walls x = ±1 take reflected light.
      if (std::abs(std::abs(b.rdb.positionsM[v].x) - 1.0f) < 1e-6f)
        reflectedOnWalls += paths.frontReflectedLux[v].g;
    }
    EXPECT_GT(reflectedOnWalls, 0.0);
    const double rms = std::sqrt(sumSquares / double(count));
    std::cout << "[ lightpath] roof window, albedo " << albedo << ", floor glossiness " << floorGlossiness
              << (glass ? ", glass" : "") << ": worst " << worst << " σ, RMS " << rms << " σ over " << count
              << " vertex channels\n";
    // The errors are honest on the whole: the RMS of the normalised differences is about 1.
    EXPECT_GT(rms, 1.0 / 1.5);
    EXPECT_LT(rms, 1.5);
  }
}

// The combined bake (light paths on) against a gathering bake of another seed: within 4.5 combined
// standard errors per vertex, and the RMS of the differences in units of the reported errors (the
// combination's and the reference's together) within 1.5× of 1; the combined error is below the
// gathering's alone at equal samples where the sun's reflected light dominates.
TEST(LightPaths, CombinedBakeIsUnbiasedAndItsErrorIsHonest) {
  const MeshBuilder b = roofWindowBox(0.7f);
  const VertexLightMaps reference = bake(b.rdb, 4096, false, 101);
  const VertexLightMaps gathered = bake(b.rdb, 256, false, 3);
  const VertexLightMaps combined = bake(b.rdb, 256, true, 3);
  ASSERT_GT(combined.lightPaths, 0u);
  double sumSquares = 0.0;
  size_t count = 0;
  double gatheredVariance = 0.0, combinedVariance = 0.0;
  for (size_t v = 0; v < b.rdb.positionsM.size(); ++v) {
    for (int c = 0; c < 3; ++c) {
      const float se = std::hypot(combined.frontStdErrorLux[v][c], reference.frontStdErrorLux[v][c]);
      const float diff = combined.frontLux[v][c] - reference.frontLux[v][c];
      EXPECT_TRUE(std::isfinite(combined.frontLux[v][c]) && combined.frontLux[v][c] >= 0.0f);
      EXPECT_LE(std::abs(diff), 4.5f * se + 1e-3f) << "vertex " << v << " channel " << c;
      if (se > 0.0f) {
        sumSquares += double(diff / se) * double(diff / se);
        ++count;
      }
      gatheredVariance += double(gathered.frontStdErrorLux[v][c]) * gathered.frontStdErrorLux[v][c];
      combinedVariance += double(combined.frontStdErrorLux[v][c]) * combined.frontStdErrorLux[v][c];
    }
  }
  const double rms = std::sqrt(sumSquares / double(count));
  std::cout << "[ lightpath] combined vs reference: RMS " << rms
            << " σ; reported variance combined / gathering " << combinedVariance / gatheredVariance << "\n";
  EXPECT_GT(rms, 1.0 / 1.5);
  EXPECT_LT(rms, 1.5);
  EXPECT_LT(combinedVariance, gatheredVariance);
}

// Light paths and the combined bake are bit-identical for any thread count.
TEST(LightPaths, DeterministicAcrossThreadCounts) {
  const MeshBuilder b = roofWindowBox(0.6f);
  const LightPathMaps one = trace(b.rdb, 5000, 3, 9, 1);
  const LightPathMaps three = trace(b.rdb, 5000, 3, 9, 3);
  EXPECT_EQ(one.frontDirectLux, three.frontDirectLux);
  EXPECT_EQ(one.frontReflectedLux, three.frontReflectedLux);
  EXPECT_EQ(one.frontReflectedStdErrorLux, three.frontReflectedStdErrorLux);
  EXPECT_EQ(one.rays, three.rays);
  const VertexLightMaps bakeOne = bake(b.rdb, 128, true, 4, 1, 4096);
  const VertexLightMaps bakeTwo = bake(b.rdb, 128, true, 4, 2, 4096);
  EXPECT_EQ(bakeOne.frontLux, bakeTwo.frontLux);
  EXPECT_EQ(bakeOne.frontStdErrorLux, bakeTwo.frontStdErrorLux);
}

// Without a sun nothing is traced and the maps are 0.
TEST(LightPaths, NoSunTracesNothing) {
  MeshBuilder b;
  b.ground(1.0f, 2, b.material(Rgb(0.5f)));
  const LightPathMaps maps = trace(b.rdb, 1000, 4);
  EXPECT_EQ(maps.paths, 0u);
  for (const Rgb& e : maps.frontDirectLux) EXPECT_EQ(e, Rgb(0.0f));
}

}  // namespace
}  // namespace fly::raytracer
