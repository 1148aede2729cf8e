// Golden images of each mode (STYLE.md 9: raster output against a threshold, a diff image on failure), the
// sky pass against the sky image, and renderer updates against fresh uploads.
//
// The goldens live in tests/data/golden/raster-<mode>-160x90.png; regenerate them (after a deliberate change,
// looking at the new images) with FLY_UPDATE_GOLDEN=1 tests/fly_raster_tests --gtest_filter='RasterGolden.*'.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "base/image_io.h"
#include "../support/helsinki_daylight.h"
#include "base/tone_map.h"
#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

// A matte box (1 m) on a 12 m ground with a two-sided fence beside it, a 400 cd lamp above, a camera looking
// at them from 4 m; site Helsinki, clear sky with sun at 2026-06-21 18:00 (low sun, the sky in view).
struct Yard {
  sdb::Scene scene;
  sdb::MaterialId ground, paint, fence;
};

Yard yard() {
  Yard y;
  sdb::Material m;
  m.name = "ground";
  m.diffuseColor = Rgb(0.3f, 0.35f, 0.25f);
  y.ground = y.scene.addMaterial(m).id;
  m.name = "paint";
  m.diffuseColor = Rgb(0.8f, 0.3f, 0.2f);
  m.reflectionColor = Rgb(1.0f);
  m.reflectionGlossiness = 0.4f;
  y.paint = y.scene.addMaterial(m).id;
  m = sdb::Material{};
  m.name = "fence";
  m.diffuseColor = Rgb(0.6f, 0.6f, 0.7f);
  y.fence = y.scene.addMaterial(m).id;

  sdb::Mesh ground;
  ground.positions = {{-6, 0, -6}, {6, 0, -6}, {6, 0, 6}, {-6, 0, 6}};
  ground.normals.assign(4, vec3(0, 1, 0));
  ground.indices = {0, 2, 1, 0, 3, 2};
  ground.material = y.ground;
  y.scene.addNode({.name = "ground", .meshes = {y.scene.addMesh(ground).id}});
  y.scene.addNode(
      {.name = "box",
       .meshes = {y.scene.addMesh(test::box(vec3(-0.5f, 0, -0.5f), vec3(0.5f, 1, 0.5f), y.paint)).id}});
  sdb::Mesh fence = test::quadXY(y.fence);  // 2 × 1 m, facing +Z
  fence.twoSided = true;
  y.scene.addNode(
      {.name = "fence",
       .parentFromLocal = frameTransform(vec3(0, 0, 1), vec3(0, 1, 0), vec3(-1, 0, 0), vec3(1.5f, 0.5f, 0)),
       .meshes = {y.scene.addMesh(fence).id}});
  sdb::Light lamp;
  lamp.intensity = 400.0f;
  y.scene.addNode(
      {.name = "lamp",
       .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0.3f, 2.5f, 0.8f)),
       .light = y.scene.addLight(lamp).id});
  sdb::Camera cam;
  cam.name = "front";
  y.scene.addNode(
      {.name = "eye",
       .parentFromLocal = sdb::lookAtTransform(vec3(-2.5f, 1.6f, 3.5f), vec3(0.3f, 0.6f, 0), vec3(0, 1, 0)),
       .camera = y.scene.addCamera(cam).id});
  fly::test::setHelsinkiClearSky(y.scene, "2026-06-21T18:00");
  return y;
}

// Synthetic vertex light maps, a smooth function of position (front) and a dimmer one (back), lux.
rdb::LightMapStore syntheticLightMaps(const rdb::RasterRdb& r) {
  rdb::LightMapStore store;
  for (const rdb::RasterMesh& m : r.meshes) {
    rdb::MeshLightMap map{m.sdbNodeId, m.sdbMeshId, {}, {}};
    for (uint32_t v = m.firstVertex; v < m.firstVertex + m.vertexCount; ++v) {
      const vec3 p = r.positionsM[v];
      map.frontLux.push_back(Rgb(300.0f + 100.0f * p.x, 250.0f + 150.0f * p.y, 200.0f - 20.0f * p.z));
      if (m.twoSided) map.backLux.push_back(Rgb(40.0f + 10.0f * p.y));
    }
    store.meshes.push_back(std::move(map));
  }
  return store;
}

constexpr uint32_t kW = 160, kH = 90;

