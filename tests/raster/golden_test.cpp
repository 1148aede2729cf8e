// Golden images of each mode (raster output against a threshold, a diff image on failure), the
// sky pass against the sky image, and renderer updates against fresh uploads.
//
// The goldens live in tests/data/golden/raster-[<scene>-]<mode>-160x90.png; regenerate them (after a deliberate change,
// looking at the new images) with FLY_UPDATE_GOLDEN=1 tests/fly_raster_tests --gtest_filter='RasterGolden.*'.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "../support/helsinki_daylight.h"
#include "../support/raster_golden.h"
#include "base/tone_map.h"
#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/material_layers.h"
#include "sdb/material_presets.h"
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

  // Texture coordinates (read only where a material has a texture: texturedYard): the ground's from x and z
  // over its 12 m, each box face's and the fence's 0..1 over its 4 corners.
  auto cornerUvs = [](sdb::Mesh& mesh) {
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const int k = int(v % 4);
      mesh.uv0.push_back(vec2(k == 1 || k == 2 ? 1.0f : 0.0f, k >= 2 ? 0.0f : 1.0f));
    }
  };
  sdb::Mesh ground;
  ground.positions = {{-6, 0, -6}, {6, 0, -6}, {6, 0, 6}, {-6, 0, 6}};
  ground.normals.assign(4, vec3(0, 1, 0));
  ground.indices = {0, 2, 1, 0, 3, 2};
  for (const vec3& p : ground.positions) ground.uv0.push_back(vec2(p.x / 12.0f + 0.5f, p.z / 12.0f + 0.5f));
  ground.material = y.ground;
  y.scene.addNode({.name = "ground", .meshes = {y.scene.addMesh(ground).id}});
  sdb::Mesh box = test::box(vec3(-0.5f, 0, -0.5f), vec3(0.5f, 1, 0.5f), y.paint);
  cornerUvs(box);
  y.scene.addNode({.name = "box", .meshes = {y.scene.addMesh(box).id}});
  sdb::Mesh fence = test::quadXY(y.fence);  // 2 × 1 m, facing +Z
  fence.twoSided = true;
  cornerUvs(fence);
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

