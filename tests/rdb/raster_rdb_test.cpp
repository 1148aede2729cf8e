#include "rdb/raster_rdb.h"

#include <gtest/gtest.h>

#include "../support/helsinki_daylight.h"
#include "test_meshes.h"

#include <cmath>
#include <cstring>
#include <functional>

#include <glm/gtc/matrix_transform.hpp>

#include "base/error.h"
#include "sdb/scene.h"

namespace fly::rdb {
namespace {

using sdb::Scene;
using test::quadXZ;
using test::quadYZ;

// A room corner: floor (normal +Y), wall x = 0 (normal +X) and wall z = 0 (normal +Z), each a separate mesh.
struct Corner {
  Scene scene;
  sdb::MaterialId paint, wood;
  sdb::NodeId floor, wallX, wallZ;
  sdb::LightId lamp;
  sdb::CameraId camera;
};

// `editFloor` changes the floor's mesh before it is added (texture coordinates, colours, tangents).
Corner corner(const std::function<void(sdb::Mesh&)>& editFloor = {}) {
  Corner c;
  sdb::Material paint;
  paint.name = "paint";
  paint.diffuseColor = Rgb(0.7f);
  c.paint = c.scene.addMaterial(paint).id;
  sdb::Material wood;
  wood.name = "wood";
  wood.diffuseColor = Rgb(0.4f, 0.25f, 0.1f);
  wood.reflectionColor = Rgb(1.0f);
  wood.reflectionGlossiness = 0.3f;
  c.wood = c.scene.addMaterial(wood).id;
  sdb::Mesh floor = quadXZ(c.wood);
  if (editFloor) editFloor(floor);
  c.floor = c.scene.addNode({.name = "floor", .meshes = {c.scene.addMesh(floor).id}}).id;
  c.wallX = c.scene.addNode({.name = "wallX", .meshes = {c.scene.addMesh(quadYZ(c.paint)).id}}).id;
  // Wall z = 0: the YZ quad turned −90° about +Y (x → z, z → −x), facing +Z, spanning x ∈ [0, 1].
  c.wallZ = c.scene
                .addNode({.name = "wallZ",
                          .parentFromLocal =
                              frameTransform(vec3(0, 0, 1), vec3(0, 1, 0), vec3(-1, 0, 0), vec3(1, 0, 0)),
                          .meshes = {c.scene.addMesh(quadYZ(c.paint)).id}})
                .id;
  sdb::Light lamp;
  lamp.type = sdb::LightType::kPoint;
  lamp.intensity = 100.0f;
  c.lamp = c.scene.addLight(lamp).id;
  c.scene.addNode(
      {.name = "lamp",
       .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0.5f, 0.8f, 0.5f)),
       .light = c.lamp});
  sdb::Camera cam;
  cam.name = "view";
  c.camera = c.scene.addCamera(cam).id;
  c.scene.addNode({.name = "eye",
                   .parentFromLocal = sdb::lookAtTransform(vec3(2, 1.5f, 2), vec3(0), vec3(0, 1, 0)),
                   .camera = c.camera});
  return c;
}

// The vertex of the RasterRdb at `p` in mesh `meshIndex`.
size_t vertexAt(const RasterRdb& r, size_t meshIndex, const vec3& p) {
  const RasterMesh& m = r.meshes.at(meshIndex);
  for (uint32_t v = m.firstVertex; v < m.firstVertex + m.vertexCount; ++v) {
    if (glm::length(r.positionsM[v] - p) < 1e-6f) return v;
  }
  ADD_FAILURE() << "no vertex at (" << p.x << ", " << p.y << ", " << p.z << ")";
  return 0;
}

