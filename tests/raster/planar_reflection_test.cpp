// Planar reflections (raster/renderer.h, RasterRdb::planarReflectors): the engine's image of a flat mirror
// against an independent ray cast of the same scene on the CPU — where the mirror shows the reflected object
// (the mask) and how bright (R · L).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "base/ggx.h"
#include "rdb/raster_rdb.h"
#include "sdb/features.h"
#include "sdb/material.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

constexpr float kMirrorHalfM = 2.0f;               // the mirror: y = 0, |x|, |z| ≤ 2 m, facing +Y
const vec3 kBoxLo(-0.5f, 0.5f, -0.5f), kBoxHi(0.5f, 1.0f, 0.5f);  // the emitter above it
constexpr float kEmissionCdM2 = 1000.0f;
constexpr float kReflection = 0.8f;

struct MirrorScene {
  sdb::Scene scene;
  rdb::RasterRdb rdb;
};

MirrorScene mirrorScene(sdb::ReflectionModel model, sdb::EngineReflection engine = sdb::EngineReflection::kAuto,
                        float glossiness = 0.0f, float fogDistanceM = std::numeric_limits<float>::infinity(),
                        const Rgb& fogColor = Rgb(0.0f)) {
  MirrorScene s;
  sdb::Material mirror;
  mirror.name = "mirror";
  mirror.diffuseColor = Rgb(0.0f);
  mirror.reflectionColor = Rgb(kReflection);
  mirror.reflectionModel = model;
  mirror.reflectionGlossiness = glossiness;
  mirror.engineReflection = engine;
  mirror.reflectionFogDistanceM = fogDistanceM;
  mirror.reflectionFogColor = fogColor;
  const sdb::MaterialId mirrorId = s.scene.addMaterial(mirror).id;
  sdb::Material lamp;
  lamp.name = "emitter";
  lamp.diffuseColor = Rgb(0.0f);
  lamp.emissionLuminance = Rgb(kEmissionCdM2);
  const sdb::MaterialId lampId = s.scene.addMaterial(lamp).id;
  // quadXY spans x ∈ [−1, 1], y ∈ [−0.5, 0.5] facing +Z: turned to face +Y and scaled to the mirror.
  const mat4 floor = glm::rotate(mat4(1.0f), -float(kPi / 2), vec3(1, 0, 0)) *
                     glm::scale(mat4(1.0f), vec3(kMirrorHalfM, 2.0f * kMirrorHalfM, 1.0f));
  s.scene.addNode({.name = "mirror", .parentFromLocal = floor, .meshes = {s.scene.addMesh(test::quadXY(mirrorId)).id}});
  s.scene.addNode({.name = "emitter", .meshes = {s.scene.addMesh(test::box(kBoxLo, kBoxHi, lampId)).id}});
  s.rdb = rdb::buildRasterRdb(s.scene);
  s.rdb.ambient = {};
  return s;
}

// The distance along the ray to the box, if it hits it.
std::optional<float> hitBox(const vec3& o, const vec3& d) {
  float t0 = 0.0f, t1 = 1e30f;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12f) {
      if (o[a] < kBoxLo[a] || o[a] > kBoxHi[a]) return std::nullopt;
      continue;
    }
    float ta = (kBoxLo[a] - o[a]) / d[a], tb = (kBoxHi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return std::nullopt;
  return t0;
}

// What the eye sees along d: 0 nothing, 1 the box, 2 the box in the mirror, 3 the mirror showing nothing.
int classify(const vec3& eye, const vec3& d) {
  const std::optional<float> box = hitBox(eye, d);
  const float tMirror = d.y < 0.0f ? -eye.y / d.y : 1e30f;
  const vec3 p = eye + tMirror * d;
  const bool onMirror = tMirror < 1e29f && std::abs(p.x) <= kMirrorHalfM && std::abs(p.z) <= kMirrorHalfM;
  if (box && (!onMirror || *box < tMirror)) return 1;
  if (!onMirror) return 0;
  return hitBox(p, vec3(d.x, -d.y, d.z)) ? 2 : 3;
}

struct Comparison {
  size_t compared = 0, maskAgrees = 0, reflected = 0;
  double worstReflected = 0.0;  // relative error of R · L where both show the box in the mirror
};