// Renders `mode` and compares the linear tone-mapped image at `ev100` with its golden: per channel at most 3
// levels off on ≥ 99.5 % of the pixels and no pixel more than 48 levels off (rasterisation rules and
// floating-point order may move an edge pixel between drivers).
void checkGolden(RenderMode mode, const rdb::RasterRdb& r, double ev100) {
  Renderer renderer;
  renderer.upload(r);
  renderer.render(viewOfCamera(r.cameras.at(0)), mode, kW, kH);
  renderer.toneMap({ToneOperator::kLinear, ev100});
  const std::vector<uint8_t> px = renderer.srgb8();
  const std::string name = std::string("raster-") + renderModeName(mode) + "-160x90.png";
  const std::filesystem::path golden = std::filesystem::path(FLY_TEST_DATA_DIR) / "golden" / name;
  if (std::getenv("FLY_UPDATE_GOLDEN")) {
    writePng(golden, int(kW), int(kH), 3, px.data());
    GTEST_SKIP() << "wrote " << golden;
  }
  ASSERT_TRUE(std::filesystem::exists(golden)) << golden << " is missing; see the top of golden_test.cpp";
  const ImageU8 g = readPng(golden);
  ASSERT_EQ(g.width, int(kW));
  ASSERT_EQ(g.height, int(kH));
  ASSERT_EQ(g.channels, 3);
  size_t off = 0;
  int worst = 0;
  std::vector<uint8_t> diff(px.size());
  for (size_t i = 0; i < px.size(); ++i) {
    const int d = std::abs(int(px[i]) - int(g.pixels[i]));
    worst = std::max(worst, d);
    off += d > 3;
    diff[i] = uint8_t(std::min(255, d * 8));
  }
  const bool ok = off * 1000 <= px.size() * 5 && worst <= 48;
  if (!ok) {
    const std::filesystem::path out = std::filesystem::absolute("golden-diff-" + name);
    writePng(out, int(kW), int(kH), 3, diff.data());
    writePng(std::filesystem::absolute("golden-actual-" + name), int(kW), int(kH), 3, px.data());
    ADD_FAILURE() << name << ": " << off << " of " << px.size() << " values differ by more than 3, worst "
                  << worst << "; the difference (×8) is in " << out;
  }
}

TEST(RasterGolden, SimpleMode) {
  context();
  Yard y = yard();
  // Daylight exposure: the simple mode shades with the scene's sun and the sky's ambient term, as well as
  // the lamp.
  checkGolden(RenderMode::kSimple, rdb::buildRasterRdb(y.scene), 13.0);
}

TEST(RasterGolden, LightMapMode) {
  context();
  Yard y = yard();
  const rdb::LightMapStore maps = syntheticLightMaps(rdb::buildRasterRdb(y.scene));
  checkGolden(RenderMode::kLightMap, rdb::buildRasterRdb(y.scene, &maps), 6.5);
}

TEST(RasterGolden, SunlightMode) {
  context();
  Yard y = yard();
  checkGolden(RenderMode::kSunlight, rdb::buildRasterRdb(y.scene), 13.0);
}

// An orthographic view sees one direction in every pixel: the sky image's value there (at a texel centre, so
// no filtering), and with the sun in view the sun's radiance on top.
TEST(RasterSkyPass, ShowsTheSkyImageInTheViewDirectionAndTheSunDisc) {
  context();
  Yard y = yard();
  const rdb::RasterRdb r = rdb::buildRasterRdb(y.scene, nullptr, {32, 16});
  ASSERT_TRUE(r.sky.has_value());
  const rdb::RasterSky& s = *r.sky;
  Renderer renderer;
  renderer.upload(r);
  // Texel (i, j) = (5, 3): φ = 2π · 5.5/32, θ = π · 3.5/16 (above the horizon, below the camera's far plane:
  // the ground is out of an orthographic view placed 100 km up).
  const double phi = 2.0 * kPi * 5.5 / 32.0, theta = kPi * 3.5 / 16.0;
  const vec3 d(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
               float(std::sin(theta) * std::sin(phi)));
  View v;
  v.orthographic = true;
  v.ymagM = 1.0f;
  v.znearM = 1.0f;
  v.zfarM = 2.0f;
  const vec3 z = -d;  // the camera looks down −Z
  const vec3 x = glm::normalize(glm::cross(vec3(0, 1, 0), z));
  v.worldFromCamera = frameTransform(x, glm::cross(z, x), z, vec3(0, 1e5f, 0));
  renderer.render(v, RenderMode::kSunlight, 8, 4);
  const Rgb expected = s.radianceCdM2[3 * 32 + 5];
  const std::vector<float> img = renderer.luminanceRgb();
  for (size_t p = 0; p < 32; ++p) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(img[3 * p + size_t(c)], expected[c], 1e-4f * expected[c] + 1e-3f);
  }
  ASSERT_TRUE(s.hasSun);
  const vec3 zs = -s.sunDirWorld;
  const vec3 xs = glm::normalize(glm::cross(vec3(0, 1, 0), zs));
  v.worldFromCamera = frameTransform(xs, glm::cross(zs, xs), zs, vec3(0, 1e5f, 0));
  renderer.render(v, RenderMode::kSunlight, 8, 4);
  EXPECT_GE(
      luminance(Rgb(renderer.luminanceRgb()[0], renderer.luminanceRgb()[1], renderer.luminanceRgb()[2])),
      0.999f * luminance(s.sunRadianceCdM2));
  EXPECT_NE(std::find(renderer.stats().programs.begin(), renderer.stats().programs.end(), "sky"),
            renderer.stats().programs.end());
}