TEST(RasterRdbCorners, CornerFactorIsTheSpreadOfTheFaceNormalsAtConcaveCorners) {
  Corner c = corner();
  const RasterRdb r = buildRasterRdb(c.scene);
  ASSERT_EQ(r.meshes.size(), 3u);
  // Three perpendicular faces: 1 − |(1,1,1)|/3 = 1 − 1/√3; two (an edge): 1 − 1/√2; one: 0.
  EXPECT_NEAR(r.cornerFactor[vertexAt(r, 0, vec3(0, 0, 0))], 1.0 - 1.0 / std::sqrt(3.0), 1e-6);
  EXPECT_NEAR(r.cornerFactor[vertexAt(r, 1, vec3(0, 0, 0))], 1.0 - 1.0 / std::sqrt(3.0), 1e-6);
  EXPECT_NEAR(r.cornerFactor[vertexAt(r, 0, vec3(0, 0, 1))], 1.0 - 1.0 / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(r.cornerFactor[vertexAt(r, 2, vec3(1, 0, 0))], 1.0 - 1.0 / std::sqrt(2.0), 1e-6);
  EXPECT_EQ(r.cornerFactor[vertexAt(r, 0, vec3(1, 0, 1))], 0.0f);
}

TEST(RasterRdbCorners, ConvexCornersGetNoAmbientRaise) {
  // The outside of a box: the floor quad and a wall facing away from it (−X) meet at a convex edge.
  Scene s;
  s.addNode({.name = "top", .meshes = {s.addMesh(quadXZ({})).id}});
  sdb::Mesh side = quadYZ({});
  side.positions = {{0, 0, 0}, {0, 0, 1}, {0, -1, 1}, {0, -1, 0}};
  side.normals.assign(4, vec3(-1, 0, 0));
  side.indices = {0, 1, 2, 0, 2, 3};
  s.addNode({.name = "side", .meshes = {s.addMesh(side).id}});
  const RasterRdb r = buildRasterRdb(s);
  for (float f : r.cornerFactor) EXPECT_EQ(f, 0.0f);
}

TEST(RasterRdbBuild, MaterialsLightsCamerasAndVariants) {
  Corner c = corner();
  const RasterRdb r = buildRasterRdb(c.scene);
  ASSERT_EQ(r.materials.size(), 3u);  // default, wood (first used), paint
  EXPECT_EQ(r.materials[1].sdbMaterialId, c.wood.value);
  EXPECT_EQ(r.materials[2].sdbMaterialId, c.paint.value);
  // Wood: white Fresnel reflection takes F0(1.5) = 4 % first (the energy rule), diffuse 0.96 · 0.4.
  EXPECT_NEAR(r.materials[1].diffuse.r, 0.96f * 0.4f, 1e-5f);
  EXPECT_NEAR(r.materials[1].specular.r, 0.04f, 1e-5f);
  // Glossiness 0.3: GGX α = 0.09.
  EXPECT_NEAR(r.materials[1].ggxAlpha, 0.09f, 1e-6f);
  ASSERT_EQ(r.lights.size(), 1u);
  EXPECT_EQ(r.lights[0].positionM, vec3(0.5f, 0.8f, 0.5f));
  ASSERT_EQ(r.cameras.size(), 1u);
  EXPECT_EQ(r.cameras[0].name, "view");
  EXPECT_FALSE(r.variants.sky);
  EXPECT_FALSE(r.variants.lightMap);
  EXPECT_FALSE(r.sky.has_value());
  // The corner's closure: each unit square sees the other two, each at the view factor of perpendicular
  // unit squares sharing an edge, 0.200044 (Hottel's crossed-strings result; Howell's catalogue of
  // configuration factors, C-14): c = 0.400088.
  ASSERT_TRUE(r.ambientClosure);
  EXPECT_NEAR(*r.ambientClosure, 0.400088, 0.01);
  // Progressive radiosity's ambient level ρ̄c/(1 − ρ̄c) · Ē, computed here independently: Ē over the three
  // unit quads with vertex weights area/3 per triangle, E = I · cos θ / d² from the 100 cd lamp; ρ̄ the mean
  // albedo.
  double eSum = 0.0, areaSum = 0.0;
  for (const RasterMesh& m : r.meshes) {
    for (uint32_t i = m.firstIndex; i < m.firstIndex + m.indexCount; i += 3) {
      const dvec3 p0(r.positionsM[r.indices[i]]), p1(r.positionsM[r.indices[i + 1]]),
          p2(r.positionsM[r.indices[i + 2]]);
      const double area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
      areaSum += area;
      for (const dvec3& p : {p0, p1, p2}) {
        const dvec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        const dvec3 d = dvec3(0.5, 0.8, 0.5) - p;
        eSum += area / 3.0 * 100.0 * std::max(0.0, glm::dot(n, d)) / std::pow(glm::length(d), 3.0);
      }
    }
  }
  const double rhoWood = luminance(Rgb(0.96f * 0.4f, 0.96f * 0.25f, 0.96f * 0.1f));
  const double rho = (rhoWood + 2.0 * 0.7) / 3.0;
  const double closure = r.ambientClosure.value_or(-1.0f);
  const double level = rho * closure / (1.0 - rho * closure) * eSum / areaSum;
  EXPECT_NEAR(r.ambient.upLux.r, level, 1e-4 * level);
  EXPECT_NEAR(r.ambient.downLux.g, level, 1e-4 * level);
}

// Emissive surfaces, which the simple mode's Phong does not shade with, add the part c of their flux that
// lands on the surfaces, spread over every surface, with its interreflections: Ē_e · c / (1 − ρ̄c) (the
// integrating-sphere formula where c = 1).
TEST(RasterRdbBuild, EmissiveSurfacesRaiseTheSimpleModesAmbientByTheirFlux) {
  Corner c = corner();
  const RasterRdb before = buildRasterRdb(c.scene);
  sdb::Material m = c.scene.material(c.wood);
  m.emissionLuminance = Rgb(50.0f);
  c.scene.setMaterial(c.wood, m);
  const RasterRdb r = buildRasterRdb(c.scene);
  // The one-sided 1 m² wooden floor emits π · 50 lm over the three unit quads; ρ̄ as above.
  const double rhoWood = luminance(Rgb(0.96f * 0.4f, 0.96f * 0.25f, 0.96f * 0.1f));
  const double rho = (rhoWood + 2.0 * 0.7) / 3.0;
  // Every face of the corner sees the other two alike (c = 0.400088, above), whichever sends the light.
  ASSERT_TRUE(before.ambientClosure && r.ambientClosure);
  EXPECT_NEAR(*r.ambientClosure, 0.400088, 0.01);
  const double cBefore = *before.ambientClosure, cAfter = *r.ambientClosure;
  // The lamp's term of `before` gives Ē; the level after is the emitter's term plus the lamp's at the closure
  // now (the flux that the closure's rays start from has moved to the floor).
  const double lampLux = before.ambient.upLux.g * (1.0 - rho * cBefore) / (rho * cBefore);
  const double expected = kPi * 50.0 / 3.0 * cAfter / (1.0 - rho * cAfter) + lampLux * rho * cAfter / (1.0 - rho * cAfter);
  EXPECT_NEAR(r.ambient.upLux.g, expected, 1e-4 * expected);
  EXPECT_NEAR(r.ambient.downLux.g, expected, 1e-4 * expected);
}

TEST(RasterRdbBuild, LightMapsAreMatchedByNodeAndMeshAndChecked) {
  Corner c = corner();
  RasterRdb plain = buildRasterRdb(c.scene);
  LightMapStore store;
  const RasterMesh& floor = plain.meshes[0];
  store.meshes.push_back({floor.sdbNodeId, floor.sdbMeshId, std::vector<Rgb>(4, Rgb(100.0f)), {}});
  const RasterRdb r = buildRasterRdb(c.scene, &store);
  EXPECT_TRUE(r.meshes[0].hasLightMap);
  EXPECT_FALSE(r.meshes[1].hasLightMap);
  EXPECT_TRUE(r.variants.lightMap);
  ASSERT_EQ(r.frontLux.size(), r.positionsM.size());
  EXPECT_TRUE(r.backLux.empty());
  EXPECT_EQ(r.frontLux[0], Rgb(100.0f));
  EXPECT_EQ(r.frontLux[4], Rgb(0.0f));
  store.meshes[0].frontLux.pop_back();
  EXPECT_THROW(buildRasterRdb(c.scene, &store), InputError);
}

// The floor (quadXZ: triangles (0,2,1), (0,3,2)) with a 2 × 3 light texture whose two triangles lie in
// separate charts: vertices 0 and 2 have a second UV and get seam copies.
LightMapStore floorLightTexture(const RasterRdb& plain) {
  LightMapStore store;
  const RasterMesh& floor = plain.meshes[0];
  MeshLightMap map{floor.sdbNodeId, floor.sdbMeshId, {Rgb(10), Rgb(11), Rgb(12), Rgb(13)}, {}, {}};
  MeshLightTexture t;
  t.width = 2;
  t.height = 3;
  for (int k = 0; k < 6; ++k) t.frontLux.push_back(Rgb(100.0f * float(k + 1)));
  t.cornerUv = {{0.1f, 0.1f}, {0.4f, 0.4f}, {0.4f, 0.1f}, {0.6f, 0.1f}, {0.6f, 0.4f}, {0.9f, 0.4f}};
  map.lightTexture = t;
  store.meshes.push_back(map);
  return store;
}

TEST(RasterRdbBuild, LightTexturedMeshesAreSplitAtSeams) {
  Corner c = corner();
  const RasterRdb plain = buildRasterRdb(c.scene);
  EXPECT_FALSE(plain.variants.lightTexture);
  EXPECT_TRUE(plain.lightMapUv.empty());
  LightMapStore store = floorLightTexture(plain);
  const RasterRdb r = buildRasterRdb(c.scene, &store);
  ASSERT_EQ(r.meshes.size(), 3u);
  const RasterMesh& floor = r.meshes[0];
  EXPECT_TRUE(r.variants.lightMap);
  EXPECT_TRUE(r.variants.lightTexture);
  ASSERT_EQ(floor.lightTexture, 0u);
  EXPECT_EQ(r.meshes[1].lightTexture, RasterMesh::kNoLightTexture);
  ASSERT_EQ(r.lightTextures.size(), 1u);
  EXPECT_EQ(r.lightTextures[0].width, 2u);
  EXPECT_EQ(r.lightTextures[0].height, 3u);
  EXPECT_EQ(r.lightTextures[0].frontLux, store.meshes[0].lightTexture->frontLux);
  EXPECT_TRUE(r.lightTextures[0].backLux.empty());
  // 4 SDB vertices, then copies of vertex 0 (UV (0.6, 0.1)) and vertex 2 (UV (0.9, 0.4)); the later meshes
  // move up by 2.
  ASSERT_EQ(floor.vertexCount, 6u);
  EXPECT_EQ(r.meshes[1].firstVertex, 6u);
  EXPECT_EQ(r.positionsM.size(), 6u + 4u + 4u);
  ASSERT_EQ(r.lightMapUv.size(), r.positionsM.size());
  const std::vector<uint32_t> expectedIndices = {0, 2, 1, 4, 3, 5};
  EXPECT_EQ(std::vector<uint32_t>(r.indices.begin(), r.indices.begin() + 6), expectedIndices);
  // Every corner reads its own UV; copies repeat their source's position, normal and vertex light value.
  for (size_t k = 0; k < 6; ++k)
    EXPECT_EQ(r.lightMapUv[r.indices[k]], store.meshes[0].lightTexture->cornerUv[k]) << "corner " << k;
  EXPECT_EQ(r.positionsM[4], r.positionsM[0]);
  EXPECT_EQ(r.positionsM[5], r.positionsM[2]);
  EXPECT_EQ(r.normals[5], r.normals[2]);
  EXPECT_EQ(r.frontLux[4], Rgb(10.0f));
  EXPECT_EQ(r.frontLux[5], Rgb(12.0f));
  EXPECT_EQ(r.cornerFactor[4], r.cornerFactor[0]);  // welded by position
  EXPECT_EQ(r.lightMapUv[6], vec2(0.0f));          // the wall has no light texture
  EXPECT_EQ(r.indices[6], 6u);

  // Corner UVs of another triangle count, or texels of another size: a bake of an edited scene.
  LightMapStore wrong = store;
  wrong.meshes[0].lightTexture->cornerUv.pop_back();
  EXPECT_THROW(buildRasterRdb(c.scene, &wrong), InputError);
  wrong = store;
  wrong.meshes[0].lightTexture->frontLux.pop_back();
  EXPECT_THROW(buildRasterRdb(c.scene, &wrong), InputError);
  wrong = store;
  wrong.meshes[0].lightTexture->cornerUv[0].x = std::nanf("");
  EXPECT_THROW(buildRasterRdb(c.scene, &wrong), InputError);
}

// update == rebuild, and only the named part is re-made.
void expectUpdateEqualsRebuild(Corner& c, const sdb::ChangeSet& changes, RasterRdb& before,
                               const LightMapStore* maps = nullptr) {
  updateRasterRdb(before, c.scene, changes, maps);
  EXPECT_TRUE(before == buildRasterRdb(c.scene, maps));
}

TEST(RasterRdbUpdate, MaterialEditReMakesOneBlock) {
  Corner c = corner();
  RasterRdb r = buildRasterRdb(c.scene);
  sdb::Material paint = c.scene.material(c.paint);
  paint.diffuseColor = Rgb(0.2f, 0.5f, 0.3f);
  const sdb::ChangeSet cs = c.scene.setMaterial(c.paint, paint);
  const RasterRdb old = r;
  const RasterRdbChanges ch = updateRasterRdb(r, c.scene, cs);
  EXPECT_FALSE(ch.geometry);
  EXPECT_FALSE(ch.materials);
  EXPECT_EQ(ch.materialBlocks, std::vector<uint32_t>{2});
  EXPECT_FALSE(ch.sky);
  EXPECT_FALSE(ch.lights);
  EXPECT_TRUE(ch.ambient);  // ρ̄ changed
  EXPECT_NE(r.materials[2], old.materials[2]);
  EXPECT_EQ(r.materials[1], old.materials[1]);
  EXPECT_TRUE(r == buildRasterRdb(c.scene));
}

// Glass lowers to its transmission, reflection and Fresnel F0, and calls for the glass pass: a frosted pane
// (transmission glossiness 0.5) with its transmission lobe's GGX α (0.25) and the frosted variant, clear glass
// (sdb::Material::hasClearTransmission) with α 0. Editing a material into glass re-makes its block and the
// variants, as a rebuild does.
TEST(RasterRdbUpdate, AMaterialEditedIntoGlassCallsForTheGlassPass) {
  Corner c = corner();
  RasterRdb r = buildRasterRdb(c.scene);
  EXPECT_FALSE(r.variants.glass);
  sdb::Material paint = c.scene.material(c.paint);
  paint.transmissionColor = Rgb(0.9f);
  paint.transmissionGlossiness = 0.5f;
  updateRasterRdb(r, c.scene, c.scene.setMaterial(c.paint, paint));
  EXPECT_TRUE(r.variants.glass);
  EXPECT_TRUE(r.variants.frostedGlass);
  EXPECT_EQ(r.materials[2].transmission, Rgb(0.9f));
  EXPECT_FLOAT_EQ(r.materials[2].transmissionAlpha, 0.25f);
  EXPECT_TRUE(r == buildRasterRdb(c.scene));
  paint.transmissionGlossiness = 0.0f;
  paint.reflectionColor = Rgb(1.0f);
  paint.ior = 1.5f;
  const RasterRdbChanges ch = updateRasterRdb(r, c.scene, c.scene.setMaterial(c.paint, paint));
  EXPECT_EQ(ch.materialBlocks, std::vector<uint32_t>{2});
  EXPECT_TRUE(r.variants.glass);
  EXPECT_FALSE(r.variants.frostedGlass);
  EXPECT_EQ(r.materials[2].transmission, Rgb(0.9f));
  EXPECT_EQ(r.materials[2].transmissionAlpha, 0.0f);
  EXPECT_EQ(r.materials[2].reflection, Rgb(1.0f));
  EXPECT_NEAR(r.materials[2].fresnelF0, 0.04f, 1e-6f);
  EXPECT_TRUE(r == buildRasterRdb(c.scene));
}

// The diffuse share towards the eye depends on the angle only where a material's reflection does (Fresnel:
// F90 ≠ F0): the corner's wood (Fresnel) turns the variant on; without its reflection, diffuse paint and a
// uniform reflection leave it off, a Fresnel reflection (ior 1.5) turns it on again, an edit as a rebuild does.
TEST(RasterRdbUpdate, AFresnelReflectionCallsForTheDiffuseShareByAngle) {
  Corner c = corner();
  RasterRdb r = buildRasterRdb(c.scene);
  EXPECT_TRUE(r.variants.diffuseByAngle);
  sdb::Material wood = c.scene.material(c.wood);
  wood.reflectionColor = Rgb(0.0f);
  updateRasterRdb(r, c.scene, c.scene.setMaterial(c.wood, wood));
  EXPECT_FALSE(r.variants.diffuseByAngle);
  sdb::Material paint = c.scene.material(c.paint);
  paint.reflectionColor = Rgb(0.5f);
  paint.reflectionModel = sdb::ReflectionModel::kUniform;
  updateRasterRdb(r, c.scene, c.scene.setMaterial(c.paint, paint));
  EXPECT_FALSE(r.variants.diffuseByAngle);
  paint.reflectionModel = sdb::ReflectionModel::kFresnel;
  paint.ior = 1.5f;
  updateRasterRdb(r, c.scene, c.scene.setMaterial(c.paint, paint));
  EXPECT_TRUE(r.variants.diffuseByAngle);
  EXPECT_TRUE(r == buildRasterRdb(c.scene));
}

TEST(RasterRdbUpdate, EachKindOfChangeEqualsARebuild) {
  Corner c = corner();
  RasterRdb r = buildRasterRdb(c.scene);
  {  // a light
    sdb::Light lamp = c.scene.light(c.lamp);
    lamp.color = Rgb(1.0f, 0.5f, 0.2f);
    expectUpdateEqualsRebuild(c, c.scene.setLight(c.lamp, lamp), r);
  }
  {  // a camera
    sdb::Camera cam = c.scene.camera(c.camera);
    cam.yfovRad = 1.0f;
    const sdb::ChangeSet cs = c.scene.setCamera(c.camera, cam);
    RasterRdb copy = r;
    const RasterRdbChanges ch = updateRasterRdb(copy, c.scene, cs);
    EXPECT_TRUE(ch.cameras);
    EXPECT_FALSE(ch.geometry || ch.materials || ch.lights || ch.sky);
    expectUpdateEqualsRebuild(c, cs, r);
  }
  {  // a mesh's material assignment re-makes the table
    const sdb::MeshId floorMesh = c.scene.node(c.floor).meshes[0];
    const sdb::ChangeSet cs = c.scene.setMeshMaterial(floorMesh, c.paint);
    RasterRdb copy = r;
    const RasterRdbChanges ch = updateRasterRdb(copy, c.scene, cs);
    EXPECT_TRUE(ch.materials);
    EXPECT_FALSE(ch.geometry);
    expectUpdateEqualsRebuild(c, cs, r);
    EXPECT_EQ(r.materials.size(), 2u);
  }
  {  // a node transform rebuilds the geometry
    const sdb::ChangeSet cs = c.scene.setNodeTransform(
        c.wallX, frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0.1f, 0, 0)));
    RasterRdb copy = r;
    EXPECT_TRUE(updateRasterRdb(copy, c.scene, cs).geometry);
    expectUpdateEqualsRebuild(c, cs, r);
  }
}

