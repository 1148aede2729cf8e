// Next-event estimation to lit patches (raytracer/lit_patches.h, IntegratorSettings::litPatches): in a room
// lit by the sun and the sky through a glazed roof window, the bake with it agrees with path sampling alone
// (unbiased), its reported errors are honest and lower; the patch samples alone, path sampling alone and
// their power-heuristic combination agree (the weights sum to one); bit-identical for any thread count and
// after resuming from a checkpoint; and it is left out where the scene has no sun or no enclosed region.
#include "raytracer/lit_patches.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "raytracer/baker.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb_builder.h"
#include "roof_window_box.h"

namespace fly::raytracer {
namespace {

using MeshBuilder = rdb::TraceRdbBuilder;
using Weights = IntegratorSettings::LitPatchWeights;

// A closed box [−1, 1]³ of inward-facing walls of albedo 0.6, 4 × 4 quads a face, with a 1 m × 1 m pane of
// clear glass in the middle of its roof; the sun (60 klx) and a uniform sky (5 kcd/m²) shine through it,
// the sun onto a patch of the floor, whose light reaches the walls and the ceiling by reflection.
MeshBuilder sunlitRoom() {
  MeshBuilder b;
  const uint32_t mat = b.material(Rgb(0.6f, 0.55f, 0.5f));
  test::addRoofWindowBox(b, mat, mat, test::clearPaneMaterial(b));
  b.sun(glm::normalize(vec3(0.3f, 0.8f, 0.2f)), Rgb(60000.0f));
  b.uniformSky(Rgb(5000.0f));
  return b;
}

// LitPatches built directly from a TraceRdb with the given radiance estimates: training points at each
// triangle's corners with its face normal, passing straight through the triangles that transmit.
LitPatches litPatchesOf(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                        const LitPatches::RadianceEstimate& radiance, const LitPatches::FaceRadiance& faceRadiance) {
  std::vector<LitPatches::TrainingPoint> points;
  for (uint32_t t = 0; t < rdb.triangleCount(); ++t) {
    for (uint32_t c = 0; c < 3; ++c) {
      const uint32_t v = rdb.indices[3 * size_t{t} + c];
      points.push_back({rdb.positionsM[v], scene.triangleNormal(t), scene.triangleMagnitudeM(t)});
    }
  }
  std::vector<uint8_t> passesStraight(rdb.triangleCount(), 0);
  for (uint32_t t = 0; t < rdb.triangleCount(); ++t) {
    passesStraight[t] = rdb.materials[rdb.triangleMaterial[t]].transmission.x > 0.0f ? 1 : 0;
  }
  return LitPatches(scene, points, passesStraight, rdb.indices, rdb.positionsM, radiance, faceRadiance);
}

struct Bake {
  VertexLightMaps maps;
  bool usesPatches = false;
};

Bake bake(const rdb::TraceRdb& rdb, uint32_t samples, bool patches, uint64_t seed,
          Weights weights = Weights::kPowerHeuristic, uint32_t threads = 0, bool patchSky = false,
          bool maps = true) {
  const EmbreeScene scene(rdb);
  BakeSettings settings;
  settings.estimate.firstPassSamples = 64;
  settings.estimate.maxSamples = samples;
  settings.estimate.replicates = 16;
  settings.estimate.seed = seed;
  settings.estimate.threads = threads;
  settings.integrator.litPatches = patches;
  settings.integrator.litPatchWeights = weights;
  settings.integrator.litPatchSky = patchSky;
  settings.integrator.litPatchMaps = maps;
  Bake out;
  out.maps = bakeVertexLightMaps(rdb, scene, settings);
  out.usesPatches = out.maps.litPatchCells > 0;
  return out;
}

// Per vertex and channel, |a − b| within k (4.5) combined standard errors; returns the RMS of the normalised
// differences (about 1 when both errors are honest). Also sums each bake's reported variances.
double compare(const VertexLightMaps& a, const VertexLightMaps& b, const std::string& what,
               double* varianceA = nullptr, float k = 4.5f) {
  double sumSquares = 0.0;
  size_t count = 0;
  for (size_t v = 0; v < a.frontLux.size(); ++v) {
    for (int c = 0; c < 3; ++c) {
      const float se = std::hypot(a.frontStdErrorLux[v][c], b.frontStdErrorLux[v][c]);
      const float diff = a.frontLux[v][c] - b.frontLux[v][c];
      EXPECT_TRUE(std::isfinite(a.frontLux[v][c]) && a.frontLux[v][c] >= 0.0f);
      EXPECT_LE(std::abs(diff), k * se + 1e-3f) << what << ": vertex " << v << " channel " << c << ": "
                                                  << a.frontLux[v][c] << " against " << b.frontLux[v][c];
      if (se > 0.0f) {
        sumSquares += double(diff / se) * double(diff / se);
        ++count;
      }
      if (varianceA) *varianceA += double(a.frontStdErrorLux[v][c]) * a.frontStdErrorLux[v][c];
    }
  }
  return count > 0 ? std::sqrt(sumSquares / double(count)) : 0.0;
}

// The bake with lit patches against path sampling alone at 4 times the samples and another seed: unbiased,
// honest (RMS of the normalised differences within 1.5× of 1), and a lower reported error than path
// sampling alone at equal samples.
TEST(LitPatches, SunlitRoomAgreesWithPathSamplingAndItsErrorIsHonestAndLower) {
  const MeshBuilder b = sunlitRoom();
  const Bake reference = bake(b.rdb, 4096, false, 101);
  const Bake plain = bake(b.rdb, 1024, false, 3);
  const Bake patches = bake(b.rdb, 1024, true, 3);
  ASSERT_TRUE(patches.usesPatches);
  ASSERT_FALSE(plain.usesPatches);
  double patchVariance = 0.0, plainVariance = 0.0;
  const double rms = compare(patches.maps, reference.maps, "lit patches", &patchVariance);
  compare(plain.maps, reference.maps, "path sampling", &plainVariance);
  std::cout << "[ litpatch ] sunlit room: RMS " << rms << " σ against the reference; reported variance with "
            << "lit patches / without " << patchVariance / plainVariance << " at 1024 samples ("
            << patches.maps.litPatchCells << " regions)\n";
  EXPECT_GT(rms, 1.0 / 1.5);
  EXPECT_LT(rms, 1.5);
  EXPECT_LT(patchVariance, 0.5 * plainVariance);
}

// The patch samples alone (where a region's distribution holds the triangle a path reaches) and path
// sampling alone make the same bake as their power-heuristic combination: were the densities of the two
// strategies evaluated inconsistently, or a path's weights not to sum to one, one of them would be biased.
// With the patch samples gathering the sun's light alone (the default), the sky's light at a patch point
// stays with path sampling in full: weighted like the sun's, it would be lost where the patches alone
// count (the patches-alone bake then lies an RMS of 8.3 σ from the combination, 25 % low at some vertices). With the sky's light gathered too (IntegratorSettings::litPatchSky, the
// estimator of resumed older bakes), the same holds.
// The patches alone have a heavy tail at some vertices by the floor's sun patch (the patch's light close to
// the vertex, 1 / r², sampled by area): with seed 18 and 8 192 samples vertex 100 lies 4.6 σ low, with the
// triangles' maps and without them alike; with the maps (IntegratorSettings::litPatchMaps) and these seeds
// vertex 50 lies 4.7 σ low. The sun-alone case runs without the maps, whose densities
// PointsOnATriangleFollowTheDensityReported checks; the sun-and-sky case with them.
void expectPatchesAlonePathsAloneAndCombinedAgree(bool patchSky, bool maps) {
  const MeshBuilder b = sunlitRoom();
  const Bake combined = bake(b.rdb, 2048, true, 7, Weights::kPowerHeuristic, 0, patchSky, maps);
  const Bake patchesOnly = bake(b.rdb, 2048, true, 8, Weights::kPatchesOnly, 0, patchSky, maps);
  const Bake pathsOnly = bake(b.rdb, 2048, true, 9, Weights::kPathsOnly, 0, patchSky, maps);
  ASSERT_TRUE(combined.usesPatches);
  // The patch samples alone report errors about 1.2× too low (their RMS below: 1.13–1.28 over seeds), so
  // over the 2 × 192 values compared with them the largest normalised difference is held to 5 rather than
  // 4.5 (at 4.5 some seeds fail by chance; a weight that does not sum to one shifts whole regions).
  const double a = compare(patchesOnly.maps, combined.maps, "patches alone against combined", nullptr, 5.0f);
  const double c = compare(pathsOnly.maps, combined.maps, "paths alone against combined");
  const double d =
      compare(patchesOnly.maps, pathsOnly.maps, "patches alone against paths alone", nullptr, 5.0f);
  std::cout << "[ litpatch ] " << (patchSky ? "sun and sky" : "sun") << " at the patches: RMS σ: patches "
            << "alone / combined " << a << ", paths alone / combined " << c << ", patches alone / paths alone "
            << d << "\n";
  for (const double rms : {a, c, d}) EXPECT_LT(rms, 1.5);
}

TEST(LitPatches, PatchSamplesAlonePathSamplingAloneAndTheirCombinationAgree) {
  expectPatchesAlonePathsAloneAndCombinedAgree(false, false);
}

TEST(LitPatches, PatchSamplesOfSunAndSkyAlonePathSamplingAloneAndTheirCombinationAgree) {
  expectPatchesAlonePathsAloneAndCombinedAgree(true, true);
}

// Training and bake are bit-identical for any thread count.
TEST(LitPatches, DeterministicAcrossThreadCounts) {
  const MeshBuilder b = sunlitRoom();
  const Bake one = bake(b.rdb, 128, true, 4, Weights::kPowerHeuristic, 1);
  const Bake two = bake(b.rdb, 128, true, 4, Weights::kPowerHeuristic, 2);
  ASSERT_TRUE(one.usesPatches);
  EXPECT_EQ(one.maps.litPatchCells, two.maps.litPatchCells);
  EXPECT_EQ(one.maps.frontLux, two.maps.frontLux);
  EXPECT_EQ(one.maps.frontStdErrorLux, two.maps.frontStdErrorLux);
  EXPECT_EQ(one.maps.rays, two.maps.rays);
}

// A bake stopped after its third checkpoint and continued from it equals one that ran through: the regions
// are trained again alike.
TEST(LitPatches, ABakeStoppedAndContinuedEqualsOneThatRanThrough) {
  const MeshBuilder b = sunlitRoom();
  const EmbreeScene scene(b.rdb);
  BakeSettings settings;
  settings.estimate.maxSamples = 64;
  settings.estimate.threads = 2;
  const VertexLightMaps whole = bakeVertexLightMaps(b.rdb, scene, settings);
  ASSERT_GT(whole.litPatchCells, 0u);
  struct Killed {};
  BakeCheckpoint state;
  std::vector<std::string> saved;
  std::vector<size_t> historyAtSave;
  BakeCheckpointing checkpointing;
  checkpointing.state = &state;
  checkpointing.intervalS = 0.0;
  checkpointing.save = [&](const BakeCheckpoint& s) {
    saved.push_back(serializeProgressState(s.progress));
    historyAtSave.push_back(s.history.size());
    if (saved.size() == 3) throw Killed{};
  };
  EXPECT_THROW(bakeVertexLightMaps(b.rdb, scene, settings, {}, checkpointing), Killed);
  ASSERT_EQ(saved.size(), 3u);
  BakeCheckpoint resumed;
  resumed.progress = deserializeProgressState(saved.back(), "state.bin");
  resumed.history = std::vector<ConvergencePoint>(
      state.history.begin(), state.history.begin() + static_cast<long>(historyAtSave.back()));
  checkpointing.state = &resumed;
  checkpointing.save = {};
  const VertexLightMaps continued = bakeVertexLightMaps(b.rdb, scene, settings, {}, checkpointing);
  EXPECT_EQ(continued.frontLux, whole.frontLux);
  EXPECT_EQ(continued.frontStdErrorLux, whole.frontStdErrorLux);
  EXPECT_EQ(continued.frontSunDirectLux, whole.frontSunDirectLux);
}

// A region's sampling picks each triangle with the probability that pmf() reports for it (the integrator's
// MIS weights evaluate the patch strategy's density by pmf()): over 2^16 evenly spaced numbers, each
// triangle's share of the picks is its pmf within one spacing, and the picks' pmfs are pmf()'s.
TEST(LitPatches, SamplingPicksEachTriangleWithTheProbabilityPmfReports) {
  const MeshBuilder b = sunlitRoom();
  const rdb::TraceRdb& rdb = b.rdb;
  const EmbreeScene scene(rdb);
  // Uneven weights: some triangles' estimates 0 (only the defensive share keeps them), others up to 9.
  const LitPatches patches = litPatchesOf(
      rdb, scene,
      [](const Hit& hit, const vec3&, uint64_t seed) { return float((hit.triangle * 7 + seed % 3) % 10); },
      [](uint32_t t, bool) { return float(t % 5); });
  ASSERT_GT(patches.cellCount(), 0u);
  constexpr uint32_t kPicks = 1u << 16;
  for (uint32_t cell = 0; cell < patches.cellCount(); ++cell) {
    std::vector<uint32_t> count(rdb.triangleCount(), 0);
    for (uint32_t k = 0; k < kPicks; ++k) {
      const LitPatches::Pick pick = patches.sample(cell, (float(k) + 0.5f) / float(kPicks));
      ASSERT_LT(pick.triangle, rdb.triangleCount());
      ASSERT_EQ(pick.pmf, patches.pmf(cell, pick.triangle)) << "cell " << cell;
      ASSERT_GE(pick.uRemapped, 0.0f);
      ASSERT_LT(pick.uRemapped, 1.0f);
      ++count[pick.triangle];
    }
    double total = 0.0;
    for (uint32_t t = 0; t < rdb.triangleCount(); ++t) {
      const float pmf = patches.pmf(cell, t);
      total += pmf;
      EXPECT_NEAR(double(count[t]) / kPicks, pmf, 1.5 / kPicks) << "cell " << cell << " triangle " << t;
    }
    EXPECT_NEAR(total, 1.0, 1e-5) << "cell " << cell;
  }
}

// The point on a picked triangle is drawn with the density that density() reports (what the integrator's
// weights use): for the radiance lit only where the barycentric u > 0.6 (a sun patch over part of each
// triangle), over a Fibonacci lattice of 46 368 points per picked triangle, the mean of 1 / factor is 1 (the density
// integrates to one over the triangle) and the mean of lit / factor is the lit part's area, 0.16; the maps
// put most points on the lit part.
TEST(LitPatches, PointsOnATriangleFollowTheDensityReported) {
  const MeshBuilder b = sunlitRoom();
  const rdb::TraceRdb& rdb = b.rdb;
  const EmbreeScene scene(rdb);
  auto lit = [](const vec2& bary) { return bary.x > 0.6f; };
  const LitPatches patches = litPatchesOf(
      rdb, scene, [&](const Hit& hit, const vec3&, uint64_t) { return lit(hit.barycentric) ? 1.0f : 0.0f; },
      [](uint32_t, bool) { return 0.16f; });
  ASSERT_GT(patches.cellCount(), 0u);
  ASSERT_GT(patches.mapCount(), 0u);
  // The Fibonacci lattice (i / F_24, frac(i F_23 / F_24)): every one of the maps' narrow intervals of u.x gets
  // its share of the points.
  constexpr uint32_t kPoints = 46368;
  constexpr uint32_t kStep = 28657;
  size_t checked = 0;
  double litShare = 0.0;
  for (uint32_t cell = 0; cell < patches.cellCount(); ++cell) {
    std::vector<uint8_t> done(rdb.triangleCount(), 0);
    for (uint32_t k = 0; k < 8; ++k) {
      const LitPatches::Pick pick = patches.sample(cell, (float(k) + 0.5f) / 8.0f);
      if (done[pick.triangle]) continue;
      done[pick.triangle] = 1;
      double inverse = 0.0, litArea = 0.0, litPoints = 0.0;
      for (uint32_t i = 0; i < kPoints; ++i) {
        {
          const uint32_t j = uint32_t((uint64_t{i} * kStep) % kPoints);
          const vec2 u((float(i) + 0.5f) / kPoints, (float(j) + 0.5f) / kPoints);
          const LitPatches::PointPick point = patches.samplePoint(pick, u);
          ASSERT_GT(point.densityFactor, 0.0f);
          ASSERT_NEAR(point.densityFactor * pick.pmf,
                      patches.density(cell, pick.triangle, point.barycentric), 1e-4f * point.densityFactor)
              << "cell " << cell << " triangle " << pick.triangle;
          inverse += 1.0 / point.densityFactor;
          litArea += lit(point.barycentric) ? 1.0 / point.densityFactor : 0.0;
          litPoints += lit(point.barycentric) ? 1.0 : 0.0;
        }
      }
      const double n = kPoints;
      EXPECT_NEAR(inverse / n, 1.0, 0.03) << "cell " << cell << " triangle " << pick.triangle;
      EXPECT_NEAR(litArea / n, 0.16, 0.01) << "cell " << cell << " triangle " << pick.triangle;
      litShare += litPoints / n;
      ++checked;
    }
  }
  ASSERT_GT(checked, 0u);
  std::cout << "[ litpatch ] points on the lit part: " << litShare / double(checked) << " (uniform: 0.16), "
            << patches.mapCount() << " maps\n";
  EXPECT_GT(litShare / double(checked), 0.5);
}

// Left out where nothing calls for it: without a sun (the sky alone), and under the open sky (a ground
// whose training rays all escape).
TEST(LitPatches, LeftOutWithoutSunOrEnclosure) {
  MeshBuilder skyOnly = sunlitRoom();
  skyOnly.rdb.hasSun = false;
  {
    const EmbreeScene scene(skyOnly.rdb);
    EXPECT_FALSE(Integrator(skyOnly.rdb, scene).usesLitPatches());
  }
  MeshBuilder open;
  open.ground(10.0f, 8, open.material(Rgb(0.5f)));
  open.sun(glm::normalize(vec3(0.3f, 0.8f, 0.2f)), Rgb(60000.0f));
  open.uniformSky(Rgb(5000.0f));
  const EmbreeScene openScene(open.rdb);
  EXPECT_FALSE(Integrator(open.rdb, openScene).usesLitPatches());
  const MeshBuilder room = sunlitRoom();
  const EmbreeScene roomScene(room.rdb);
  EXPECT_TRUE(Integrator(room.rdb, roomScene).usesLitPatches());
}

}  // namespace
}  // namespace fly::raytracer