// `scene` names the golden: raster-<scene>-<mode>-160x90.png, or raster-<mode>-160x90.png for the yard
// (the rule: tests/support/raster_golden.h).
void checkGolden(RenderMode mode, const rdb::RasterRdb& r, double ev100, const std::string& scene = "") {
  test::checkGolden(mode, r, ev100,
                    std::string("raster-") + (scene.empty() ? "" : scene + "-") + renderModeName(mode) + "-160x90.png");
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

// A chrome sphere (uniform reflection 0.9, glossiness 0: a cube-map reflector) in the yard at sunset: its cube
// map holds the sky, the ground, the box and the fence (raster/cube_reflections.h).
TEST(RasterGolden, ChromeSphereSunlightMode) {
  context();
  Yard y = yard();
  sdb::Material chrome;
  chrome.name = "chrome";
  chrome.diffuseColor = Rgb(0.0f);
  chrome.reflectionColor = Rgb(0.9f);
  chrome.reflectionModel = sdb::ReflectionModel::kUniform;
  chrome.reflectionGlossiness = 0.0f;
  const sdb::MaterialId id = y.scene.addMaterial(chrome).id;
  y.scene.addNode({.name = "chrome", .meshes = {y.scene.addMesh(test::uvSphere(vec3(-0.9f, 0.4f, 1.0f), 0.4f, 24, 48, id)).id}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(y.scene);
  ASSERT_EQ(r.cubeReflectors.size(), 1u);
  checkGolden(RenderMode::kSunlight, r, 13.0, "chrome-sphere");
}

// The realistic material per pixel in the yard at sunset, one golden each (sunlight mode: the sky's image-based
// light, the sun, planar reflections):
// a mirror (uniform reflection 0.9, glossiness 0) standing behind the box — a planar reflector showing the box,
// the fence and the sky;
TEST(RasterGolden, MirrorSunlightMode) {
  context();
  Yard y = yard();
  sdb::Material mirror;
  mirror.name = "mirror";
  mirror.diffuseColor = Rgb(0.0f);
  mirror.reflectionColor = Rgb(0.9f);
  mirror.reflectionModel = sdb::ReflectionModel::kUniform;
  mirror.reflectionGlossiness = 0.0f;
  const sdb::MaterialId id = y.scene.addMaterial(mirror).id;
  y.scene.addNode({.name = "mirror",
                   .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0.2f, 0.6f, -1.0f)),
                   .meshes = {y.scene.addMesh(test::quadXY(id)).id}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(y.scene);
  ASSERT_EQ(r.planarReflectors.size(), 1u);
  checkGolden(RenderMode::kSunlight, r, 13.0, "mirror");
}

// a polished floor (the tiles preset, 4 % at normal incidence by Fresnel, glossiness 0.1, marked "planar") —
// the box and the fence mirrored in it, weak near the camera and stronger at grazing angles;
TEST(RasterGolden, PolishedFloorSunlightMode) {
  context();
  Yard y = yard();
  sdb::Material tiles = sdb::findMaterialPreset("tiles")->material;
  tiles.name = "ground";
  tiles.engineReflection = sdb::EngineReflection::kPlanar;
  y.scene.setMaterial(y.ground, tiles);
  const rdb::RasterRdb r = rdb::buildRasterRdb(y.scene);
  ASSERT_EQ(r.planarReflectors.size(), 1u);
  checkGolden(RenderMode::kSunlight, r, 13.0, "polished-floor");
}

// a frosted-glass pane (the preset: transmission glossiness 0.6) between the camera and the box — the box and
// the ground behind it blurred, neither hidden nor sharp;
TEST(RasterGolden, FrostedGlassSunlightMode) {
  context();
  Yard y = yard();
  sdb::Material frosted = sdb::findMaterialPreset("frosted-glass")->material;
  frosted.name = "frosted";
  const sdb::MaterialId id = y.scene.addMaterial(frosted).id;
  sdb::Mesh pane = test::quadXY(id);
  pane.twoSided = true;
  y.scene.addNode(
      {.name = "pane",
       .parentFromLocal = frameTransform(vec3(0.8f, 0, 0.6f), vec3(0, 1, 0), vec3(-0.6f, 0, 0.8f), vec3(-0.5f, 0.55f, 1.2f)),
       .meshes = {y.scene.addMesh(pane).id}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(y.scene);
  ASSERT_TRUE(r.variants.frostedGlass);
  checkGolden(RenderMode::kSunlight, r, 13.0, "frosted-glass");
}

// a brushed-metal plate (the preset: aluminium, glossiness 0.35, anisotropy 0.6 / 0.1) lying on the ground
// beside the box, its tangent along world −Z (n × x̂: the plate has no UVs) — the sky reflected by the lobe
// stretched along the tangent, and the highlight of a lamp of 400 cd 0.63 m above the plate where the eye sees it
// mirrored, stretched by the anisotropic lobe along the tangent (1.82 times as wide as across it).
TEST(RasterGolden, BrushedMetalSunlightMode) {
  context();
  Yard y = yard();
  sdb::Material brushed = sdb::findMaterialPreset("brushed-metal")->material;
  brushed.name = "brushed";
  const sdb::MaterialId id = y.scene.addMaterial(brushed).id;
  y.scene.addNode(
      {.name = "plate",
       .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 0, -1), vec3(0, 1, 0), vec3(-1.4f, 0.02f, 0.6f)),
       .meshes = {y.scene.addMesh(test::quadXY(id)).id}});
  sdb::Light lamp;
  lamp.intensity = 400.0f;
  y.scene.addNode({.name = "plate-lamp",
                   .parentFromLocal = glm::translate(mat4(1.0f), vec3(-1.08f, 0.47f, -0.23f)),
                   .light = y.scene.addLight(lamp).id});
  const rdb::RasterRdb r = rdb::buildRasterRdb(y.scene);
  ASSERT_TRUE(r.variants.anisotropy);
  checkGolden(RenderMode::kSunlight, r, 13.0, "brushed-metal");
}

// Small textures made here (the repository owns them as code): 8-bit RGB or RGBA, row-major from the top.
sdb::TextureId addTexture(sdb::Scene& s, const std::string& name, int w, int h, int channels,
                          const std::function<std::array<uint8_t, 4>(int x, int y)>& texel) {
  sdb::Texture t;
  t.name = name;
  t.sourcePath = "<generated>";
  t.width = w;
  t.height = h;
  t.channels = channels;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::array<uint8_t, 4> c = texel(x, y);
      t.pixels.insert(t.pixels.end(), c.begin(), c.begin() + channels);
    }
  }
  return s.addTexture(std::move(t)).id;
}

// The yard with textures: the ground a two-tone 8 × 8 checker repeated 3 × 3 times (KHR_texture_transform
// scale 3), the box a 4 × 4 colour ramp on each face, the fence dark (albedo 0.05) with an emission texture
// of stripes (40 cd/m² × the texel); the UVs are yard()'s.
Yard texturedYard() {
  Yard y = yard();
  sdb::Scene& s = y.scene;
  const sdb::TextureId checker = addTexture(s, "checker", 8, 8, 3, [](int x, int yy) {
    return (x + yy) % 2 ? std::array<uint8_t, 4>{200, 60, 40, 255} : std::array<uint8_t, 4>{230, 220, 200, 255};
  });
  const sdb::TextureId ramp = addTexture(s, "ramp", 4, 4, 3, [](int x, int yy) {
    return std::array<uint8_t, 4>{uint8_t(60 + 60 * x), uint8_t(60 + 60 * yy), 140, 255};
  });
  const sdb::TextureId stripes = addTexture(s, "stripes", 8, 1, 3, [](int x, int) {
    return x % 2 ? std::array<uint8_t, 4>{255, 200, 80, 255} : std::array<uint8_t, 4>{0, 0, 0, 255};
  });
  sdb::Material ground = s.material(y.ground);
  ground.diffuseColor = Rgb(1.0f);
  ground.diffuseTexture.texture = checker;
  ground.diffuseTexture.transform.scale = vec2(3.0f);
  s.setMaterial(y.ground, ground);
  sdb::Material paint = s.material(y.paint);
  paint.diffuseColor = Rgb(1.0f);
  paint.diffuseTexture.texture = ramp;
  s.setMaterial(y.paint, paint);
  sdb::Material fence = s.material(y.fence);
  fence.diffuseColor = Rgb(0.05f);
  fence.emissionLuminance = Rgb(40.0f);
  fence.emissionTexture.texture = stripes;
  s.setMaterial(y.fence, fence);
  return y;
}

TEST(RasterGolden, TexturedLightMapMode) {
  context();
  Yard y = texturedYard();
  const rdb::LightMapStore maps = syntheticLightMaps(rdb::buildRasterRdb(y.scene));
  const rdb::RasterRdb r = rdb::buildRasterRdb(y.scene, &maps);
  ASSERT_TRUE(r.variants.textures);
  checkGolden(RenderMode::kLightMap, r, 6.5, "textured");
}

TEST(RasterGolden, TexturedSunlightMode) {
  context();
  Yard y = texturedYard();
  checkGolden(RenderMode::kSunlight, rdb::buildRasterRdb(y.scene), 13.0, "textured");
}

// A wall (2 × 1 m) facing the camera with a 16 × 16 normal map of a 2 × 2 grid of bumps (height sin(2πu·2) ·
// sin(2πv·2), slopes up to 0.3 · 4π), lit from the left by a 300 cd lamp at a grazing angle: the bumps' lit
// and shaded sides.
TEST(RasterGolden, NormalMappedSimpleMode) {
  context();
  sdb::Scene s;
  const sdb::TextureId bumps = addTexture(s, "bumps", 16, 16, 3, [](int x, int y) {
    const double u = (x + 0.5) / 16.0, v = (y + 0.5) / 16.0, k = 2.0 * kPi * 2.0, a = 0.3;
    // ∂h/∂u, ∂h/∂v; the normal's y is along −v (the image's top).
    const double du = a * k * std::cos(k * u) * std::sin(k * v), dv = a * k * std::sin(k * u) * std::cos(k * v);
    const dvec3 n = glm::normalize(dvec3(-du, dv, 1.0));
    auto enc = [](double c) { return uint8_t(std::lround((c * 0.5 + 0.5) * 255.0)); };
    return std::array<uint8_t, 4>{enc(n.x), enc(n.y), enc(n.z), 255};
  });
  sdb::Material m;
  m.name = "plaster";
  m.diffuseColor = Rgb(0.7f, 0.65f, 0.6f);
  m.bumpTexture.texture = bumps;
  const sdb::MaterialId plaster = s.addMaterial(m).id;
  sdb::Mesh wall = test::quadXY(plaster);
  for (const vec3& p : wall.positions) wall.uv0.push_back(vec2((p.x + 1.0f) * 0.5f, 0.5f - p.y));
  s.addNode({.name = "wall", .meshes = {s.addMesh(wall).id}});
  sdb::Light lamp;
  lamp.intensity = 300.0f;
  s.addNode({.name = "lamp",
             .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(-1.6f, 0.3f, 0.3f)),
             .light = s.addLight(lamp).id});
  sdb::Camera cam;
  cam.name = "front";
  s.addNode({.name = "eye",
             .parentFromLocal = sdb::lookAtTransform(vec3(0, 0, 2.2f), vec3(0, 0, 0), vec3(0, 1, 0)),
             .camera = s.addCamera(cam).id});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s);
  ASSERT_TRUE(r.variants.normalMaps);
  checkGolden(RenderMode::kSimple, r, 7.0, "normalmap");
}