TEST(RasterRdbUpdate, LightTexturesSurviveUpdatesAsARebuild) {
  Corner c = corner();
  const LightMapStore store = floorLightTexture(buildRasterRdb(c.scene));
  RasterRdb r = buildRasterRdb(c.scene, &store);
  {  // a material edit keeps the split geometry
    sdb::Material paint = c.scene.material(c.paint);
    paint.diffuseColor = Rgb(0.3f);
    expectUpdateEqualsRebuild(c, c.scene.setMaterial(c.paint, paint), r, &store);
  }
  {  // a moved wall rebuilds it, split again
    const sdb::ChangeSet cs = c.scene.setNodeTransform(
        c.wallX, frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0.1f, 0, 0)));
    expectUpdateEqualsRebuild(c, cs, r, &store);
  }
  EXPECT_EQ(r.meshes[0].vertexCount, 6u);
  EXPECT_TRUE(r.variants.lightTexture);
}

// A textured room corner: the floor's material reads a 16-bit RGB base colour (2 × 1 texels) through a
// KHR_texture_transform and a 1-channel emission texture, both with UV set 0, and a grey + alpha normal map
// with UV set 1; the walls stay untextured. The floor's UVs: uv0 = (x, z), uv1 = (x, 1 − z).
struct TexturedCorner {
  Corner c;
  sdb::TextureId rgb16, grey, greyAlpha;
};

