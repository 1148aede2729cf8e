// Cube-map reflections of curved reflectors (raster/cube_reflections.h, RasterRdb::cubeReflectors): a chrome
// sphere between two emitters against a CPU ray cast of the same scene — what each pixel reflects (the mask)
// and how bright (R · L) — and when the maps are captured again.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <vector>

#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/material.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

constexpr float kRadiusM = 0.5f;
constexpr float kChrome = 0.9f;  // uniform reflection
constexpr uint32_t kPx = 96;
const vec3 kEye(0.0f, 0.3f, 1.6f);
struct Emitter {
  vec3 lo, hi;
  float cdM2;
};
const std::array<Emitter, 2> kEmitters = {Emitter{{1.0f, -0.8f, -0.8f}, {2.0f, 0.8f, 0.8f}, 1000.0f},
                                          Emitter{{-0.8f, 1.0f, -0.8f}, {0.8f, 1.4f, 0.8f}, 400.0f}};

rdb::RasterRdb chromeScene(sdb::EngineReflection engine = sdb::EngineReflection::kAuto,
                           float fogDistanceM = std::numeric_limits<float>::infinity(),
                           const Rgb& fogColor = Rgb(0.0f)) {
  sdb::Scene scene;
  sdb::Material chrome;
  chrome.name = "chrome";
  chrome.diffuseColor = Rgb(0.0f);
  chrome.reflectionColor = Rgb(kChrome);
  chrome.reflectionModel = sdb::ReflectionModel::kUniform;
  chrome.reflectionGlossiness = 0.0f;
  chrome.engineReflection = engine;
  chrome.reflectionFogDistanceM = fogDistanceM;
  chrome.reflectionFogColor = fogColor;
  const sdb::MaterialId chromeId = scene.addMaterial(chrome).id;
  scene.addNode({.name = "sphere", .meshes = {scene.addMesh(test::uvSphere(vec3(0.0f), kRadiusM, 48, 96, chromeId)).id}});
  for (const Emitter& e : kEmitters) {
    sdb::Material lamp;
    lamp.name = "emitter";
    lamp.diffuseColor = Rgb(0.0f);
    lamp.reflectionColor = Rgb(0.0f);
    lamp.emissionLuminance = Rgb(e.cdM2);
    const sdb::MaterialId id = scene.addMaterial(lamp).id;
    scene.addNode({.name = "emitter", .meshes = {scene.addMesh(test::box(e.lo, e.hi, id)).id}});
  }
  rdb::RasterRdb r = rdb::buildRasterRdb(scene);
  r.ambient = {};
  return r;
}