// The engine's image against the ray cast at every pixel whose 3 × 3 neighbourhood the ray cast classifies
// alike (edges are a pixel's coverage question, not the reflection's).
// reflectance(cos θ): the mirror's R at the angle the eye sees it.
template <class R>
Comparison compare(const std::vector<float>& rgb, const View& view, uint32_t px, const R& reflectance) {
  const vec3 eye(view.worldFromCamera[3]);
  const float tanY = std::tan(0.5f * view.yfovRad);
  std::vector<int> cls(size_t(px) * px);
  std::vector<float> cosines(size_t(px) * px);
  for (uint32_t y = 0; y < px; ++y) {
    for (uint32_t x = 0; x < px; ++x) {
      const vec3 cam(((x + 0.5f) / px * 2.0f - 1.0f) * tanY, (1.0f - (y + 0.5f) / px * 2.0f) * tanY, -1.0f);
      const vec3 d = glm::normalize(mat3(view.worldFromCamera) * cam);
      cls[y * px + x] = classify(eye, d);
      cosines[y * px + x] = -d.y;
    }
  }
  Comparison c;
  for (uint32_t y = 1; y + 1 < px; ++y) {
    for (uint32_t x = 1; x + 1 < px; ++x) {
      const int k = cls[y * px + x];
      bool uniform = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) uniform &= cls[(y + dy) * px + x + dx] == k;
      if (!uniform) continue;
      const float l = rgb[3 * (size_t(y) * px + x) + 1];
      const float expectedReflected = reflectance(cosines[y * px + x]) * kEmissionCdM2;
      const int got = l > 0.9f * kEmissionCdM2 ? 1 : (l > 0.5f * expectedReflected ? 2 : 0);
      const int want = k == 3 ? 0 : k;
      ++c.compared;
      c.maskAgrees += got == want;
      if (k == 2 && got == 2) {
        ++c.reflected;
        c.worstReflected = std::max(c.worstReflected, std::abs(l / expectedReflected - 1.0));
      }
    }
  }
  return c;
}

TEST(PlanarReflection, MirrorShowsTheReflectedEmitterWhereTheRayCastDoes) {
  context();
  for (const sdb::ReflectionModel model : {sdb::ReflectionModel::kUniform, sdb::ReflectionModel::kFresnel}) {
    MirrorScene s = mirrorScene(model);
    if (model == sdb::ReflectionModel::kFresnel) {
      // Fresnel at ior 1.5 reflects 4 % at normal incidence: no mirror by the SDB's rule, no reflector.
      EXPECT_TRUE(s.rdb.planarReflectors.empty());
      continue;
    }
    ASSERT_EQ(s.rdb.planarReflectors.size(), 1u);
    EXPECT_NEAR(s.rdb.planarReflectors[0].normal.y, 1.0f, 1e-6f);
    EXPECT_NEAR(s.rdb.planarReflectors[0].offsetM, 0.0f, 1e-6f);
    EXPECT_NEAR(s.rdb.planarReflectors[0].areaM2, 16.0f, 1e-3f);
    Renderer renderer;
    renderer.upload(s.rdb);
    constexpr uint32_t kPx = 128;
    const View view = test::lookAtView(vec3(0.3f, 2.0f, 4.0f), vec3(0.0f, 0.3f, 0.0f), 50.0f);
    renderer.render(view, RenderMode::kSimple, kPx, kPx);
    EXPECT_EQ(renderer.stats().reflectionPasses, 1);
    const Comparison c = compare(renderer.luminanceRgb(), view, kPx, [](float) { return kReflection; });
    std::printf("planar mirror: mask agrees at %zu of %zu pixels; the reflected emitter at %zu pixels within %.4f "
                "of R · L\n", c.maskAgrees, c.compared, c.reflected, c.worstReflected);
    EXPECT_GT(c.reflected, 300u);
    EXPECT_GE(double(c.maskAgrees), 0.999 * double(c.compared));
    EXPECT_LT(c.worstReflected, 1e-3);
  }
}

// A Fresnel reflector (a polished floor: 4 % at normal incidence) shows no reflection by the automatic choice;
// marked "planar" (sdb::EngineReflection::kPlanar) it does, by R(θ) = colour · Schlick(F0 = 0.04, θ).
TEST(PlanarReflection, PolishedFloorMarkedPlanarReflectsByFresnel) {
  context();
  EXPECT_TRUE(mirrorScene(sdb::ReflectionModel::kFresnel).rdb.planarReflectors.empty());
  MirrorScene s = mirrorScene(sdb::ReflectionModel::kFresnel, sdb::EngineReflection::kPlanar);
  ASSERT_EQ(s.rdb.planarReflectors.size(), 1u);
  EXPECT_TRUE(sdb::computeFeatures(s.scene).planarReflectors);
  Renderer renderer;
  renderer.upload(s.rdb);
  constexpr uint32_t kPx = 128;
  const View view = test::lookAtView(vec3(0.3f, 1.2f, 4.5f), vec3(0.0f, 0.3f, 0.0f), 50.0f);
  renderer.render(view, RenderMode::kSimple, kPx, kPx);
  const float f0 = sdb::fresnelF0(1.5f);
  const Comparison c = compare(renderer.luminanceRgb(), view, kPx, [&](float cosTheta) {
    return kReflection * (f0 + (1.0f - f0) * std::pow(1.0f - cosTheta, 5.0f));
  });
  std::printf("polished floor: mask agrees at %zu of %zu pixels; the reflected emitter at %zu pixels within %.4f "
              "of R(θ) · L\n", c.maskAgrees, c.compared, c.reflected, c.worstReflected);
  EXPECT_GT(c.reflected, 200u);
  EXPECT_GE(double(c.maskAgrees), 0.999 * double(c.compared));
  EXPECT_LT(c.worstReflected, 0.01);
  EXPECT_TRUE(mirrorScene(sdb::ReflectionModel::kUniform, sdb::EngineReflection::kNone).rdb.planarReflectors.empty());
}