// A cut-out quad (a 16 × 16 RGBA texture: a red disc with a square hole, alpha 0 around and in the hole,
// cut-off 0.5) 0.5 m in front of a bright emissive wall (200 cd/m²), lit by a lamp: the wall shows through the hole and
// around the disc.
TEST(RasterGolden, AlphaMaskSimpleMode) {
  context();
  sdb::Scene s;
  const sdb::TextureId disc = addTexture(s, "disc", 16, 16, 4, [](int x, int y) {
    const double dx = x + 0.5 - 8.0, dy = y + 0.5 - 8.0;
    const bool inDisc = dx * dx + dy * dy < 7.2 * 7.2;
    const bool hole = std::abs(dx) < 2.0 && std::abs(dy) < 2.0;
    return std::array<uint8_t, 4>{220, 40, 30, uint8_t(inDisc && !hole ? 255 : 0)};
  });
  sdb::Material cut;
  cut.name = "cut-out";
  cut.diffuseColor = Rgb(1.0f);
  cut.diffuseTexture.texture = disc;
  cut.alphaMode = sdb::AlphaMode::kMask;
  cut.alphaCutoff = 0.5f;
  const sdb::MaterialId cutId = s.addMaterial(cut).id;
  sdb::Material glow;
  glow.name = "wall";
  glow.diffuseColor = Rgb(0.0f);
  glow.emissionLuminance = Rgb(120.0f, 200.0f, 255.0f);
  const sdb::MaterialId glowId = s.addMaterial(glow).id;
  sdb::Mesh quad = test::quadXY(cutId);
  quad.positions = {{-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 0.0f}, {-0.5f, 0.5f, 0.0f}};
  for (const vec3& p : quad.positions) quad.uv0.push_back(vec2(p.x + 0.5f, 0.5f - p.y));
  s.addNode({.name = "cut-out", .meshes = {s.addMesh(quad).id}});
  s.addNode({.name = "wall",
             .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 0, -0.5f)),
             .meshes = {s.addMesh(test::quadXY(glowId)).id}});
  sdb::Light lamp;
  lamp.intensity = 200.0f;
  s.addNode({.name = "lamp",
             .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0.3f, 0.5f, 1.0f)),
             .light = s.addLight(lamp).id});
  sdb::Camera cam;
  cam.name = "front";
  s.addNode({.name = "eye",
             .parentFromLocal = sdb::lookAtTransform(vec3(0.4f, 0.2f, 1.6f), vec3(0, 0, -0.2f), vec3(0, 1, 0)),
             .camera = s.addCamera(cam).id});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s);
  ASSERT_TRUE(r.variants.alphaMask);
  checkGolden(RenderMode::kSimple, r, 8.0, "mask");
}

