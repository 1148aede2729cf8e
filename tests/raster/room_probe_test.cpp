// The room probe (raster/room_probe.h): its box from a face's depth, and what a polished floor reflects with
// it — the room inside a closed room, the sky outdoors — in light-map and sunlight modes.
#include "raster/room_probe.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/light_map_store.h"
#include "rdb/raster_rdb.h"
#include "sdb/material.h"
#include "sdb/scene.h"
#include "split_sum_reference.h"

namespace fly::raster {
namespace {

using test::context;

constexpr uint32_t kFacePx = 64;
constexpr float kNearM = 0.02f;

// The window depth of an infinite-far perspective view of a point at axial distance d: 1 − n / d.
float depthAt(float distanceM) { return 1.0f - kNearM / distanceM; }

TEST(RoomProbeBox, AWallFacingTheProbeGivesItsDistance) {
  for (float d : {0.3f, 2.0f, 17.5f}) {
    const std::vector<float> depth(kFacePx * kFacePx, depthAt(d));
    EXPECT_NEAR(RoomProbe::sideDistanceM(depth, kFacePx, kNearM) / d, 1.0f, 1e-3f) << d << " m";
  }
}

TEST(RoomProbeBox, MostlySkyIsAnOpenSideAndFurnitureInTheMiddleIsIgnored) {
  // The central half of the face (32 × 32 texels) 60 % sky: open.
  std::vector<float> depth(kFacePx * kFacePx, depthAt(3.0f));
  for (uint32_t y = 16; y < 16 + 20; ++y) {
    for (uint32_t x = 0; x < kFacePx; ++x) depth[y * kFacePx + x] = 1.0f;
  }
  EXPECT_EQ(RoomProbe::sideDistanceM(depth, kFacePx, kNearM), kOpenSideM);
  // A table at 1 m over 40 % of the central half in front of a wall at 3 m: the wall.
  std::vector<float> room(kFacePx * kFacePx, depthAt(3.0f));
  for (uint32_t y = 16; y < 16 + 13; ++y) {
    for (uint32_t x = 0; x < kFacePx; ++x) room[y * kFacePx + x] = depthAt(1.0f);
  }
  EXPECT_NEAR(RoomProbe::sideDistanceM(room, kFacePx, kNearM), 3.0f, 3e-3f);
}

// Walls and ceiling: Lambertian, albedo 0.5.
sdb::Material wallMaterial() {
  sdb::Material m;
  m.name = "wall";
  m.diffuseColor = Rgb(0.5f);
  m.reflectionColor = Rgb(0.0f);
  return m;
}

// A polished floor with no diffuse part: it shows only what it reflects (Fresnel, ior 1.5, GGX α = 0.09).
sdb::Material polishedMaterial() {
  sdb::Material m;
  m.name = "polished floor";
  m.diffuseColor = Rgb(0.0f);
  m.reflectionColor = Rgb(1.0f);
  m.reflectionModel = sdb::ReflectionModel::kFresnel;
  m.ior = 1.5f;
  m.reflectionGlossiness = 0.3f;
  return m;
}

// A polished floor (no diffuse part: it shows only what it reflects; GGX α = 0.09, F0 = 0.04) in a room
// lit so that its walls and ceiling show `wallCdM2` (light maps of π·wall/0.5 lx on albedo 0.5), under a
// uniform sky of `skyCdM2` — closed, or without walls and ceiling (`open`: the floor alone); `planar`: the floor
// is a planar reflector (sdb::EngineReflection::kPlanar), which shows its own mirrored image.
rdb::RasterRdb floorScene(bool open, float wallCdM2, float skyCdM2, bool planar = false) {
  sdb::Scene scene;
  const sdb::MaterialId wallId = scene.addMaterial(wallMaterial()).id;
  sdb::Material polished = polishedMaterial();
  if (planar) polished.engineReflection = sdb::EngineReflection::kPlanar;
  const sdb::MaterialId floorId = scene.addMaterial(polished).id;
  rdb::LightMapStore store;
  if (!open) {
    const sdb::MeshId room = scene.addMesh(test::box(vec3(-2, 0, -2), vec3(2, 3, 2), wallId, true)).id;
    const sdb::NodeId node = scene.addNode({.name = "room", .meshes = {room}}).id;
    store.meshes.push_back({node.value, room.value, std::vector<Rgb>(24, Rgb(float(kPi) * wallCdM2 / 0.5f)), {}});
  }
  sdb::Mesh floor;
  floor.name = "floor";
  floor.positions = {{-1.9f, 0.001f, -1.9f}, {1.9f, 0.001f, -1.9f}, {1.9f, 0.001f, 1.9f}, {-1.9f, 0.001f, 1.9f}};
  floor.normals.assign(4, vec3(0, 1, 0));
  floor.indices = {0, 2, 1, 0, 3, 2};  // counter-clockwise seen from +Y
  floor.material = floorId;
  const sdb::MeshId floorMesh = scene.addMesh(floor).id;
  const sdb::NodeId floorNode = scene.addNode({.name = "floor", .meshes = {floorMesh}}).id;
  store.meshes.push_back({floorNode.value, floorMesh.value, std::vector<Rgb>(4, Rgb(0.0f)), {}});
  rdb::RasterRdb r = rdb::buildRasterRdb(scene, &store);
  rdb::RasterSky sky;
  sky.width = 64;
  sky.height = 32;
  sky.radianceCdM2.assign(64 * 32, Rgb(skyCdM2));
  r.sky = sky;
  r.variants.sky = true;
  return r;
}

// The mean luminance of the image's central 4 × 4 pixels.
double centreLuminance(const Renderer& renderer, uint32_t size) {
  const std::vector<float> rgb = renderer.luminanceRgb();
  double sum = 0.0;
  for (uint32_t y = size / 2 - 2; y < size / 2 + 2; ++y) {
    for (uint32_t x = size / 2 - 2; x < size / 2 + 2; ++x) {
      const size_t i = 3 * (size_t(y) * size + x);
      sum += luminance(Rgb(rgb[i], rgb[i + 1], rgb[i + 2]));
    }
  }
  return sum / 16.0;
}

constexpr uint32_t kSize = 32;
const vec3 kEye(0.0f, 1.5f, 0.3f);

TEST(RoomProbe, APolishedFloorInAClosedRoomReflectsTheRoomNotTheSky) {
  context();
  constexpr float kWallCdM2 = 100.0f, kSkyCdM2 = 10000.0f;
  const rdb::RasterRdb r = floorScene(false, kWallCdM2, kSkyCdM2);
  const View view = test::lookAtView(kEye, vec3(0.0f), 20.0f);
  // The floor's centre pixel sees the eye at cos θo = 1.5 / √(1.5² + 0.3²); its lobe sees walls and ceiling
  // alone, all at kWallCdM2: L = kWallCdM2 (F0 A + F90 B).
  const float cosO = 1.5f / std::sqrt(1.5f * 1.5f + 0.3f * 0.3f);
  const vec2 ab = test::splitSumByQuadrature(cosO, 0.09f, 1024, 256);
  const rdb::RasterMaterial& floor = r.materials.back();
  const double expected = kWallCdM2 * luminance(floor.specular * ab.x + floor.environmentF90 * ab.y);
  for (const RenderMode mode : {RenderMode::kLightMap, RenderMode::kSunlight}) {
    Renderer withProbe, without;
    without.setRoomProbe(false);
    withProbe.upload(r);
    without.upload(r);
    withProbe.render(view, mode, kSize, kSize);
    without.render(view, mode, kSize, kSize);
    const double l = centreLuminance(withProbe, kSize), lWithout = centreLuminance(without, kSize);
    std::printf("%s mode: the floor shows %.3f cd/m² (the room through the split sum: %.3f), %.3f without the "
                "probe\n",
                renderModeName(mode), l, expected, lWithout);
    EXPECT_NEAR(l / expected, 1.0, 0.03) << renderModeName(mode);
    EXPECT_EQ(withProbe.stats().probeCaptures, 1);
    EXPECT_EQ(without.stats().probeCaptures, 0);
    // Without it the floor shows the sky times its light map's specular occlusion (0: its light map is dark)
    // in sunlight mode, and nothing in light-map mode.
    EXPECT_LT(lWithout, 0.01 * expected);
  }
}

// A quad at height y facing down, over x in [x0, x1], z in [−4, 4].
sdb::Mesh ceilingPart(float x0, float x1, float y, sdb::MaterialId material) {
  sdb::Mesh m;
  m.name = "ceiling";
  m.positions = {{x0, y, -4}, {x1, y, -4}, {x1, y, 4}, {x0, y, 4}};
  m.normals.assign(4, vec3(0, -1, 0));
  m.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from below
  m.material = material;
  return m;
}

// The box projection: an 8 × 3 × 8 m room whose ceiling shows 50 cd/m² over x < 0 and 200 cd/m² over x > 0
// (walls 100). From the eye at (0.8, 2, 0) the floor point (−0.5, 0, 0) mirrors the eye towards the ceiling at
// x = −2.45 (the dark half), where the same direction from the probe's centre meets it at x = 0.15 (the bright
// half): the floor must show the dark half (blurred towards the wall).
TEST(RoomProbe, TheBoxPlacesAReflectionWhereTheMirrorRayMeetsTheRoom) {
  context();
  sdb::Scene scene;
  const sdb::MaterialId wallId = scene.addMaterial(wallMaterial()).id;
  const sdb::MaterialId floorId = scene.addMaterial(polishedMaterial()).id;
  rdb::LightMapStore store;
  auto add = [&](const sdb::Mesh& mesh, float cdM2) {
    const sdb::MeshId id = scene.addMesh(mesh).id;
    const sdb::NodeId node = scene.addNode({.name = mesh.name, .meshes = {id}}).id;
    store.meshes.push_back(
        {node.value, id.value, std::vector<Rgb>(mesh.positions.size(), Rgb(float(kPi) * cdM2 / 0.5f)), {}});
  };
  add(test::box(vec3(-4, 0, -4), vec3(4, 3, 4), wallId, true), 100.0f);
  add(ceilingPart(-4.0f, 0.0f, 2.999f, wallId), 50.0f);
  add(ceilingPart(0.0f, 4.0f, 2.999f, wallId), 200.0f);
  sdb::Mesh floor;
  floor.name = "floor";
  floor.positions = {{-3.9f, 0.001f, -3.9f}, {3.9f, 0.001f, -3.9f}, {3.9f, 0.001f, 3.9f}, {-3.9f, 0.001f, 3.9f}};
  floor.normals.assign(4, vec3(0, 1, 0));
  floor.indices = {0, 2, 1, 0, 3, 2};
  floor.material = floorId;
  add(floor, 0.0f);
  rdb::RasterRdb r = rdb::buildRasterRdb(scene, &store);
  rdb::RasterSky sky;
  sky.width = 64;
  sky.height = 32;
  sky.radianceCdM2.assign(64 * 32, Rgb(10000.0f));
  r.sky = sky;
  r.variants.sky = true;

  const vec3 eye(0.8f, 2.0f, 0.0f), target(-0.5f, 0.0f, 0.0f);
  const View view = test::lookAtView(eye, target, 30.0f);
  const float cosO = 2.0f / glm::length(eye - target);
  const vec2 ab = test::splitSumByQuadrature(cosO, 0.09f, 1024, 256);
  const rdb::RasterMaterial& block = r.materials.back();
  const double lobe = luminance(block.specular * ab.x + block.environmentF90 * ab.y);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(view, RenderMode::kLightMap, kSize, kSize);
  const double l = centreLuminance(renderer, kSize);
  std::printf("the floor at x = -0.5 shows %.3f cd/m²: the dark half %.3f, the bright half %.3f\n", l, 50.0 * lobe,
              200.0 * lobe);
  // The dark half, blurred towards the wall beside it (100 cd/m²): the lobe is prefiltered from the probe's
  // centre, where the same angular width covers more of the room than from the floor point. Without the box
  // the lookup would meet the seam at x = 0.15 and show about half the bright ceiling.
  EXPECT_GT(l, 50.0 * lobe * 0.98);
  EXPECT_LT(l, 100.0 * lobe);
}

TEST(RoomProbe, OutdoorsThePolishedFloorStillReflectsTheSky) {
  context();
  constexpr float kSkyCdM2 = 5000.0f;
  const rdb::RasterRdb r = floorScene(true, 0.0f, kSkyCdM2);
  const View view = test::lookAtView(kEye, vec3(0.0f), 20.0f);
  const float cosO = 1.5f / std::sqrt(1.5f * 1.5f + 0.3f * 0.3f);
  const vec2 ab = test::splitSumByQuadrature(cosO, 0.09f, 1024, 256);
  const rdb::RasterMaterial& floor = r.materials.back();
  const double expected = kSkyCdM2 * luminance(floor.specular * ab.x + floor.environmentF90 * ab.y);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(view, RenderMode::kSunlight, kSize, kSize);
  const double l = centreLuminance(renderer, kSize);
  std::printf("open floor: %.3f cd/m² (the sky through the split sum: %.3f)\n", l, expected);
  EXPECT_NEAR(l / expected, 1.0, 0.03);
}

TEST(RoomProbe, CapturedAgainOnlyWhenTheEyeMovesOrTheSceneChanges) {
  context();
  const rdb::RasterRdb r = floorScene(false, 100.0f, 10000.0f);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(test::lookAtView(kEye, vec3(0.0f), 20.0f), RenderMode::kLightMap, 8, 8);
  renderer.render(test::lookAtView(kEye + vec3(0.2f, 0.0f, 0.0f), vec3(0.0f), 20.0f), RenderMode::kLightMap, 8, 8);
  EXPECT_EQ(renderer.stats().probeCaptures, 1);  // 0.2 m: within kRecaptureDistanceM
  renderer.render(test::lookAtView(kEye + vec3(0.3f, 0.0f, 0.0f), vec3(0.0f), 20.0f), RenderMode::kLightMap, 8, 8);
  EXPECT_EQ(renderer.stats().probeCaptures, 2);
  renderer.render(test::lookAtView(kEye + vec3(0.3f, 0.0f, 0.0f), vec3(0.0f), 20.0f), RenderMode::kSunlight, 8, 8);
  EXPECT_EQ(renderer.stats().probeCaptures, 3);  // another mode
  renderer.update(r, {.lights = true});
  renderer.render(test::lookAtView(kEye + vec3(0.3f, 0.0f, 0.0f), vec3(0.0f), 20.0f), RenderMode::kSunlight, 8, 8);
  EXPECT_EQ(renderer.stats().probeCaptures, 4);
  renderer.render(test::lookAtView(kEye, vec3(0.0f), 20.0f), RenderMode::kSimple, 8, 8);
  EXPECT_EQ(renderer.stats().probeCaptures, 4);  // simple mode has none
}

// A scene whose only reflecting surfaces are planar or cube reflectors (they show their own images) builds no
// probe and compiles no program with it.
TEST(RoomProbe, NoneWhereOnlyPlanarReflectorsReflect) {
  context();
  const rdb::RasterRdb r = floorScene(false, 100.0f, 10000.0f, true);
  ASSERT_FALSE(r.planarReflectors.empty());
  Renderer renderer;
  renderer.upload(r);
  for (const RenderMode mode : {RenderMode::kLightMap, RenderMode::kSunlight})
    renderer.render(test::lookAtView(kEye, vec3(0.0f), 20.0f), mode, 8, 8);
  EXPECT_EQ(renderer.stats().probeCaptures, 0);
  for (const std::string& p : renderer.stats().programs) EXPECT_EQ(p.find("+roomprobe"), std::string::npos) << p;
}

}  // namespace
}  // namespace fly::raster