// A glossy mirror (glossiness 0.4, GGX α 0.16, marked "planar") shows the emitter blurred by its lobe: about
// 2α · D / (E + D) in tan units, D ≈ 0.5–1 m the emitter's height above the mirror, E ≈ 4.5 m from the eye,
// i.e. 5–9 px here; a box-filtered mip level read trilinearly reaches up to twice its radius, 18 px. The light
// spills onto mirror pixels where the sharp mirror shows nothing, no farther than that. The reflected light
// summed over the mirror pixels the eye sees is 9 % less than the sharp mirror's: the lobe spreads part of the
// reflection under the emitter's own image, which hides those mirror pixels (GlossyMirrorKeepsTheReflectedLight
// checks the blur's balance where nothing hides the mirror). Test: between 88 % and 101 % of the sharp sum.
// The same with the pass drawn at a quarter of the resolution, as the automatic choice does here (an eighth of
// the sky's spread 2α · 133 = 42 px is 5.3 px): its pixels move the sharp image's edges by up to 3 px, so the
// spill may reach 18 + 3 px.
TEST(PlanarReflection, GlossyMirrorBlursItsImageByItsLobe) {
  context();
  constexpr uint32_t kPx = 128;
  const View view = test::lookAtView(vec3(0.3f, 2.0f, 4.0f), vec3(0.0f, 0.3f, 0.0f), 50.0f);
  const vec3 eye(view.worldFromCamera[3]);
  const float tanY = std::tan(0.5f * view.yfovRad);
  struct Look {
    double summedCdM2 = 0.0;  // over the pixels that see the mirror
    size_t spill = 0;         // pixels that see the mirror where it reflects nothing, brighter than 5 % of R · L
    size_t farSpill = 0;      // those of them farther than 18 px from every pixel that reflects the emitter
  };
  auto look = [&](float glossiness, uint32_t scale) {
    MirrorScene s = mirrorScene(sdb::ReflectionModel::kUniform, sdb::EngineReflection::kPlanar, glossiness);
    Renderer renderer;
    renderer.upload(s.rdb);
    renderer.setGlossyReflectionScale(scale);
    renderer.render(view, RenderMode::kSimple, kPx, kPx);
    if (glossiness > 0.0f) EXPECT_EQ(renderer.stats().lastGlossyReflectionScale, scale == 0 ? 4u : scale);
    const std::vector<float> rgb = renderer.luminanceRgb();
    std::vector<int> cls(size_t(kPx) * kPx);
    for (uint32_t y = 0; y < kPx; ++y) {
      for (uint32_t x = 0; x < kPx; ++x) {
        const vec3 cam(((x + 0.5f) / kPx * 2.0f - 1.0f) * tanY, (1.0f - (y + 0.5f) / kPx * 2.0f) * tanY, -1.0f);
        cls[y * kPx + x] = classify(eye, glm::normalize(mat3(view.worldFromCamera) * cam));
      }
    }
    Look l;
    for (int y = 0; y < int(kPx); ++y) {
      for (int x = 0; x < int(kPx); ++x) {
        const int k = cls[size_t(y) * kPx + size_t(x)];
        if (k < 2) continue;
        const float g = rgb[3 * (size_t(y) * kPx + size_t(x)) + 1];
        l.summedCdM2 += g;
        if (k != 3 || g <= 0.05f * kReflection * kEmissionCdM2) continue;
        ++l.spill;
        bool near = false;
        const int reach = 18 + (scale == 0 ? 4 : int(scale)) - 1;
        for (int dy = -reach; dy <= reach && !near; ++dy)
          for (int dx = -reach; dx <= reach && !near; ++dx) {
            const int xx = x + dx, yy = y + dy;
            near = xx >= 0 && yy >= 0 && xx < int(kPx) && yy < int(kPx) && cls[size_t(yy) * kPx + size_t(xx)] == 2;
          }
        l.farSpill += !near;
      }
    }
    return l;
  };
  const Look sharp = look(0.0f, 1);
  EXPECT_EQ(sharp.spill, 0u);
  for (const uint32_t scale : {1u, 0u}) {
    const Look glossy = look(0.4f, scale);
    std::printf("glossy mirror, pass scale %s: %zu pixels of spilled light, %zu of them farther than %d px (sharp: "
                "%zu); reflected light summed over the mirror %.4g cd/m² (sharp: %.4g)\n",
                scale == 0 ? "automatic (4)" : "1", glossy.spill, glossy.farSpill, 18 + (scale == 0 ? 4 : 1) - 1,
                sharp.spill, glossy.summedCdM2, sharp.summedCdM2);
    EXPECT_GT(glossy.spill, 100u);
    EXPECT_EQ(glossy.farSpill, 0u);
    EXPECT_GT(glossy.summedCdM2, 0.88 * sharp.summedCdM2);
    EXPECT_LT(glossy.summedCdM2, 1.01 * sharp.summedCdM2);
  }
}