sdb::Texture texture(const std::string& name, int w, int h, int channels, int bits,
                     const std::vector<uint16_t>& values) {
  sdb::Texture t;
  t.name = name;
  t.sourcePath = "<embedded>";
  t.width = w;
  t.height = h;
  t.channels = channels;
  t.bitsPerChannel = bits;
  for (uint16_t v : values) {
    if (bits == 16) {
      uint8_t b[2];
      std::memcpy(b, &v, 2);  // native-endian pairs (sdb/texture.h)
      t.pixels.insert(t.pixels.end(), b, b + 2);
    } else {
      t.pixels.push_back(uint8_t(v));
    }
  }
  return t;
}

void floorUvs(sdb::Mesh& m) {
  for (const vec3& p : m.positions) {
    m.uv0.push_back(vec2(p.x, p.z));
    m.uv1.push_back(vec2(p.x, 1.0f - p.z));
  }
}

TexturedCorner texturedCorner(const std::function<void(sdb::Mesh&)>& editFloor = floorUvs) {
  TexturedCorner t{corner(editFloor), {}, {}, {}};
  Scene& s = t.c.scene;
  t.rgb16 = s.addTexture(texture("base", 2, 1, 3, 16, {65535, 0, 32768, 257, 65534, 128})).id;
  t.grey = s.addTexture(texture("glow", 1, 1, 1, 8, {200})).id;
  t.greyAlpha = s.addTexture(texture("bumps", 1, 2, 2, 8, {128, 10, 255, 20})).id;
  sdb::Material wood = s.material(t.c.wood);
  wood.diffuseTexture.texture = t.rgb16;
  wood.diffuseTexture.transform = {vec2(0.0f, 1.0f), float(kPi / 2.0), vec2(0.5f)};
  wood.emissionTexture.texture = t.grey;
  wood.emissionLuminance = Rgb(10.0f);
  wood.bumpTexture.texture = t.greyAlpha;
  wood.bumpTexture.texCoord = 1;
  wood.bumpScale = 0.5f;
  s.setMaterial(t.c.wood, wood);
  return t;
}