// A sphere of car paint as the glTF importer makes it from KHR_materials_clearcoat: a red metallic base
// (reflectance 0.5, 0.05, 0.04, roughness 0.6) under a full coat of roughness 0.35, which becomes a red diffuse
// body under the coat's white 4 % Fresnel lobe (sdb/material_layers.h), lit by two lamps: the coat's
// highlights over the paint's colour.
TEST(RasterGolden, ClearCoatedSimpleMode) {
  context();
  sdb::Scene s;
  sdb::Material metal;
  metal.name = "red-metal";
  metal.diffuseColor = Rgb(0.0f);
  metal.reflectionModel = sdb::ReflectionModel::kUniform;
  metal.reflectionColor = Rgb(0.5f, 0.05f, 0.04f);
  metal.reflectionGlossiness = 0.6f;
  const sdb::CoatedMaterial paint = sdb::applyClearCoat(metal, {.amount = 1.0f, .glossiness = 0.35f});
  ASSERT_TRUE(paint.coatIsLobe);
  const sdb::MaterialId paintId = s.addMaterial(paint.material).id;
  sdb::Mesh sphere;
  sphere.name = "sphere";
  sphere.material = paintId;
  constexpr int kRings = 24, kSegments = 48;
  for (int i = 0; i <= kRings; ++i) {
    for (int j = 0; j <= kSegments; ++j) {
      const float theta = float(kPi) * float(i) / kRings, phi = 2.0f * float(kPi) * float(j) / kSegments;
      const vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      sphere.positions.push_back(0.5f * d);
      sphere.normals.push_back(d);
    }
  }
  for (uint32_t i = 0; i < uint32_t(kRings); ++i) {
    for (uint32_t j = 0; j < uint32_t(kSegments); ++j) {
      const uint32_t a = i * (kSegments + 1) + j, b = a + 1, c = a + kSegments + 1, d = c + 1;
      sphere.indices.insert(sphere.indices.end(), {a, c, b, b, c, d});
    }
  }
  s.addNode({.name = "sphere", .meshes = {s.addMesh(sphere).id}});
  sdb::Light key, fill;
  key.intensity = 600.0f;
  fill.intensity = 150.0f;
  s.addNode({.name = "key",
             .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(-1.2f, 1.2f, 1.5f)),
             .light = s.addLight(key).id});
  s.addNode({.name = "fill",
             .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(1.5f, -0.3f, 1.0f)),
             .light = s.addLight(fill).id});
  sdb::Camera cam;
  cam.name = "front";
  s.addNode({.name = "eye",
             .parentFromLocal = sdb::lookAtTransform(vec3(0, 0.2f, 2.0f), vec3(0, 0, 0), vec3(0, 1, 0)),
             .camera = s.addCamera(cam).id});
  checkGolden(RenderMode::kSimple, rdb::buildRasterRdb(s), 5.0, "clearcoat");
}