// The glossy blur moves light and loses none (raster/mirror_blur.h): a 40 m mirror on the floor (uniform
// reflection 0.8) fills the lower view; the emitter (1000 cd/m², 2 m × 0.5 m × 1 m) hangs 2.5–3 m up, 5–6 m
// ahead, above the view (whose top edge is 0.8° below the horizontal), so every pixel that shows its light
// shows it in the mirror and nothing hides the mirror. Its reflection lies at the image's centre, spread over
// r = 2α · D / (E + D) ≈ 0.046 in tan units (glossiness 0.2, α = 0.04; D / (E + D) ≈ 0.58 from the heights of
// the emitter and the mirrored eye): 9 px on 192², about 80 px from the mirror's far edge and the image's
// lower edge, which less than 0.1 % of the light reaches. So the image's summed luminance must be the sharp
// mirror's: the pyramid's levels keep the light up to float rounding, and the bilinear reads clamped to the
// mirror's rectangle lose only what the lobe spreads past it (next to none here). Test: 1 % (llvmpipe: 0.00 %).
TEST(PlanarReflection, GlossyMirrorKeepsTheReflectedLight) {
  context();
  constexpr uint32_t kPx = 192;
  const View view = test::lookAtView(vec3(0.0f, 2.0f, 4.0f), vec3(0.0f, 0.0f, 0.0f), 200.0f);
  auto summed = [&](float glossiness) {
    sdb::Scene scene;
    sdb::Material mirror;
    mirror.name = "mirror";
    mirror.diffuseColor = Rgb(0.0f);
    mirror.reflectionColor = Rgb(kReflection);
    mirror.reflectionModel = sdb::ReflectionModel::kUniform;
    mirror.reflectionGlossiness = glossiness;
    mirror.engineReflection = sdb::EngineReflection::kPlanar;
    const sdb::MaterialId mirrorId = scene.addMaterial(mirror).id;
    sdb::Material lamp;
    lamp.name = "emitter";
    lamp.diffuseColor = Rgb(0.0f);
    lamp.emissionLuminance = Rgb(kEmissionCdM2);
    const sdb::MaterialId lampId = scene.addMaterial(lamp).id;
    const mat4 floor = glm::rotate(mat4(1.0f), -float(kPi / 2), vec3(1, 0, 0)) * glm::scale(mat4(1.0f), vec3(20.0f, 40.0f, 1.0f));
    scene.addNode({.name = "mirror", .parentFromLocal = floor, .meshes = {scene.addMesh(test::quadXY(mirrorId)).id}});
    scene.addNode({.name = "emitter",
                   .meshes = {scene.addMesh(test::box(vec3(-1.0f, 2.5f, -6.0f), vec3(1.0f, 3.0f, -5.0f), lampId)).id}});
    rdb::RasterRdb rdb = rdb::buildRasterRdb(scene);
    rdb.ambient = {};
    EXPECT_EQ(rdb.planarReflectors.size(), 1u);
    Renderer renderer;
    renderer.upload(rdb);
    renderer.render(view, RenderMode::kSimple, kPx, kPx);
    const std::vector<float> rgb = renderer.luminanceRgb();
    double sum = 0.0, edge = 0.0;
    size_t lit = 0;
    for (size_t i = 0; i < size_t(kPx) * kPx; ++i) {
      sum += rgb[3 * i + 1];
      lit += rgb[3 * i + 1] > 0.01f * kReflection * kEmissionCdM2;
      if (i >= size_t(kPx) * (kPx - 20)) edge += rgb[3 * i + 1];  // the lowest 20 rows (row 0 is the top)
    }
    // What reaches the image's lower edge is a negligible part of the light (the sum below is not cut off).
    EXPECT_LT(edge, 1e-3 * sum);
    return std::pair{sum, lit};
  };
  const auto [sharp, sharpLit] = summed(0.0f);
  const auto [glossy, glossyLit] = summed(0.2f);
  std::printf("glossy mirror: reflected light summed over the image %.5g cd/m² at %zu pixels (sharp: %.5g at %zu), "
              "ratio %.4f\n",
              glossy, glossyLit, sharp, sharpLit, glossy / sharp);
  EXPECT_GT(sharpLit, 200u);
  EXPECT_GT(glossyLit, 2 * sharpLit);  // it is blurred
  EXPECT_NEAR(glossy, sharp, 0.01 * sharp);
}