// uv' of a RasterTextureRef's transform.
vec2 transformed(const RasterTextureRef& r, const vec2& uv) {
  return vec2(glm::dot(vec2(r.uvRow0), uv) + r.uvRow0.z, glm::dot(vec2(r.uvRow1), uv) + r.uvRow1.z);
}

TEST(RasterRdbTextures, TexturesAreRgba8InTheirSlotsEncodingWithTransformsAndUvSets) {
  TexturedCorner t = texturedCorner();
  const RasterRdb r = buildRasterRdb(t.c.scene);
  ASSERT_EQ(r.textures.size(), 3u);  // first use: base colour, emission, normal map
  EXPECT_EQ(r.textures[0].sdbTextureId, t.rgb16.value);
  EXPECT_TRUE(r.textures[0].srgb);
  EXPECT_EQ(r.textures[0].width, 2u);
  EXPECT_EQ(r.textures[0].height, 1u);
  // round(v · 255 / 65535): 65535 → 255, 0 → 0, 32768 → 128 (127.50…), 257 → 1, 65534 → 255, 128 → 0.
  EXPECT_EQ(r.textures[0].rgba8, (std::vector<uint8_t>{255, 0, 128, 255, 1, 255, 0, 255}));
  EXPECT_TRUE(r.textures[1].srgb);
  EXPECT_EQ(r.textures[1].rgba8, (std::vector<uint8_t>{200, 200, 200, 255}));
  EXPECT_FALSE(r.textures[2].srgb);  // a normal map is linear
  EXPECT_EQ(r.textures[2].rgba8, (std::vector<uint8_t>{128, 128, 128, 10, 255, 255, 255, 20}));

  const RasterMaterial& wood = r.materials[1];
  EXPECT_EQ(wood.baseColorTexture.texture, 0u);
  EXPECT_EQ(wood.emissionTexture.texture, 1u);
  EXPECT_EQ(wood.normalTexture.texture, 2u);
  EXPECT_EQ(wood.normalTexture.texCoord, 1u);
  EXPECT_EQ(wood.normalScale, 0.5f);
  EXPECT_FALSE(r.materials[2].hasTexture());
  // The extension's example: offset (0, 1), rotation 90°, scale 0.5 shows the lower left quadrant of the
  // image turned 90° clockwise: (0,0) → (0,1), (1,0) → (0,0.5), (0,1) → (0.5,1), (1,1) → (0.5,0.5).
  const std::pair<vec2, vec2> corners[] = {
      {{0, 0}, {0, 1}}, {{1, 0}, {0, 0.5f}}, {{0, 1}, {0.5f, 1}}, {{1, 1}, {0.5f, 0.5f}}};
  for (const auto& [uv, expected] : corners) {
    const vec2 got = transformed(wood.baseColorTexture, uv);
    EXPECT_NEAR(got.x, expected.x, 1e-6f);
    EXPECT_NEAR(got.y, expected.y, 1e-6f);
  }
  EXPECT_EQ(transformed(wood.emissionTexture, vec2(0.3f, 0.7f)), vec2(0.3f, 0.7f));  // identity

  EXPECT_TRUE(r.variants.textures);
  EXPECT_TRUE(r.variants.normalMaps);
  EXPECT_TRUE(r.variants.uv1);
  EXPECT_FALSE(r.variants.vertexColors);
  EXPECT_FALSE(r.variants.alphaMask || r.variants.alphaBlend);
  // Per-vertex attributes: the floor's, zeros for the walls (which read none).
  ASSERT_EQ(r.uv0.size(), r.positionsM.size());
  ASSERT_EQ(r.uv1.size(), r.positionsM.size());
  ASSERT_EQ(r.tangents.size(), r.positionsM.size());
  EXPECT_TRUE(r.colors.empty());
  const RasterMesh& floor = r.meshes[0];
  EXPECT_TRUE(r.shadedPerFragment(floor));
  EXPECT_FALSE(r.shadedPerFragment(r.meshes[1]));
  for (uint32_t v = floor.firstVertex; v < floor.firstVertex + floor.vertexCount; ++v) {
    EXPECT_EQ(r.uv0[v], vec2(r.positionsM[v].x, r.positionsM[v].z));
    EXPECT_EQ(r.uv1[v], vec2(r.positionsM[v].x, 1.0f - r.positionsM[v].z));
  }
  EXPECT_EQ(r.uv0[r.meshes[1].firstVertex], vec2(0.0f));
}