// A material edit re-uploads one block and renders what a fresh upload of a rebuilt RasterRdb renders.
TEST(RendererUpdate, MaterialEditReUploadsOneBlockAndMatchesAFreshUpload) {
  context();
  Yard y = yard();
  rdb::RasterRdb r = rdb::buildRasterRdb(y.scene);
  Renderer renderer;
  renderer.upload(r);
  const View view = viewOfCamera(r.cameras.at(0));
  renderer.render(view, RenderMode::kSimple, 64, 36);
  const std::vector<float> before = renderer.luminanceRgb();
  sdb::Material paint = y.scene.material(y.paint);
  paint.diffuseColor = Rgb(0.1f, 0.7f, 0.2f);
  const rdb::RasterRdbChanges ch = rdb::updateRasterRdb(r, y.scene, y.scene.setMaterial(y.paint, paint));
  renderer.update(r, ch);
  renderer.render(view, RenderMode::kSimple, 64, 36);
  const std::vector<float> after = renderer.luminanceRgb();
  EXPECT_EQ(renderer.stats().geometryUploads, 1);
  EXPECT_EQ(renderer.stats().materialBlockUploads, 1);
  EXPECT_EQ(renderer.stats().materialTableUploads, 1);
  EXPECT_EQ(renderer.stats().skyUploads, 1);
  EXPECT_NE(before, after);

  const rdb::RasterRdb fresh = rdb::buildRasterRdb(y.scene);
  Renderer other;
  other.upload(fresh);
  other.render(view, RenderMode::kSimple, 64, 36);
  EXPECT_EQ(after, other.luminanceRgb());
}

// A new time of day re-uploads the sky only, and renders what a fresh upload of a rebuilt RasterRdb renders.
TEST(RendererUpdate, TimeOfDayReUploadsOnlyTheSky) {
  context();
  Yard y = yard();
  rdb::RasterRdb r = rdb::buildRasterRdb(y.scene, nullptr, {64, 32});
  Renderer renderer;
  renderer.upload(r);
  const View view = viewOfCamera(r.cameras.at(0));
  renderer.render(view, RenderMode::kSunlight, 64, 36);
  const std::vector<float> evening = renderer.luminanceRgb();
  const rdb::RasterRdbChanges ch =
      rdb::updateRasterRdb(r, y.scene, y.scene.setTime({"2026-06-21T06:00"}), nullptr, {64, 32});
  renderer.update(r, ch);
  EXPECT_EQ(renderer.stats().geometryUploads, 1);
  EXPECT_EQ(renderer.stats().materialTableUploads, 1);
  EXPECT_EQ(renderer.stats().materialBlockUploads, 0);
  EXPECT_EQ(renderer.stats().lightUploads, 1);
  EXPECT_EQ(renderer.stats().skyUploads, 2);
  renderer.render(view, RenderMode::kSunlight, 64, 36);
  const std::vector<float> morning = renderer.luminanceRgb();
  EXPECT_NE(evening, morning);
  Renderer other;
  const rdb::RasterRdb fresh = rdb::buildRasterRdb(y.scene, nullptr, {64, 32});
  other.upload(fresh);
  other.render(view, RenderMode::kSunlight, 64, 36);
  EXPECT_EQ(morning, other.luminanceRgb());
}

}  // namespace
}  // namespace fly::raster