// A 40 m mirror floor of `mirror` (marked "planar") under an emitter of 1000 cd/m² from `lo` to `hi`, above the
// view of farMirrorView (whose top edge is 0.8° below the horizontal): every pixel that shows the emitter's
// light shows it in the mirror. Simple mode, px² pixels, the glossy pass drawn at `scale`
// (Renderer::setGlossyReflectionScale); the ambient term `ambientLux` from above (for reflection fog).
const View farMirrorView = test::lookAtView(vec3(0.0f, 2.0f, 4.0f), vec3(0.0f, 0.0f, 0.0f), 200.0f);
struct FarMirror {
  std::vector<float> rgb;
  uint32_t scale = 0;  // the scale the glossy pass was drawn at (0: no glossy pass)
};
FarMirror renderFarMirror(sdb::Material mirror, const vec3& lo, const vec3& hi, uint32_t px, uint32_t scale,
                          float ambientLux = 0.0f, const sdb::Material* wall = nullptr) {
  sdb::Scene scene;
  mirror.name = "mirror";
  mirror.engineReflection = sdb::EngineReflection::kPlanar;
  const sdb::MaterialId mirrorId = scene.addMaterial(mirror).id;
  sdb::Material lamp;
  lamp.name = "emitter";
  lamp.diffuseColor = Rgb(0.0f);
  lamp.emissionLuminance = Rgb(kEmissionCdM2);
  const sdb::MaterialId lampId = scene.addMaterial(lamp).id;
  const mat4 floor = glm::rotate(mat4(1.0f), -float(kPi / 2), vec3(1, 0, 0)) * glm::scale(mat4(1.0f), vec3(20.0f, 40.0f, 1.0f));
  scene.addNode({.name = "mirror", .parentFromLocal = floor, .meshes = {scene.addMesh(test::quadXY(mirrorId)).id}});
  scene.addNode({.name = "emitter", .meshes = {scene.addMesh(test::box(lo, hi, lampId)).id}});
  if (wall) {
    // A second reflector: a wall 40 m wide and 1 m high standing on the mirror's far edge, facing the eye.
    sdb::Material w = *wall;
    w.name = "wall";
    w.engineReflection = sdb::EngineReflection::kPlanar;
    const sdb::MaterialId wallId = scene.addMaterial(w).id;
    scene.addNode({.name = "wall",
                   .parentFromLocal = glm::translate(mat4(1.0f), vec3(0.0f, 0.5f, -19.9f)) *
                                      glm::scale(mat4(1.0f), vec3(20.0f, 1.0f, 1.0f)),
                   .meshes = {scene.addMesh(test::quadXY(wallId)).id}});
  }
  rdb::RasterRdb rdb = rdb::buildRasterRdb(scene);
  rdb.ambient = {};
  rdb.ambient.upLux = Rgb(ambientLux);
  EXPECT_EQ(rdb.planarReflectors.size(), wall ? 2u : 1u);
  Renderer renderer;
  renderer.upload(rdb);
  renderer.setGlossyReflectionScale(scale);
  renderer.render(farMirrorView, RenderMode::kSimple, px, px);
  EXPECT_EQ(renderer.stats().reflectionPasses, wall ? 2 : 1);
  return {renderer.luminanceRgb(), renderer.stats().lastGlossyReflectionScale};
}

sdb::Material glossyMirror(float glossiness) {
  sdb::Material m;
  m.diffuseColor = Rgb(0.0f);
  m.reflectionColor = Rgb(kReflection);
  m.reflectionModel = sdb::ReflectionModel::kUniform;
  m.reflectionGlossiness = glossiness;
  return m;
}

// A glossy reflector's pass drawn at half or a quarter of the image's resolution per axis
// (Renderer::setGlossyReflectionScale) against the full pass, where the lobe spreads the light wider than
// that (the emitter, 2 m × 0.5 m × 1 m, 2.5–3 m above the mirror, D / (E + D) ≈ 0.58: a spread of
// 2α · 199 · 0.58 ≈ 9 px for glossiness 0.2 at 192², 21 px for 0.3). The blur keeps the coarse pass's light,
// but the coarse pass rasterises the emitter's sharp image (about 30 × 22 px) in 2- or 4-pixel steps: its
// light is off by what its outline's pass pixels hold (llvmpipe: −4.6 % at half, −2.1 % at a quarter), and
// per pixel the images differ by at most 8.1 % of the brightest reflected pixel. Test: the summed light within
// 6 %, every pixel within 10 % of the brightest, the sum of |difference| within 7 % of the light. The
// automatic choice: a quarter at glossiness 0.3 (an eighth of the sky's spread 2α · 199 = 36 px is 4.5 px),
// the full image at glossiness 0.2 (2.0 px, below 2) and for a fogged mirror (its fog reads the pass's depth).
TEST(PlanarReflection, CoarserGlossyPassAgreesWithTheFullOne) {
  context();
  constexpr uint32_t kPx = 192;
  const vec3 lo(-1.0f, 2.5f, -6.0f), hi(1.0f, 3.0f, -5.0f);
  for (const float glossiness : {0.2f, 0.3f}) {
    const FarMirror full = renderFarMirror(glossyMirror(glossiness), lo, hi, kPx, 1);
    ASSERT_EQ(full.scale, 1u);
    for (const uint32_t scale : {2u, 4u}) {
      const FarMirror coarse = renderFarMirror(glossyMirror(glossiness), lo, hi, kPx, scale);
      ASSERT_EQ(coarse.scale, scale);
      double sumFull = 0.0, sumCoarse = 0.0, sumDiff = 0.0, peak = 0.0, worst = 0.0;
      for (size_t i = 0; i < size_t(kPx) * kPx; ++i) {
        const double a = full.rgb[3 * i + 1], b = coarse.rgb[3 * i + 1];
        sumFull += a;
        sumCoarse += b;
        sumDiff += std::abs(a - b);
        peak = std::max(peak, a);
        worst = std::max(worst, std::abs(a - b));
      }
      std::printf("glossiness %.1f, pass at 1/%u: summed %.5g cd/m² (full pass %.5g, %+.2f %%), worst pixel %.2f %% of "
                  "the brightest, summed |difference| %.2f %% of the light\n",
                  double(glossiness), scale, sumCoarse, sumFull, 100.0 * (sumCoarse / sumFull - 1.0),
                  100.0 * worst / peak, 100.0 * sumDiff / sumFull);
      EXPECT_NEAR(sumCoarse, sumFull, 0.06 * sumFull);
      EXPECT_LT(worst, 0.10 * peak);
      EXPECT_LT(sumDiff, 0.07 * sumFull);
    }
  }
  EXPECT_EQ(renderFarMirror(glossyMirror(0.3f), lo, hi, kPx, 0).scale, 4u);
  EXPECT_EQ(renderFarMirror(glossyMirror(0.2f), lo, hi, kPx, 0).scale, 1u);
  sdb::Material fogged = glossyMirror(0.3f);
  fogged.reflectionFogDistanceM = 8.0f;
  EXPECT_EQ(renderFarMirror(fogged, lo, hi, kPx, 0, 300.0f).scale, 1u);
}