// Generated tangents (Lengyel's method) on the floor (normal +Y): u grows along +X, so the tangent is +X; the
// image's up (−v) is +Z for uv1 = (x, 1 − z), against cross(+Y, +X) = −Z: w = −1; with v = z instead, −v is
// −Z: w = +1. A file's tangents are taken as given, and a mirroring node flips their w.
TEST(RasterRdbTextures, TangentsFromTheFileOrGeneratedFromTheNormalMapsUvSet) {
  TexturedCorner t = texturedCorner();
  RasterRdb r = buildRasterRdb(t.c.scene);
  const RasterMesh& floor = r.meshes[0];
  for (uint32_t v = floor.firstVertex; v < floor.firstVertex + floor.vertexCount; ++v) {
    EXPECT_NEAR(glm::length(vec3(r.tangents[v]) - vec3(1, 0, 0)), 0.0f, 1e-6f);
    EXPECT_EQ(r.tangents[v].w, -1.0f);
  }
  sdb::Material wood = t.c.scene.material(t.c.wood);
  wood.bumpTexture.texCoord = 0;  // uv0 = (x, z)
  t.c.scene.setMaterial(t.c.wood, wood);
  r = buildRasterRdb(t.c.scene);
  EXPECT_TRUE(r.uv1.empty());
  EXPECT_NEAR(glm::length(vec3(r.tangents[0]) - vec3(1, 0, 0)), 0.0f, 1e-6f);
  EXPECT_EQ(r.tangents[0].w, 1.0f);

  TexturedCorner withTangents = texturedCorner([](sdb::Mesh& m) {
    floorUvs(m);
    m.tangents.assign(m.positions.size(), vec4(0, 0, 1, 1));
  });
  r = buildRasterRdb(withTangents.c.scene);
  EXPECT_EQ(r.tangents[0], vec4(0, 0, 1, 1));
  withTangents.c.scene.setNodeTransform(withTangents.c.floor,
                                        glm::scale(mat4(1.0f), vec3(-1, 1, 1)));  // mirrored in x
  r = buildRasterRdb(withTangents.c.scene);
  EXPECT_EQ(r.tangents[0], vec4(0, 0, 1, -1));
}

// An anisotropic material's meshes carry the tangent frame (of the UV set its anisotropy textures read, else
// UV set 0) and are shaded per fragment; a scene without one carries no tangents and calls for no variant.
TEST(RasterRdbTextures, AnisotropicMaterialsCarryTangentsAndAreShadedPerFragment) {
  Corner c = corner(floorUvs);
  RasterRdb r = buildRasterRdb(c.scene);
  EXPECT_FALSE(r.variants.anisotropy);
  EXPECT_TRUE(r.tangents.empty());
  EXPECT_FALSE(r.shadedPerFragment(r.meshes[0]));

  sdb::Material wood = c.scene.material(c.wood);
  wood.anisotropyU = 0.6f;
  wood.anisotropyV = 0.1f;
  wood.anisotropyRotationRad = 0.5f;
  sdb::ChangeSet changes = c.scene.setMaterial(c.wood, wood);
  RasterRdb updated = r;
  updateRasterRdb(updated, c.scene, changes);
  r = buildRasterRdb(c.scene);
  EXPECT_EQ(updated, r);
  EXPECT_TRUE(r.variants.anisotropy);
  EXPECT_FALSE(r.variants.textures);
  const RasterMaterial& m = r.materials[r.meshes[0].material];
  EXPECT_TRUE(m.anisotropic);
  EXPECT_EQ(m.anisotropyU, 0.6f);
  EXPECT_EQ(m.anisotropyV, 0.1f);
  EXPECT_EQ(m.anisotropyRotationRad, 0.5f);
  EXPECT_FALSE(m.anisotropyTexture || m.anisotropyRotationTexture);
  EXPECT_FALSE(r.materials[r.meshes[1].material].anisotropic);
  ASSERT_EQ(r.tangents.size(), r.positionsM.size());
  const RasterMesh& floor = r.meshes[0];
  for (uint32_t v = floor.firstVertex; v < floor.firstVertex + floor.vertexCount; ++v)
    EXPECT_NEAR(glm::length(vec3(r.tangents[v]) - vec3(1, 0, 0)), 0.0f, 1e-6f);  // +u of uv0 = (x, z)
  EXPECT_TRUE(r.shadedPerFragment(floor));
  EXPECT_FALSE(r.shadedPerFragment(r.meshes[1]));  // the paint

  // A rotation texture read with UV set 1 (u = x, v = 1 − z): the tangents follow that set.
  const sdb::TextureId grey = c.scene.addTexture(texture("rotation", 1, 1, 1, 8, {64})).id;
  wood.anisotropyRotationTexture.texture = grey;
  wood.anisotropyRotationTexture.texCoord = 1;
  c.scene.setMaterial(c.wood, wood);
  r = buildRasterRdb(c.scene);
  EXPECT_TRUE(r.variants.textures && r.variants.uv1 && r.variants.anisotropy);
  ASSERT_EQ(r.textures.size(), 1u);
  EXPECT_FALSE(r.textures[0].srgb);
  EXPECT_EQ(r.materials[r.meshes[0].material].anisotropyRotationTexture.texCoord, 1u);
  EXPECT_NEAR(glm::length(vec3(r.tangents[0]) - vec3(1, 0, 0)), 0.0f, 1e-6f);
  EXPECT_EQ(r.tangents[0].w, -1.0f);  // ∂p/∂(−v) = +z, against n × t = −z

  // Equal U and V without a texture: isotropic, nothing carried.
  wood.anisotropyRotationTexture = {};
  wood.anisotropyV = wood.anisotropyU;
  c.scene.setMaterial(c.wood, wood);
  r = buildRasterRdb(c.scene);
  EXPECT_FALSE(r.variants.anisotropy);
  EXPECT_TRUE(r.tangents.empty());

  // Anisotropic glass is shaded as glass (per vertex, in its own pass): no anisotropy in the engine.
  wood.anisotropyV = 0.0f;
  wood.transmissionColor = Rgb(0.9f);
  wood.diffuseColor = Rgb(0.0f);
  c.scene.setMaterial(c.wood, wood);
  r = buildRasterRdb(c.scene);
  EXPECT_FALSE(r.variants.anisotropy);
  EXPECT_FALSE(r.materials[r.meshes[0].material].anisotropic);
}