// The luminance along a ray from o in direction d: the nearest emitter's, or 0; its distance in distM (1e30
// for none).
float traceEmitters(const vec3& o, const vec3& d, float* distM = nullptr) {
  float best = 1e30f, l = 0.0f;
  for (const Emitter& e : kEmitters) {
    float t0 = 0.0f, t1 = 1e30f;
    for (int a = 0; a < 3; ++a) {
      const float inv = 1.0f / d[a];
      float ta = (e.lo[a] - o[a]) * inv, tb = (e.hi[a] - o[a]) * inv;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    if (t0 <= t1 && t0 < best) {
      best = t0;
      l = e.cdM2;
    }
  }
  if (distM) *distM = best;
  return l;
}

// What the chrome sphere shows at pixel (x, y) by the cube-map technique: the scene seen from its centre in
// the mirror direction of the view ray about the analytic normal, times R; nullopt off the sphere (within 2 %
// of its silhouette) and where a direction 3° away sees something else (the edges of the emitters, where the
// cube's 1.4° texels and the facets' normals blur).
std::optional<float> expectedPixel(const View& view, uint32_t x, uint32_t y) {
  const float t = std::tan(0.5f * view.yfovRad);
  const vec3 dCamera((2.0f * (float(x) + 0.5f) / kPx - 1.0f) * t, (1.0f - 2.0f * (float(y) + 0.5f) / kPx) * t, -1.0f);
  const vec3 d = glm::normalize(mat3(view.worldFromCamera) * dCamera);
  const vec3 o(view.worldFromCamera[3]);
  const float b = glm::dot(o, d), c = glm::dot(o, o) - kRadiusM * kRadiusM;
  if (b * b - c <= 0.0f || glm::dot(o, o) - b * b > 0.98f * 0.98f * kRadiusM * kRadiusM) return std::nullopt;
  const vec3 n = glm::normalize(o + (-b - std::sqrt(b * b - c)) * d);
  const vec3 r = glm::normalize(d - 2.0f * glm::dot(d, n) * n);
  const float l = traceEmitters(vec3(0.0f), r);
  const vec3 u = glm::normalize(glm::cross(std::abs(r.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0), r));
  const vec3 v = glm::cross(r, u);
  const float tilt = std::tan(3.0f * float(kPi) / 180.0f);
  for (int k = 0; k < 8; ++k) {
    const float a = float(k) * float(kPi) / 4.0f;
    if (traceEmitters(vec3(0.0f), glm::normalize(r + tilt * (std::cos(a) * u + std::sin(a) * v))) != l) return std::nullopt;
  }
  return kChrome * l;
}

TEST(CubeReflection, ChromeSphereAgainstARayCast) {
  context();
  const rdb::RasterRdb r = chromeScene();
  ASSERT_EQ(r.cubeReflectors.size(), 1u);
  EXPECT_TRUE(r.variants.cubeReflectors);
  EXPECT_TRUE(r.planarReflectors.empty());
  Renderer renderer;
  renderer.upload(r);
  const View view = test::lookAtView(kEye, vec3(0.0f), 100.0f);
  renderer.render(view, RenderMode::kSimple, kPx, kPx);
  const std::vector<float> image = renderer.luminanceRgb();
  int compared = 0, agree = 0, lit = 0;
  double worstLit = 0.0, worstDark = 0.0;
  for (uint32_t y = 0; y < kPx; ++y) {
    for (uint32_t x = 0; x < kPx; ++x) {
      const std::optional<float> want = expectedPixel(view, x, y);
      if (!want) continue;
      const float got = image[3 * (size_t(y) * kPx + x) + 1];
      ++compared;
      // The mask: which of 0, 0.9 · 400 and 0.9 · 1000 cd/m² the pixel is nearest.
      auto nearest = [](float l) {
        const float levels[3] = {0.0f, kChrome * 400.0f, kChrome * 1000.0f};
        return int(std::min_element(levels, levels + 3, [&](float a, float b) { return std::abs(a - l) < std::abs(b - l); }) - levels);
      };
      agree += nearest(got) == nearest(*want);
      if (*want > 0.0f) {
        ++lit;
        worstLit = std::max(worstLit, std::abs(double(got) / *want - 1.0));
      } else {
        worstDark = std::max(worstDark, double(got));
      }
    }
  }
  std::printf("chrome sphere: %d of %d pixels reflect what the ray cast from its centre sees; %d show an "
              "emitter, worst %.4f of R · L; the rest at most %.2f cd/m²\n", agree, compared, lit, worstLit, worstDark);
  EXPECT_GT(compared, 2500);
  EXPECT_GT(lit, 400);
  EXPECT_EQ(agree, compared);
  EXPECT_LT(worstLit, 0.02);
  EXPECT_LT(worstDark, 0.01 * kChrome * 400.0f);
}

// The maps are captured at the first frame and again only when the scene, its light or the mode changes: a
// new view reuses them. "none" gives the sphere no cube map; "cubemap" gives a flat mesh one.
TEST(CubeReflection, CapturedOnlyWhenTheSceneChanges) {
  context();
  const rdb::RasterRdb r = chromeScene();
  Renderer renderer;
  renderer.upload(r);
  renderer.render(test::lookAtView(kEye, vec3(0.0f), 100.0f), RenderMode::kSimple, 32, 32);
  renderer.render(test::lookAtView(vec3(1.0f, 1.0f, 3.0f), vec3(0.0f), 100.0f), RenderMode::kSimple, 32, 32);
  EXPECT_EQ(renderer.stats().cubeCaptures, 1);
  renderer.update(r, {.lights = true});
  renderer.render(test::lookAtView(kEye, vec3(0.0f), 100.0f), RenderMode::kSimple, 32, 32);
  EXPECT_EQ(renderer.stats().cubeCaptures, 2);

  EXPECT_TRUE(chromeScene(sdb::EngineReflection::kNone).cubeReflectors.empty());
  sdb::Scene flat;
  sdb::Material paint;
  paint.name = "paint";
  paint.engineReflection = sdb::EngineReflection::kCubemap;
  flat.addNode({.name = "quad", .meshes = {flat.addMesh(test::quadXY(flat.addMaterial(paint).id)).id}});
  const rdb::RasterRdb q = rdb::buildRasterRdb(flat);
  ASSERT_EQ(q.cubeReflectors.size(), 1u);
  EXPECT_TRUE(q.planarReflectors.empty());
  EXPECT_NEAR(q.cubeReflectors[0].radiusM, std::sqrt(1.25f), 1e-5f);
}

// Reflection fog (D = 2 m, colour c) on the chrome sphere under an ambient term of E = 200 lux from every side
// (simple mode: the sphere's E is the same at every normal): each pixel shows R · mix(L, c E / π, t), t =
// min(d / D, 1), d the distance from the sphere's centre to what the mirror direction meets (the emitters at
// 1–2.3 m: t from 0.5; nothing: t = 1), as the cube map has it (no parallax), checked against the ray cast at
// the pixels of the test above within 2 %.
TEST(CubeReflection, ReflectionFogFadesTheCubeMapToTheFogColourTimesTheIrradiance) {
  context();
  constexpr float kFogDistanceM = 2.0f;
  const Rgb fogColor(0.3f, 0.5f, 0.7f);
  const Rgb irradianceLux(200.0f);
  rdb::RasterRdb r = chromeScene(sdb::EngineReflection::kAuto, kFogDistanceM, fogColor);
  ASSERT_EQ(r.cubeReflectors.size(), 1u);
  EXPECT_TRUE(r.variants.reflectionFog);
  r.ambient.upLux = r.ambient.downLux = irradianceLux;
  Renderer renderer;
  renderer.upload(r);
  const View view = test::lookAtView(kEye, vec3(0.0f), 100.0f);
  renderer.render(view, RenderMode::kSimple, kPx, kPx);
  const std::vector<float> image = renderer.luminanceRgb();
  const Rgb fogCdM2 = fogColor * irradianceLux / float(kPi);
  const float t = std::tan(0.5f * view.yfovRad);
  int lit = 0, dark = 0;
  double worst = 0.0, tMin = 1.0;
  for (uint32_t y = 0; y < kPx; ++y) {
    for (uint32_t x = 0; x < kPx; ++x) {
      if (!expectedPixel(view, x, y)) continue;
      const vec3 dCamera((2.0f * (float(x) + 0.5f) / kPx - 1.0f) * t, (1.0f - 2.0f * (float(y) + 0.5f) / kPx) * t, -1.0f);
      const vec3 d = glm::normalize(mat3(view.worldFromCamera) * dCamera);
      const vec3 o(view.worldFromCamera[3]);
      const float b = glm::dot(o, d), c = glm::dot(o, o) - kRadiusM * kRadiusM;
      const vec3 n = glm::normalize(o + (-b - std::sqrt(b * b - c)) * d);
      float distM = 0.0f;
      const float l = traceEmitters(vec3(0.0f), glm::normalize(d - 2.0f * glm::dot(d, n) * n), &distM);
      const float fog = l > 0.0f ? std::min(distM / kFogDistanceM, 1.0f) : 1.0f;
      const Rgb want = kChrome * ((1.0f - fog) * Rgb(l) + fog * fogCdM2);
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(double(image[3 * (size_t(y) * kPx + x) + size_t(k)]) / want[k] - 1.0));
      }
      (l > 0.0f ? lit : dark) += 1;
      if (l > 0.0f) tMin = std::min(tMin, double(fog));
    }
  }
  std::printf("chrome sphere with reflection fog: %d emitter pixels (t from %.3f), %d of nothing; worst %.4f of "
              "R · mix(L, c E / π, t)\n", lit, tMin, dark, worst);
  EXPECT_GT(lit, 400);
  EXPECT_GT(dark, 1000);
  EXPECT_LT(tMin, 0.7);
  EXPECT_LT(worst, 0.02);
}

}  // namespace
}  // namespace fly::raster