// Two glossy reflectors in one frame are blurred together, level by level (raster/mirror_blur.h, finish): a
// glossy wall (glossiness 0.5, more levels than the floor's) standing on the far edge of the glossy floor
// (glossiness 0.3) leaves the floor's blurred reflection of the emitter as it is alone, at the pixels the wall
// does not cover (the wall reflects the black space behind the eye, and the floor's light there is nil).
// llvmpipe: identical at every pixel, at full and at the automatic pass scale.
TEST(PlanarReflection, TwoGlossyReflectorsAreBlurredTogether) {
  context();
  constexpr uint32_t kPx = 192;
  const vec3 lo(-1.0f, 2.5f, -6.0f), hi(1.0f, 3.0f, -5.0f);
  const sdb::Material wall = glossyMirror(0.5f);
  for (const uint32_t scale : {1u, 0u}) {
    const FarMirror alone = renderFarMirror(glossyMirror(0.3f), lo, hi, kPx, scale);
    const FarMirror both = renderFarMirror(glossyMirror(0.3f), lo, hi, kPx, scale, 0.0f, &wall);
    size_t compared = 0;
    double worst = 0.0, peak = 0.0;
    for (size_t i = 0; i < size_t(kPx) * kPx; ++i) {
      peak = std::max(peak, double(alone.rgb[3 * i + 1]));
      if (both.rgb[3 * i + 1] == 0.0f && alone.rgb[3 * i + 1] > 0.0f) continue;  // hidden by the wall
      worst = std::max(worst, std::abs(double(both.rgb[3 * i + 1]) - double(alone.rgb[3 * i + 1])));
      ++compared;
    }
    std::printf("two glossy reflectors, pass scale %s: %zu pixels compared, worst difference %.2e of the brightest\n",
                scale == 0 ? "automatic" : "1", compared, worst / peak);
    EXPECT_GT(compared, size_t(kPx) * kPx * 9 / 10);
    EXPECT_LT(worst, 1e-4 * peak);
  }
}

// Luminance-weighted moments of an image's green channel over its pixels (x right, y down).
struct Moments {
  double sum = 0.0, mx = 0.0, my = 0.0, cxx = 0.0, cyy = 0.0, cxy = 0.0;
};
Moments moments(const std::vector<float>& rgb, uint32_t px) {
  Moments m;
  for (uint32_t y = 0; y < px; ++y) {
    for (uint32_t x = 0; x < px; ++x) {
      const double w = rgb[3 * (size_t(y) * px + x) + 1];
      m.sum += w;
      m.mx += w * x;
      m.my += w * y;
      m.cxx += w * double(x) * x;
      m.cyy += w * double(y) * y;
      m.cxy += w * double(x) * y;
    }
  }
  m.mx /= m.sum;
  m.my /= m.sum;
  m.cxx = m.cxx / m.sum - m.mx * m.mx;
  m.cyy = m.cyy / m.sum - m.my * m.my;
  m.cxy = m.cxy / m.sum - m.mx * m.my;
  return m;
}

