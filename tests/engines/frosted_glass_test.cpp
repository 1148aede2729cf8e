// Frosted glass in the GL engine shows what lies behind it blurred — neither hidden nor clear — by the width
// of its transmission lobe at the distance behind the pane, and passes the baker's share of the light.
// A pane (4 m × 2 m) 2 m in front of the eye, and behind it a wall of vertical stripes, emitting 1000 cd/m²
// and 0 in turn (period 0.2 m); no other light, so the pane shows only what it transmits (simple mode).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "../raster/raster_test_scenes.h"
#include "raster/renderer.h"
#include "raytracer/bsdf.h"
#include "rdb/raster_rdb.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/material_presets.h"
#include "sdb/scene.h"

namespace fly {
namespace {

constexpr uint32_t kPx = 64;
constexpr float kStripeCdM2 = 1000.0f;

struct Look {
  double mean = 0.0;      // cd/m², luminance over the central 32 × 32 pixels
  double contrast = 0.0;  // (max − min) / (max + min) over them
  double imageMean = 0.0;  // cd/m², luminance over the whole image
};

// The central pixels' luminance with `glass` (a preset) between the eye (z = 2) and the stripes at z = −wallM.
Look throughPane(const char* glass, float wallM) {
  sdb::Scene scene;
  sdb::Material pane = sdb::findMaterialPreset(glass)->material;
  pane.name = "pane";
  const sdb::MaterialId paneId = scene.addMaterial(pane).id;
  sdb::Material bright;
  bright.name = "bright";
  bright.diffuseColor = Rgb(0.0f);
  bright.emissionLuminance = Rgb(kStripeCdM2);
  const sdb::MaterialId brightId = scene.addMaterial(bright).id;
  sdb::Material dark;
  dark.name = "dark";
  dark.diffuseColor = Rgb(0.0f);
  const sdb::MaterialId darkId = scene.addMaterial(dark).id;
  // The pane as a 32 × 16 grid: glass is shaded per vertex, and its T falls from 0° to the corners' 48°.
  sdb::Mesh paneMesh;
  paneMesh.name = "pane";
  paneMesh.material = paneId;
  constexpr int kCols = 32, kRows = 16;
  for (int j = 0; j <= kRows; ++j) {
    for (int i = 0; i <= kCols; ++i) {
      paneMesh.positions.push_back(vec3(-2.0f + 4.0f * float(i) / kCols, -1.0f + 2.0f * float(j) / kRows, 0.0f));
      paneMesh.normals.push_back(vec3(0.0f, 0.0f, 1.0f));
    }
  }
  for (int j = 0; j < kRows; ++j) {
    for (int i = 0; i < kCols; ++i) {
      const uint32_t a = uint32_t(j * (kCols + 1) + i), b = a + 1, c = a + kCols + 2, d = a + kCols + 1;
      paneMesh.indices.insert(paneMesh.indices.end(), {a, b, c, a, c, d});
    }
  }
  paneMesh.twoSided = true;
  scene.addNode({.name = "pane", .meshes = {scene.addMesh(paneMesh).id}});
  for (int k = 0; k < 80; ++k) {
    sdb::Mesh stripe = raster::test::quadXY(k % 2 ? darkId : brightId);
    const float x0 = -4.0f + 0.1f * float(k);
    stripe.positions = {{x0, -3.0f, -wallM}, {x0 + 0.1f, -3.0f, -wallM}, {x0 + 0.1f, 3.0f, -wallM}, {x0, 3.0f, -wallM}};
    scene.addNode({.name = "stripe", .meshes = {scene.addMesh(stripe).id}});
  }
  const rdb::RasterRdb r = rdb::buildRasterRdb(scene);
  raster::Renderer renderer;
  renderer.upload(r);
  renderer.render(raster::test::lookAtView(vec3(0.0f, 0.0f, 2.0f), vec3(0.0f), 100.0f), raster::RenderMode::kSimple,
                  kPx, kPx);
  const std::vector<float> image = renderer.luminanceRgb();
  double sum = 0.0, lo = 1e30, hi = 0.0;
  for (uint32_t y = kPx / 4; y < 3 * kPx / 4; ++y) {
    for (uint32_t x = kPx / 4; x < 3 * kPx / 4; ++x) {
      const double l = image[3 * (size_t(y) * kPx + x) + 1];  // green: the stripes and panes are grey
      sum += l;
      lo = std::min(lo, l);
      hi = std::max(hi, l);
    }
  }
  double all = 0.0;
  for (size_t p = 0; p < size_t(kPx) * kPx; ++p) all += image[3 * p + 1];
  return {sum / double(kPx * kPx / 4), (hi - lo) / std::max(hi + lo, 1e-12), all / double(kPx * kPx)};
}

// The baker's transmittance of a preset towards cos θo: the mean weight of Bsdf::sample's directions below
// the surface.
double bakerTransmittance(const char* preset, float cosO) {
  const raytracer::Bsdf bsdf(rdb::lowerMaterial(sdb::findMaterialPreset(preset)->material, 0), true);
  const vec3 wo(std::sqrt(1.0f - cosO * cosO), 0.0f, cosO);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u01(0.0f, 0x1.fffffep-1f);
  constexpr int kSamples = 1 << 16;
  double sum = 0.0;
  for (int k = 0; k < kSamples; ++k) {
    raytracer::Bsdf::Sample s;
    const float uLobe = u01(rng);
    const vec2 u(u01(rng), u01(rng));
    if (bsdf.sample(wo, uLobe, u, s) && s.wi.z < 0.0f) sum += s.weight.g;
  }
  return sum / kSamples;
}

TEST(FrostedGlass, BlursWhatLiesBehindByItsDistanceAndPassesTheBakersShare) {
  raster::test::context();
  const Look clear = throughPane("clear-glass", 2.0f);
  const Look far = throughPane("frosted-glass", 2.0f);
  const Look touching = throughPane("frosted-glass", 0.005f);
  // The central pixels see the pane within 13° of its normal, where T varies by < 1 %. Blurred over a radius of many
  // periods, the central pixels show the mean of the stripes over the image (the coarse mip levels' average),
  // which the clear view gives as its image mean / T.
  const double clearT = bakerTransmittance("clear-glass", 1.0f);
  const double frostedT = bakerTransmittance("frosted-glass", 1.0f);
  const double behind = clear.imageMean / clearT;  // the stripes' mean luminance over the image
  std::printf("clear: mean %.1f cd/m², contrast %.3f; frosted, wall 2 m behind: mean %.1f (baker T %.4f × %.1f = "
              "%.1f), contrast %.3f; wall 5 mm behind: contrast %.3f\n",
              clear.mean, clear.contrast, far.mean, frostedT, behind, frostedT * behind, far.contrast,
              touching.contrast);
  EXPECT_GT(clear.contrast, 0.99);     // sharp stripes
  EXPECT_LT(far.contrast, 0.1);        // blurred over many periods (a radius of 2α · 2/4 · 66 ≈ 24 px, period 3.3 px)
  EXPECT_NEAR(far.mean, frostedT * behind, 0.03 * frostedT * behind);  // not opaque: the baker's share
  EXPECT_GT(touching.contrast, 0.9);   // what touches the pane stays sharp
}

}  // namespace
}  // namespace fly