// Two spheres of the measured car paints (the metallic-car-paint and pearl-car-paint presets' BRDFs, shown by
// ball textures: raster/ball_texture.h) under 5 point lights, FLY §4's test case, in simple mode; and the same
// under Helsinki's clear sky at 18:00 in sunlight mode (sky and sun in the balls).
sdb::Scene carPaintSpheres() {
  sdb::Scene s;
  for (const char* preset : {"metallic-car-paint", "pearl-car-paint"}) {
    const sdb::MaterialPreset* p = sdb::findMaterialPreset(preset);
    EXPECT_TRUE(p && p->material.isMeasured()) << preset;
    const sdb::MaterialId id = s.addMaterial(p->material).id;
    const float x = std::string(preset) == "pearl-car-paint" ? 0.6f : -0.6f;
    s.addNode({.name = preset, .meshes = {s.addMesh(test::uvSphere(vec3(x, 0.0f, 0.0f), 0.5f, 32, 64, id)).id}});
  }
  const vec3 lamps[5] = {{-2.0f, 2.0f, 2.5f}, {2.5f, 1.0f, 2.0f}, {0.0f, -1.5f, 2.5f}, {-3.0f, -0.5f, 0.5f},
                         {1.0f, 3.0f, -1.0f}};
  const float candela[5] = {800.0f, 500.0f, 300.0f, 400.0f, 600.0f};
  for (int k = 0; k < 5; ++k) {
    sdb::Light l;
    l.intensity = candela[k];
    s.addNode({.name = "lamp",
               .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), lamps[k]),
               .light = s.addLight(l).id});
  }
  sdb::Camera cam;
  cam.name = "front";
  s.addNode({.name = "eye",
             .parentFromLocal = sdb::lookAtTransform(vec3(0, 0.3f, 3.2f), vec3(0, 0, 0), vec3(0, 1, 0)),
             .camera = s.addCamera(cam).id});
  return s;
}

TEST(RasterGolden, CarPaintSpheresSimpleMode) {
  context();
  checkGolden(RenderMode::kSimple, rdb::buildRasterRdb(carPaintSpheres()), 5.5, "car-paint");
}

TEST(RasterGolden, CarPaintSpheresSunlightMode) {
  context();
  sdb::Scene s = carPaintSpheres();
  fly::test::setHelsinkiClearSky(s, "2026-06-21T18:00");
  checkGolden(RenderMode::kSunlight, rdb::buildRasterRdb(s), 13.0, "car-paint");
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