// An anisotropic glossy mirror (glossiness 0.25, anisotropy U 0.6, V 0.1: base/ggx.h's widths α_t = 0.0843
// along its tangent and α_b = 0.0464 across it, a ratio of 1.818) blurs the reflection of a small emitter
// (0.3 m, 2.6–2.9 m above it, above the view) by its lobe's widths along and across the tangent's direction on
// screen. The blur's covariance is the blurred image's less the sharp mirror's (a convolution adds them). The
// mirror has no UVs: its tangent is n × x̂ = −z (rdb::RasterRdb::tangents), vertical on this screen; turned by
// 90° (the material's rotation) it is −x, horizontal. Along the axis the blur is α_t / α_b times as wide as
// across it (test: within 10 %), across it as wide as an isotropic lobe of α_b's (10 %), and at U = V the
// blur is round (10 %); the summed light is the sharp mirror's (1 %). Full-resolution passes (the emitter's
// image, 6 × 8 px, would be rasterised coarsely in a coarser one: CoarserGlossyPassAgreesWithTheFullOne).
// llvmpipe: ratios 1.732 (vertical) and 1.787 (horizontal) against 1.818; across 16.66 and 16.64 px against the
// isotropic α_b's 16.73 × 16.66.
TEST(PlanarReflection, AnisotropicGlossyMirrorBlursAlongItsWideAxis) {
  context();
  constexpr uint32_t kPx = 192;
  const vec3 lo(-0.15f, 2.6f, -5.65f), hi(0.15f, 2.9f, -5.35f);
  const vec2 alphas = ggxAnisotropicAlphas(0.25f * 0.25f, 0.6f, 0.1f);
  const double ratio = double(alphas.x / alphas.y);
  const Moments sharp = moments(renderFarMirror(glossyMirror(0.0f), lo, hi, kPx, 1).rgb, kPx);
  // The blur's variance along x and y (the blurred image's less the sharp one's), and its summed light.
  auto blur = [&](const sdb::Material& m, uint32_t scale) {
    const FarMirror f = renderFarMirror(m, lo, hi, kPx, scale);
    const Moments b = moments(f.rgb, kPx);
    // What reaches the image's border is a negligible part of the light (the moments are not cut off).
    double border = 0.0;
    for (uint32_t y = 0; y < kPx; ++y)
      for (uint32_t x = 0; x < kPx; ++x)
        if (x < 4 || y < 4 || x + 4 >= kPx || y + 4 >= kPx) border += f.rgb[3 * (size_t(y) * kPx + x) + 1];
    EXPECT_LT(border, 5e-3 * b.sum);
    EXPECT_NEAR(b.sum, sharp.sum, 0.01 * sharp.sum);
    return std::array<double, 3>{b.cxx - sharp.cxx, b.cyy - sharp.cyy, b.cxy - sharp.cxy};
  };
  {
    constexpr uint32_t scale = 1;
    sdb::Material brushed = glossyMirror(0.25f);
    brushed.anisotropyU = 0.6f;
    brushed.anisotropyV = 0.1f;
    const auto vertical = blur(brushed, scale);
    brushed.anisotropyRotationRad = float(kPi / 2);
    const auto horizontal = blur(brushed, scale);
    const auto narrow = blur(glossyMirror(std::sqrt(alphas.y)), scale);  // isotropic, α = α_b
    const auto round = blur(glossyMirror(0.25f), scale);                 // isotropic, α = 0.0625
    const double alongV = std::sqrt(vertical[1]), acrossV = std::sqrt(vertical[0]);
    const double alongH = std::sqrt(horizontal[0]), acrossH = std::sqrt(horizontal[1]);
    const double narrowX = std::sqrt(narrow[0]), narrowY = std::sqrt(narrow[1]);
    std::printf("blur σ along / across the tangent: vertical %.2f / %.2f px (ratio %.3f), horizontal %.2f / %.2f px "
                "(ratio %.3f), lobe %.3f; isotropic α_b: %.2f × %.2f px; U = V: %.2f × %.2f px\n",
                alongV, acrossV, alongV / acrossV, alongH, acrossH, alongH / acrossH,
                ratio, narrowX, narrowY, std::sqrt(round[0]), std::sqrt(round[1]));
    EXPECT_NEAR(alongV / acrossV, ratio, 0.1 * ratio);
    EXPECT_NEAR(alongH / acrossH, ratio, 0.1 * ratio);
    EXPECT_NEAR(acrossV, narrowX, 0.1 * narrowX);
    EXPECT_NEAR(acrossH, narrowY, 0.1 * narrowY);
    EXPECT_NEAR(std::sqrt(round[0] / round[1]), 1.0, 0.1);
    // The covariance's principal axes are the screen's (the tangent's image is vertical or horizontal).
    EXPECT_LT(std::abs(vertical[2]), 0.05 * vertical[1]);
    EXPECT_LT(std::abs(horizontal[2]), 0.05 * horizontal[0]);
  }
}

// Seen from below (its back), or out of the view, the mirror reflects nothing and no mirrored pass is drawn.
TEST(PlanarReflection, NoPassForAMirrorSeenFromBehindOrOutOfView) {
  context();
  MirrorScene s = mirrorScene(sdb::ReflectionModel::kUniform);
  Renderer renderer;
  renderer.upload(s.rdb);
  renderer.render(test::lookAtView(vec3(0.3f, -2.0f, 4.0f), vec3(0.0f, 0.0f, 0.0f), 50.0f), RenderMode::kSimple, 64, 64);
  EXPECT_EQ(renderer.stats().reflectionPasses, 0);
  renderer.render(test::lookAtView(vec3(0.3f, 2.0f, 4.0f), vec3(0.0f, 3.0f, 10.0f), 50.0f), RenderMode::kSimple, 64, 64);
  EXPECT_EQ(renderer.stats().reflectionPasses, 0);
  EXPECT_EQ(renderer.stats().scenePasses, 2);
  renderer.render(test::lookAtView(vec3(0.3f, 2.0f, 4.0f), vec3(0.0f, 0.0f, 0.0f), 50.0f), RenderMode::kSimple, 64, 64);
  EXPECT_EQ(renderer.stats().reflectionPasses, 1);
}