// A glossiness texture (linear; read with its UV set and KHR_texture_transform) of a material that reflects is
// carried and its meshes are shaded per fragment, without tangents; an edit that adds it equals a rebuild. A
// material that reflects nothing, glass and a scene without one carry none and call for no variant.
TEST(RasterRdbTextures, GlossinessTexturesOfReflectingMaterialsAreShadedPerFragment) {
  Corner c = corner(floorUvs);
  RasterRdb r = buildRasterRdb(c.scene);
  EXPECT_FALSE(r.variants.glossinessTextures);

  sdb::Material wood = c.scene.material(c.wood);
  wood.reflectionGlossinessTexture.texture = c.scene.addTexture(texture("roughness", 2, 1, 1, 8, {51, 204})).id;
  wood.reflectionGlossinessTexture.texCoord = 1;
  wood.reflectionGlossinessTexture.transform = {vec2(0.0f, 1.0f), float(kPi / 2.0), vec2(0.5f)};
  const sdb::ChangeSet changes = c.scene.setMaterial(c.wood, wood);
  RasterRdb updated = r;
  updateRasterRdb(updated, c.scene, changes);
  r = buildRasterRdb(c.scene);
  EXPECT_EQ(updated, r);
  EXPECT_TRUE(r.variants.glossinessTextures && r.variants.textures && r.variants.uv1);
  EXPECT_FALSE(r.variants.anisotropy || r.variants.normalMaps);
  EXPECT_TRUE(r.tangents.empty());
  ASSERT_EQ(r.textures.size(), 1u);
  EXPECT_FALSE(r.textures[0].srgb);
  EXPECT_EQ(r.textures[0].rgba8, (std::vector<uint8_t>{51, 51, 51, 255, 204, 204, 204, 255}));
  const RasterMaterial& m = r.materials[r.meshes[0].material];
  EXPECT_EQ(m.glossinessTexture.texture, 0u);
  EXPECT_EQ(m.glossinessTexture.texCoord, 1u);
  EXPECT_NEAR(m.ggxAlpha, 0.09f, 1e-7f);  // the factor's α; the texel's red² multiplies it per pixel
  const vec2 corner = transformed(m.glossinessTexture, vec2(1.0f, 0.0f));  // the extension's (1,0) → (0,0.5)
  EXPECT_NEAR(corner.x, 0.0f, 1e-6f);
  EXPECT_NEAR(corner.y, 0.5f, 1e-6f);
  EXPECT_TRUE(r.shadedPerFragment(r.meshes[0]));
  EXPECT_FALSE(r.shadedPerFragment(r.meshes[1]));  // the paint

  // Reflecting nothing, or glass: the width shows nowhere (glass reads no textures).
  for (const bool glass : {false, true}) {
    sdb::Material other = wood;
    if (glass) {
      other.transmissionColor = Rgb(0.9f);
      other.diffuseColor = Rgb(0.0f);
    } else {
      other.reflectionColor = Rgb(0.0f);
    }
    c.scene.setMaterial(c.wood, other);
    r = buildRasterRdb(c.scene);
    EXPECT_FALSE(r.variants.glossinessTextures) << glass;
    EXPECT_FALSE(r.materials[r.meshes[0].material].glossinessTexture) << glass;
    EXPECT_TRUE(r.textures.empty()) << glass;
  }
}

TEST(RasterRdbTextures, VertexColorsAndAlphaModes) {
  Corner c = corner([](sdb::Mesh& m) { m.colors = {{1, 0, 0, 1}, {0, 1, 0, 0.5f}, {0, 0, 1, 1}, {1, 1, 1, 0}}; });
  sdb::Material paint = c.scene.material(c.paint);
  paint.alphaMode = sdb::AlphaMode::kMask;
  paint.alphaCutoff = 0.25f;
  paint.opacity = 0.75f;
  c.scene.setMaterial(c.paint, paint);
  const RasterRdb r = buildRasterRdb(c.scene);
  EXPECT_TRUE(r.variants.vertexColors);
  EXPECT_TRUE(r.variants.alphaMask);
  EXPECT_FALSE(r.variants.alphaBlend);
  EXPECT_FALSE(r.variants.textures);
  EXPECT_TRUE(r.uv0.empty());
  ASSERT_EQ(r.colors.size(), r.positionsM.size());
  EXPECT_TRUE(r.meshes[0].hasColors);
  EXPECT_FALSE(r.meshes[1].hasColors);
  EXPECT_EQ(r.colors[1], vec4(0, 1, 0, 0.5f));
  EXPECT_EQ(r.colors[r.meshes[1].firstVertex], vec4(1.0f));  // white where a mesh has none
  EXPECT_EQ(r.materials[2].alphaMode, RasterAlphaMode::kMask);
  EXPECT_EQ(r.materials[2].alphaCutoff, 0.25f);
  EXPECT_EQ(r.materials[2].opacity, 0.75f);
  EXPECT_TRUE(r.shadedPerFragment(r.meshes[0]));  // COLOR_0
  EXPECT_TRUE(r.shadedPerFragment(r.meshes[1]));  // the cut-out paint
}