// Reflection fog (sdb::Material::reflectionFogDistanceM D, reflectionFogColor c): the mirror under an ambient
// term of E = 300 lux from above (simple mode; the mirror's corner factor is 0) shows at each pixel
// R · mix(L, c E / π, t), t = min(d / D, 1), d the distance from the mirror point to what the reflected ray
// meets (the box, of L = 1000 cd/m², from 0.86 m away: t from 0.43; nothing: t = 1, L = 0), by the same CPU
// ray cast. The engine's d comes from the mirrored pass's depth; a 2 mm error in it moves t by 10⁻³, the check
// allows 0.5 % of the expected luminance. Without fog the scene has no fog variant (and the tests above show
// R · L and 0).
TEST(PlanarReflection, ReflectionFogFadesTheImageToTheFogColourTimesTheIrradiance) {
  context();
  constexpr uint32_t kPx = 128;
  constexpr float kFogDistanceM = 2.0f;
  const Rgb fogColor(0.2f, 0.5f, 0.8f);
  const Rgb irradianceLux(300.0f);
  MirrorScene s = mirrorScene(sdb::ReflectionModel::kUniform, sdb::EngineReflection::kAuto, 0.0f, kFogDistanceM,
                              fogColor);
  ASSERT_EQ(s.rdb.planarReflectors.size(), 1u);
  EXPECT_TRUE(s.rdb.variants.reflectionFog);
  EXPECT_TRUE(sdb::computeFeatures(s.scene).reflectionFog);
  EXPECT_FALSE(sdb::computeFeatures(mirrorScene(sdb::ReflectionModel::kUniform).scene).reflectionFog);
  EXPECT_FALSE(mirrorScene(sdb::ReflectionModel::kUniform).rdb.variants.reflectionFog);
  s.rdb.ambient.upLux = irradianceLux;
  Renderer renderer;
  renderer.upload(s.rdb);
  const View view = test::lookAtView(vec3(0.3f, 2.0f, 4.0f), vec3(0.0f, 0.3f, 0.0f), 50.0f);
  renderer.render(view, RenderMode::kSimple, kPx, kPx);
  const std::vector<float> rgb = renderer.luminanceRgb();
  const vec3 eye(view.worldFromCamera[3]);
  const float tanY = std::tan(0.5f * view.yfovRad);
  const Rgb fogCdM2 = fogColor * irradianceLux / float(kPi);
  size_t boxPixels = 0, skyPixels = 0;
  double worst = 0.0, tMin = 1.0;
  for (uint32_t y = 1; y + 1 < kPx; ++y) {
    for (uint32_t x = 1; x + 1 < kPx; ++x) {
      // Pixels whose 3 × 3 neighbourhood the ray cast classifies alike, as `compare`.
      auto direction = [&](int dx, int dy) {
        const vec3 cam(((float(x) + float(dx) + 0.5f) / kPx * 2.0f - 1.0f) * tanY,
                       (1.0f - (float(y) + float(dy) + 0.5f) / kPx * 2.0f) * tanY, -1.0f);
        return glm::normalize(mat3(view.worldFromCamera) * cam);
      };
      const int k = classify(eye, direction(0, 0));
      bool uniform = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) uniform &= classify(eye, direction(dx, dy)) == k;
      if (!uniform || k < 2) continue;
      const vec3 d = direction(0, 0);
      const vec3 p = eye + (-eye.y / d.y) * d;
      const std::optional<float> reflectedM = hitBox(p, vec3(d.x, -d.y, d.z));
      const float t = reflectedM ? std::min(*reflectedM / kFogDistanceM, 1.0f) : 1.0f;
      const Rgb seen = reflectedM ? Rgb(kEmissionCdM2) : Rgb(0.0f);
      const Rgb expected = kReflection * ((1.0f - t) * seen + t * fogCdM2);
      for (int c = 0; c < 3; ++c) {
        const float got = rgb[3 * (size_t(y) * kPx + x) + size_t(c)];
        worst = std::max(worst, std::abs(double(got) / double(expected[c]) - 1.0));
      }
      (reflectedM ? boxPixels : skyPixels) += 1;
      if (reflectedM) tMin = std::min(tMin, double(t));
    }
  }
  std::printf("reflection fog: %zu pixels reflect the box (t from %.3f), %zu nothing; worst relative error %.2e\n",
              boxPixels, tMin, skyPixels, worst);
  EXPECT_GT(boxPixels, 300u);
  EXPECT_GT(skyPixels, 1000u);
  EXPECT_LT(tMin, 0.6);  // the comparison spans the fade, not only its end
  EXPECT_LT(worst, 5e-3);
}

}  // namespace
}  // namespace fly::raster