// A factor edit of a textured material re-makes its block; other textures, UV sets or alpha modes rebuild,
// and every update equals a rebuild.
TEST(RasterRdbUpdate, TexturedMaterialEditsEqualARebuild) {
  TexturedCorner t = texturedCorner();
  RasterRdb r = buildRasterRdb(t.c.scene);
  sdb::Material wood = t.c.scene.material(t.c.wood);
  wood.diffuseColor = Rgb(0.9f, 0.5f, 0.1f);
  wood.diffuseTexture.transform.offset = vec2(0.25f, 0.0f);
  RasterRdbChanges ch = updateRasterRdb(r, t.c.scene, t.c.scene.setMaterial(t.c.wood, wood));
  EXPECT_FALSE(ch.geometry);
  EXPECT_EQ(ch.materialBlocks, std::vector<uint32_t>{1});
  EXPECT_TRUE(r == buildRasterRdb(t.c.scene));

  // Another sampler (the engine binds one per draw from the block): the block only.
  wood.diffuseTexture.wrapS = sdb::WrapMode::kClampToEdge;
  wood.diffuseTexture.wrapT = sdb::WrapMode::kMirroredRepeat;
  wood.diffuseTexture.magFilter = sdb::MagFilter::kNearest;
  wood.diffuseTexture.minFilter = sdb::MinFilter::kLinearMipmapNearest;
  ch = updateRasterRdb(r, t.c.scene, t.c.scene.setMaterial(t.c.wood, wood));
  EXPECT_FALSE(ch.geometry);
  EXPECT_EQ(ch.materialBlocks, std::vector<uint32_t>{1});
  EXPECT_EQ(r.materials[1].baseColorTexture.wrapS, RasterWrap::kClampToEdge);
  EXPECT_EQ(r.materials[1].baseColorTexture.wrapT, RasterWrap::kMirroredRepeat);
  EXPECT_EQ(r.materials[1].baseColorTexture.magFilter, RasterMagFilter::kNearest);
  EXPECT_EQ(r.materials[1].baseColorTexture.minFilter, RasterMinFilter::kLinearMipmapNearest);
  EXPECT_EQ(r.materials[1].emissionTexture.wrapS, RasterWrap::kRepeat);
  EXPECT_EQ(r.materials[1].emissionTexture.minFilter, RasterMinFilter::kLinearMipmapLinear);
  EXPECT_TRUE(r == buildRasterRdb(t.c.scene));

  wood.emissionTexture = {};  // one texture fewer: the table shrinks
  ch = updateRasterRdb(r, t.c.scene, t.c.scene.setMaterial(t.c.wood, wood));
  EXPECT_TRUE(ch.geometry);
  EXPECT_EQ(r.textures.size(), 2u);
  EXPECT_TRUE(r == buildRasterRdb(t.c.scene));

  sdb::Material paint = t.c.scene.material(t.c.paint);
  paint.diffuseTexture.texture = t.grey;  // the walls gain a texture: their uv0 appear
  ch = updateRasterRdb(r, t.c.scene, t.c.scene.setMaterial(t.c.paint, paint));
  EXPECT_TRUE(ch.geometry);
  EXPECT_TRUE(r == buildRasterRdb(t.c.scene));

  paint.alphaMode = sdb::AlphaMode::kBlend;
  ch = updateRasterRdb(r, t.c.scene, t.c.scene.setMaterial(t.c.paint, paint));
  EXPECT_TRUE(ch.geometry);
  EXPECT_TRUE(r.variants.alphaBlend);
  EXPECT_TRUE(r == buildRasterRdb(t.c.scene));

  paint.opacity = 0.3f;  // coverage within the same mode: the block only
  ch = updateRasterRdb(r, t.c.scene, t.c.scene.setMaterial(t.c.paint, paint));
  EXPECT_FALSE(ch.geometry);
  EXPECT_TRUE(r == buildRasterRdb(t.c.scene));

  const sdb::MeshId floorMesh = t.c.scene.node(t.c.floor).meshes[0];
  expectUpdateEqualsRebuild(t.c, t.c.scene.setMeshMaterial(floorMesh, t.c.paint), r);
}

// A new time of day re-makes the sky (dawn and noon differ) and nothing else.
TEST(RasterRdbUpdate, TimeOfDayReMakesOnlyTheSky) {
  Corner c = corner();
  fly::test::setHelsinkiClearSky(c.scene, "2026-06-21T12:00");
  RasterRdb r = buildRasterRdb(c.scene);
  ASSERT_TRUE(r.sky.has_value());
  EXPECT_TRUE(r.variants.sky);
  EXPECT_TRUE(r.variants.sun);
  EXPECT_GT(luminance(r.daylightAmbient.upLux), 1000.0f);
  const RasterRdb noon = r;
  const sdb::ChangeSet cs = c.scene.setTime({"2026-06-21T05:00"});
  const RasterRdbChanges ch = updateRasterRdb(r, c.scene, cs);
  EXPECT_TRUE(ch.sky);
  EXPECT_FALSE(ch.geometry || ch.materials || !ch.materialBlocks.empty() || ch.lights || ch.cameras);
  EXPECT_TRUE(r == buildRasterRdb(c.scene));
  ASSERT_TRUE(r.sky.has_value());
  EXPECT_TRUE(r.sky->radianceCdM2 != noon.sky->radianceCdM2);
  EXPECT_NE(r.sky->sunDirWorld, noon.sky->sunDirWorld);
  EXPECT_LT(luminance(r.daylightAmbient.upLux), luminance(noon.daylightAmbient.upLux));
  EXPECT_EQ(r.positionsM, noon.positionsM);
}

}  // namespace
}  // namespace fly::rdb

namespace fly::rdb {
namespace {

// A point light's range window is KHR_lights_punctual's recommended clamp(1 − (d/range)⁴, 0, 1) / d², as the
// baker applies it (raytracer/integrator.cpp): at half the range 15/16 of the inverse-square value, nothing
// at and beyond the range.
TEST(RasterRdbLights, RangeWindowAsKhrLightsPunctualRecommends) {
  RasterLight l;
  l.type = RasterLightType::kPoint;
  l.positionM = vec3(0.0f);
  l.intensity = Rgb(100.0f);
  l.rangeM = 8.0f;
  const RasterRdb rdb;
  vec3 toLight;
  EXPECT_NEAR(punctualIlluminanceLux(rdb, l, vec3(4.0f, 0.0f, 0.0f), toLight).g, 100.0f / 16.0f * 15.0f / 16.0f, 1e-4f);
  EXPECT_NEAR(toLight.x, -1.0f, 1e-6f);
  EXPECT_EQ(punctualIlluminanceLux(rdb, l, vec3(0.0f, 8.0f, 0.0f), toLight).g, 0.0f);
  EXPECT_EQ(punctualIlluminanceLux(rdb, l, vec3(0.0f, 9.0f, 0.0f), toLight).g, 0.0f);
}

}  // namespace
}  // namespace fly::rdb
