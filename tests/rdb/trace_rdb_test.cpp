#include "rdb/trace_rdb_build.h"

#include <gtest/gtest.h>

#include "test_meshes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "base/error.h"
#include "base/log.h"
#include "rdb/site_lowering.h"
#include "sdb/material_presets.h"
#include "sdb/scene_load.h"
#include "sunsky/cie_sky.h"
#include "sunsky/clear_sky.h"
#include "sunsky/civil_time.h"
#include "sunsky/perez_sky.h"
#include "sunsky/sun_position.h"

namespace fly::rdb {
namespace {

using sdb::Scene;
using test::quadXZ;
using test::quadYZ;

void expectVec(const vec3& actual, const vec3& expected, float tolerance = 1e-6f) {
  EXPECT_NEAR(actual.x, expected.x, tolerance) << "expected (" << expected.x << ", " << expected.y << ", " << expected.z << ")";
  EXPECT_NEAR(actual.y, expected.y, tolerance) << "expected (" << expected.x << ", " << expected.y << ", " << expected.z << ")";
  EXPECT_NEAR(actual.z, expected.z, tolerance) << "expected (" << expected.x << ", " << expected.y << ", " << expected.z << ")";
}

TEST(TraceRdbGeometry, FlattensPlacedMeshesIntoWorldSpace) {
  Scene s;
  const sdb::MeshId a = s.addMesh(quadXZ({})).id;
  // Quad B in the local XY plane with slanted normals (1, 0, 1)/√2, and a third triangle of zero area.
  sdb::Mesh bMesh;
  bMesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  bMesh.normals.assign(4, glm::normalize(vec3(1, 0, 1)));
  bMesh.indices = {0, 1, 2, 0, 2, 3, 1, 1, 2};
  const sdb::MeshId b = s.addMesh(bMesh).id;

  // Node 1: translate (1, 2, 3) · rotate +90° about +Y (x → −z, z → +x) · scale 2, written with exact axes.
  const mat4 n1 = frameTransform(vec3(0, 0, -2), vec3(0, 2, 0), vec3(2, 0, 0), vec3(1, 2, 3));
  const sdb::NodeId node1 = s.addNode({.name = "rotated", .parentFromLocal = n1, .meshes = {a}}).id;
  // Node 2: translate (0, 0, 5) · scale (−1, 2, 1), a mirror.
  const mat4 n2 = frameTransform(vec3(-1, 0, 0), vec3(0, 2, 0), vec3(0, 0, 1), vec3(0, 0, 5));
  s.addNode({.name = "mirrored", .parentFromLocal = n2, .meshes = {b}});
  // Node 3, a child of node 1, moved by local +Z: world = node 1 · translate (0, 0, 1), holding quad A again.
  s.addNode({.name = "child", .parent = node1,
             .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 0, 1)),
             .meshes = {a}});

  const TraceRdb r = buildTraceRdb(s);
  ASSERT_EQ(r.meshes.size(), 3u);
  ASSERT_EQ(r.positionsM.size(), 12u);
  ASSERT_EQ(r.normals.size(), 12u);
  EXPECT_EQ(r.skippedTriangles, 1u);
  EXPECT_EQ(r.triangleCount(), 6u);
  EXPECT_EQ(r.triangleMaterial.size(), 6u);

  // Node 1: (a, 0, c) → (1 + 2c, 2, 3 − 2a); normals stay +Y.
  const vec3 expectA[4] = {{1, 2, 3}, {1, 2, 1}, {3, 2, 1}, {3, 2, 3}};
  for (int i = 0; i < 4; ++i) {
    expectVec(r.positionsM[size_t(i)], expectA[i]);
    expectVec(r.normals[size_t(i)], vec3(0, 1, 0));
  }
  EXPECT_EQ(r.meshes[0].sdbMeshId, a.value);
  EXPECT_EQ(r.meshes[0].sdbNodeId, node1.value);
  EXPECT_EQ(r.meshes[0].firstVertex, 0u);
  EXPECT_EQ(r.meshes[0].triangleCount, 2u);
  const uint32_t firstIndices[6] = {0, 2, 1, 0, 3, 2};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(r.indices[size_t(i)], firstIndices[i]);

  // The child (visited right after its parent): node 1's (a, 0, c + 1) → (3 + 2c, 2, 3 − 2a).
  EXPECT_EQ(r.meshes[1].sdbMeshId, a.value);
  EXPECT_EQ(r.meshes[1].firstVertex, 4u);
  EXPECT_EQ(r.meshes[1].firstTriangle, 2u);
  const vec3 expectChild[4] = {{3, 2, 3}, {3, 2, 1}, {5, 2, 1}, {5, 2, 3}};
  for (int i = 0; i < 4; ++i) expectVec(r.positionsM[size_t(4 + i)], expectChild[i]);
  EXPECT_EQ(r.indices[6], 4u);

  // Node 2: (x, y, z) → (−x, 2y, z + 5); the normal (1, 0, 1)/√2 by the inverse transpose diag(−1, ½, 1) is
  // (−1, 0, 1)/√2. Quad B keeps its two triangles; the zero-area one is left out.
  const vec3 expectB[4] = {{0, 0, 5}, {-1, 0, 5}, {-1, 2, 5}, {0, 2, 5}};
  for (int i = 0; i < 4; ++i) {
    expectVec(r.positionsM[size_t(8 + i)], expectB[i]);
    expectVec(r.normals[size_t(8 + i)], glm::normalize(vec3(-1, 0, 1)));
  }
  EXPECT_EQ(r.meshes[2].vertexCount, 4u);
  EXPECT_EQ(r.meshes[2].triangleCount, 2u);

  expectVec(r.boundsM.min, vec3(-1, 0, 1));
  expectVec(r.boundsM.max, vec3(5, 2, 5));
}

TEST(TraceRdbGeometry, MissingOrDegenerateNormalsBecomeTheFaceNormal) {
  Scene s;
  sdb::Mesh m;
  m.positions = {{0, 0, 0}, {0, 0, 2}, {0, 3, 0}, {5, 5, 5}};  // vertex 3 belongs to no triangle with area
  m.indices = {0, 1, 2, 3, 3, 3};
  s.addNode({.meshes = {s.addMesh(m).id}});
  m.normals = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}};  // a zero normal at vertex 0
  s.addNode({.meshes = {s.addMesh(m).id}});

  const TraceRdb r = buildTraceRdb(s);
  EXPECT_EQ(r.skippedTriangles, 2u);
  // (0,0,2) × (0,3,0) = (−6, 0, 0): the face faces −X.
  for (int i = 0; i < 3; ++i) expectVec(r.normals[size_t(i)], vec3(-1, 0, 0));
  expectVec(r.normals[3], vec3(0, 1, 0));
  expectVec(r.normals[4], vec3(-1, 0, 0));
  expectVec(r.normals[5], vec3(1, 0, 0));
}

TEST(TraceRdbMaterials, FollowTheEnergyRuleAndListEmitters) {
  Scene s;
  const sdb::MaterialId glass = s.addMaterial(sdb::findMaterialPreset("clear-glass")->material).id;
  sdb::Material lamp;
  lamp.name = "lamp";
  lamp.emissionLuminance = Rgb(100.0f, 50.0f, 25.0f);
  lamp.doubleSided = true;
  const sdb::MaterialId emitter = s.addMaterial(lamp).id;
  s.addMaterial(lamp);  // unused: not lowered
  sdb::Mesh paint = quadXZ({});
  paint.positions[0].y = 0.25f;  // not planar, still two triangles
  s.addNode({.meshes = {s.addMesh(quadXZ(glass)).id, s.addMesh(quadXZ(emitter)).id, s.addMesh(paint).id}});

  const TraceRdb r = buildTraceRdb(s);
  ASSERT_EQ(r.materials.size(), 3u);  // default, glass, emitter
  EXPECT_EQ(r.materials[0].sdbMaterialId, 0u);
  expectVec(r.materials[0].diffuse, Rgb(0.8f));  // the default: no reflection colour, so all diffuse

  const TraceMaterial& g = r.materials[1];
  EXPECT_EQ(g.sdbMaterialId, glass.value);
  expectVec(g.diffuse, Rgb(0.0f));
  expectVec(g.transmission, Rgb(1.0f));
  expectVec(g.reflection, Rgb(1.0f));
  EXPECT_TRUE(g.fresnel);
  EXPECT_FLOAT_EQ(g.ior, 1.52f);
  EXPECT_TRUE(g.doubleSided);
  expectVec(g.emissionCdM2, Rgb(0.0f));

  // A white Fresnel dielectric: diffuse' = (1 − F0)·diffuse at normal incidence, F0 = ((1.5 − 1)/(1.5 + 1))².
  sdb::Material plastic;
  plastic.diffuseColor = Rgb(0.5f);
  plastic.reflectionColor = Rgb(1.0f);
  expectVec(lowerMaterial(plastic, 7).diffuse, Rgb(0.5f * (1.0f - 0.04f)));

  EXPECT_EQ(r.materials[2].sdbMaterialId, emitter.value);
  expectVec(r.materials[2].emissionCdM2, Rgb(100.0f, 50.0f, 25.0f));
  EXPECT_EQ(r.triangleMaterial, (std::vector<uint32_t>{1, 1, 2, 2, 0, 0}));
  EXPECT_EQ(r.emissiveTriangles, (std::vector<uint32_t>{2, 3}));
}

// Measured BRDFs: materials that name one file share one table (its albedo checked once: a Lambertian table
// of 0.5 reflects 0.5 and is not scaled), a table without a file is its own, a car paint keeps its
// parameters, and a scene without measured materials lowers no table.
TEST(TraceRdbMaterials, MeasuredBrdfTablesAreSharedPerFile) {
  const auto half = std::make_shared<const sdb::MeasuredBrdf>(
      std::vector<Rgb>(sdb::MeasuredBrdf::kSamples, Rgb(0.5f / float(M_PI))));
  const auto sameFileReadAgain = std::make_shared<const sdb::MeasuredBrdf>(*half);
  Scene s;
  auto measured = [&](const char* name, std::shared_ptr<const sdb::MeasuredBrdf> table, const char* path) {
    sdb::Material m;
    m.name = name;
    m.measuredBrdf = std::move(table);
    m.measuredBrdfPath = path;
    return s.addMaterial(m).id;
  };
  const sdb::MaterialId a = measured("a", half, "paint.binary");
  const sdb::MaterialId b = measured("b", sameFileReadAgain, "paint.binary");
  const sdb::MaterialId c = measured("c", half, "");
  const sdb::MaterialId paint = s.addMaterial(sdb::findMaterialPreset("metallic-car-paint")->material).id;
  s.addNode({.meshes = {s.addMesh(quadXZ(a)).id, s.addMesh(quadXZ(b)).id, s.addMesh(quadXZ(c)).id,
                        s.addMesh(quadXZ(paint)).id}});
  const TraceRdb r = buildTraceRdb(s);
  ASSERT_EQ(r.materials.size(), 5u);
  ASSERT_EQ(r.brdfTables.size(), 2u);
  EXPECT_EQ(r.materials[1].brdfTable, 0u);
  EXPECT_EQ(r.materials[2].brdfTable, 0u);
  EXPECT_EQ(r.materials[3].brdfTable, 1u);
  EXPECT_EQ(r.brdfTables[0].file, "paint.binary");
  EXPECT_EQ(r.brdfTables[0].table, half);
  EXPECT_NEAR(r.brdfTables[0].maxAlbedo, 0.5f, 1e-3f);
  EXPECT_EQ(r.brdfTables[0].scale, 1.0f);
  EXPECT_FALSE(r.materials[3].carPaint);
  EXPECT_EQ(r.materials[4].brdfTable, TraceMaterial::kNoBrdfTable);
  ASSERT_TRUE(r.materials[4].carPaint);
  EXPECT_EQ(*r.materials[4].carPaint, *sdb::findMaterialPreset("metallic-car-paint")->material.carPaint);
  EXPECT_TRUE(r.materials[4].isMeasured());
  EXPECT_FALSE(r.materials[0].isMeasured());

  Scene plain;
  plain.addNode({.meshes = {plain.addMesh(quadXZ({})).id}});
  EXPECT_TRUE(buildTraceRdb(plain).brdfTables.empty());
}

// Textures are lowered once each to 8 bits (16-bit values rounded), slots keep their UV set, wrap modes and
// KHR_texture_transform (the extension's example maps uv (1, 0) to (0, 0.5) and (0, 1) to (0.5, 1): the
// lower-left quadrant, turned), and only the per-vertex attributes that materials read are kept.
TEST(TraceRdbMaterials, TexturesSlotsAndOnlyTheAttributesMaterialsRead) {
  Scene s;
  sdb::Texture sixteen;
  sixteen.name = "sixteen";
  sixteen.width = 2;
  sixteen.height = 1;
  sixteen.channels = 1;
  sixteen.bitsPerChannel = 16;
  for (uint16_t v : {uint16_t(65535), uint16_t(32896)}) {  // 32896 = 128 · 257
    sixteen.pixels.push_back(uint8_t(v & 0xff));
    sixteen.pixels.push_back(uint8_t(v >> 8));
  }
  if (const uint16_t probe = 1; *reinterpret_cast<const uint8_t*>(&probe) == 0) {
    std::swap(sixteen.pixels[0], sixteen.pixels[1]);  // native-endian pairs on a big-endian machine
    std::swap(sixteen.pixels[2], sixteen.pixels[3]);
  }
  const sdb::TextureId texture = s.addTexture(sixteen).id;
  sdb::Material m;
  m.diffuseTexture.texture = texture;
  m.diffuseTexture.transform = {vec2(0.0f, 1.0f), 1.5707963f, vec2(0.5f)};
  m.diffuseTexture.wrapS = sdb::WrapMode::kClampToEdge;
  m.diffuseTexture.wrapT = sdb::WrapMode::kMirroredRepeat;
  m.diffuseTexture.magFilter = sdb::MagFilter::kNearest;
  m.emissionTexture.texture = texture;  // the same texture: lowered once
  m.alphaMode = sdb::AlphaMode::kMask;
  m.alphaCutoff = 0.3f;
  m.opacity = 0.9f;
  const sdb::MaterialId textured = s.addMaterial(m).id;
  sdb::Mesh mesh = quadXZ(textured);
  mesh.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.uv1 = mesh.uv0;
  sdb::Mesh plain = quadXZ({});
  plain.colors.assign(4, vec4(0.5f));
  s.addNode({.meshes = {s.addMesh(mesh).id, s.addMesh(plain).id}});

  const TraceRdb r = buildTraceRdb(s);
  ASSERT_EQ(r.textures.size(), 1u);
  EXPECT_EQ(r.textures[0].texels, (std::vector<uint8_t>{255, 128}));
  const TraceMaterial& t = r.materials[1];
  EXPECT_EQ(t.diffuseTexture.texture, 0u);
  EXPECT_EQ(t.emissionTexture.texture, 0u);
  EXPECT_FALSE(t.normalTexture);
  EXPECT_EQ(t.diffuseTexture.wrapS, TraceWrap::kClampToEdge);
  EXPECT_EQ(t.diffuseTexture.wrapT, TraceWrap::kMirroredRepeat);
  EXPECT_TRUE(t.diffuseTexture.nearest);
  EXPECT_FALSE(t.emissionTexture.nearest);
  EXPECT_EQ(t.alpha, TraceAlpha::kMask);
  EXPECT_FLOAT_EQ(t.alphaCutoff, 0.3f);
  EXPECT_FLOAT_EQ(t.opacity, 0.9f);
  auto transformed = [&](const vec2& uv) {
    const TraceTextureSlot& slot = t.diffuseTexture;
    return slot.uvFromU * uv.x + slot.uvFromV * uv.y + slot.uvOffset;
  };
  expectVec(vec3(transformed({0, 0}), 0), vec3(0, 1, 0));
  expectVec(vec3(transformed({1, 0}), 0), vec3(0, 0.5f, 0));
  expectVec(vec3(transformed({0, 1}), 0), vec3(0.5f, 1, 0));
  // uv0 for the slots, COLOR_0 (some mesh has it; 1 where one has none); no uv1, no tangents.
  EXPECT_EQ(r.uv0.size(), r.positionsM.size());
  EXPECT_EQ(r.uv0[2], vec2(1, 1));
  EXPECT_EQ(r.uv0[4], vec2(0, 0));
  ASSERT_EQ(r.colors.size(), r.positionsM.size());
  EXPECT_EQ(r.colors[0], vec4(1.0f));
  EXPECT_EQ(r.colors[4], vec4(0.5f));
  EXPECT_TRUE(r.uv1.empty());
  EXPECT_TRUE(r.tangents.empty());

  // A normal map needs tangents: from the UVs, ∂p/∂u = +x and ∂p/∂v = +z; the bitangent points to the image's
  // up, −v = −Z, and N × T = +Y × +X = −Z, so w = +1 (as the GL engine's, raster_rdb_test.cpp).
  Scene n;
  sdb::Material bumpy;
  bumpy.bumpTexture.texture = n.addTexture(sixteen).id;
  sdb::Mesh quad = quadXZ(n.addMaterial(bumpy).id);
  quad.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  n.addNode({.meshes = {n.addMesh(quad).id}});
  const TraceRdb withMap = buildTraceRdb(n);
  ASSERT_EQ(withMap.tangents.size(), 4u);
  for (const vec4& tangent : withMap.tangents) {
    expectVec(vec3(tangent), vec3(1, 0, 0));
    EXPECT_EQ(tangent.w, 1.0f);
  }
  EXPECT_TRUE(withMap.colors.empty());

  // Anisotropic reflection needs tangents too (from the UVs, as for the normal map), and its values and
  // textures are lowered; a rotation texture is read only for an anisotropic material.
  Scene a;
  sdb::Material brushed = sdb::findMaterialPreset("brushed-metal")->material;
  brushed.anisotropyRotationRad = 0.25f;
  brushed.anisotropyRotationTexture.texture = a.addTexture(sixteen).id;
  sdb::Mesh plate = quadXZ(a.addMaterial(brushed).id);
  plate.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  sdb::Material rotatedOnly;  // isotropic: its rotation texture is of no use
  rotatedOnly.anisotropyRotationTexture.texture = brushed.anisotropyRotationTexture.texture;
  a.addNode({.meshes = {a.addMesh(plate).id, a.addMesh(quadXZ(a.addMaterial(rotatedOnly).id)).id}});
  const TraceRdb anisotropic = buildTraceRdb(a);
  ASSERT_EQ(anisotropic.tangents.size(), 8u);
  for (size_t i = 0; i < 4; ++i) {
    expectVec(vec3(anisotropic.tangents[i]), vec3(1, 0, 0));
    EXPECT_EQ(anisotropic.tangents[i].w, 1.0f);
  }
  ASSERT_EQ(anisotropic.materials.size(), 3u);
  const TraceMaterial& lowered = anisotropic.materials[1];
  EXPECT_TRUE(lowered.isAnisotropic());
  EXPECT_FLOAT_EQ(lowered.anisotropyU, 0.6f);
  EXPECT_FLOAT_EQ(lowered.anisotropyV, 0.1f);
  EXPECT_FLOAT_EQ(lowered.anisotropyRotationRad, 0.25f);
  EXPECT_TRUE(bool(lowered.anisotropyRotationTexture));
  EXPECT_FALSE(bool(lowered.anisotropyTexture));
  EXPECT_FALSE(anisotropic.materials[2].isAnisotropic());
  EXPECT_FALSE(bool(anisotropic.materials[2].anisotropyRotationTexture));

  // Without UVs or tangents the anisotropy has no direction on the surface: a warning names the mesh.
  Scene noUv;
  sdb::Mesh bareQuad = quadXZ(noUv.addMaterial(sdb::findMaterialPreset("brushed-metal")->material).id);
  bareQuad.name = "plate";
  noUv.addNode({.meshes = {noUv.addMesh(bareQuad).id}});
  std::string warning;
  const log::Sink previous = log::setSink([&](log::Level, std::string_view message) { warning += message; });
  const TraceRdb arbitrary = buildTraceRdb(noUv);
  log::setSink(previous);
  EXPECT_EQ(arbitrary.tangents.size(), 4u);
  EXPECT_NE(warning.find("mesh \"plate\""), std::string::npos) << warning;
  EXPECT_NE(warning.find("TEXCOORD_0"), std::string::npos) << warning;

  // Nothing textured, nothing kept.
  Scene bare;
  bare.addNode({.meshes = {bare.addMesh(quadXZ({})).id}});
  const TraceRdb plainRdb = buildTraceRdb(bare);
  EXPECT_TRUE(plainRdb.uv0.empty() && plainRdb.uv1.empty() && plainRdb.colors.empty() &&
              plainRdb.tangents.empty() && plainRdb.textures.empty());
}

TEST(TraceRdbLights, SpotPointsAlongItsNodesMinusZWithCosCones) {
  Scene s;
  sdb::Light spot;
  spot.type = sdb::LightType::kSpot;
  spot.color = Rgb(1.0f, 0.5f, 0.25f);
  spot.intensity = 200.0f;
  spot.rangeM = 12.0f;
  spot.innerConeRad = float(degToRad(20.0));
  spot.outerConeRad = float(degToRad(30.0));
  const sdb::LightId id = s.addLight(spot).id;
  // A downlight at (0, 3, 0): local −Z → world −Y; local +X sheared towards +Y (made perpendicular: +X).
  const mat4 m = frameTransform(vec3(1, 0.5f, 0), vec3(0, 0, -1), vec3(0, 1, 0), vec3(0, 3, 0));
  s.addNode({.parentFromLocal = m, .light = id});

  const TraceRdb r = buildTraceRdb(s);
  ASSERT_EQ(r.punctualLights.size(), 1u);
  const TracePunctualLight& l = r.punctualLights[0];
  EXPECT_EQ(l.type, PunctualType::kSpot);
  EXPECT_EQ(l.sdbLightId, id.value);
  expectVec(l.positionM, vec3(0, 3, 0));
  expectVec(l.directionWorld, vec3(0, -1, 0));
  expectVec(l.cAxisWorld, vec3(1, 0, 0));
  expectVec(l.intensity, Rgb(200.0f, 100.0f, 50.0f), 1e-4f);
  EXPECT_FLOAT_EQ(l.rangeM, 12.0f);
  EXPECT_NEAR(l.cosInner, std::cos(degToRad(20.0)), 1e-6);
  EXPECT_NEAR(l.cosOuter, std::cos(degToRad(30.0)), 1e-6);
  EXPECT_TRUE(r.goniometricTables.empty());

  // A zero scale leaves the light no direction: an input error naming the node.
  s.addNode({.name = "flat", .parentFromLocal = glm::mat4(0.0f), .light = id});
  try {
    buildTraceRdb(s);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"flat\""), std::string::npos) << e.what();
  }
}

// ∫ I dω of a TraceGoniometricTable, interpolated bilinearly as trace_rdb.h defines (wrapping in C): the midpoint
// rule on 8 × 8 points per table cell, dω = sin γ dγ dC.
double tableFluxLm(const TraceGoniometricTable& t) {
  const int sub = 8;
  const double dGamma = kPi / (t.gammaSteps - 1), dC = 2.0 * kPi / t.cSteps;
  double sum = 0.0;
  for (uint32_t c = 0; c < t.cSteps; ++c) {
    const uint32_t c1 = (c + 1) % t.cSteps;
    for (uint32_t g = 0; g + 1 < t.gammaSteps; ++g) {
      const double i00 = t.candelaCd[c * t.gammaSteps + g], i01 = t.candelaCd[c * t.gammaSteps + g + 1];
      const double i10 = t.candelaCd[c1 * t.gammaSteps + g], i11 = t.candelaCd[c1 * t.gammaSteps + g + 1];
      for (int a = 0; a < sub; ++a) {
        const double u = (a + 0.5) / sub;  // along γ
        const double sinGamma = std::sin((g + u) * dGamma);
        for (int b = 0; b < sub; ++b) {
          const double v = (b + 0.5) / sub;  // along C
          sum += ((1 - v) * ((1 - u) * i00 + u * i01) + v * ((1 - u) * i10 + u * i11)) * sinGamma;
        }
      }
    }
  }
  return sum * dGamma * dC / (sub * sub);
}

TEST(TraceRdbLights, GoniometricTableKeepsTheProfilesFlux) {
  for (const char* file : {"asymmetric_c_full_lm63-2002.ies", "quadrant_c_feet_lm63-1995.ies",
                           "floodlight_b_lm63-2002.ies", "headlamp_a_lm63-2002.ies"}) {
    SCOPED_TRACE(file);
    const sdb::IesProfile profile = sdb::loadIes(std::string(FLY_TEST_DATA_DIR) + "/ies/" + file);
    const TraceGoniometricTable t = tabulateGoniometric(profile, 181, 72);
    ASSERT_EQ(t.candelaCd.size(), 181u * 72u);
    EXPECT_FLOAT_EQ(t.candelaCd[0], float(profile.candelaTowards(0, 0, 1)));  // γ = 0: the photometric axis
    // C = 90°, γ = 60°: local (sin 60°·cos 90°, sin 60°·sin 90°, −cos 60°), the profile's (0, sin 60°, cos 60°).
    EXPECT_FLOAT_EQ(t.candelaCd[18 * 181 + 60],
                    float(profile.candelaTowards(0, std::sin(degToRad(60.0)), std::cos(degToRad(60.0)))));
    const double tableLm = tableFluxLm(t), profileLm = profile.totalFluxLm();
    std::printf("[ flux     ] %s: table %.2f lm, profile %.2f lm, ratio %.5f\n", file, tableLm, profileLm,
                tableLm / profileLm);
    EXPECT_NEAR(tableLm / profileLm, 1.0, 0.01);
  }

  Scene s;
  sdb::Light gonio;
  gonio.type = sdb::LightType::kGoniometric;
  gonio.color = Rgb(1.0f, 0.5f, 0.25f);
  gonio.intensity = 2.0f;
  gonio.ies = std::make_shared<const sdb::IesProfile>(
      sdb::loadIes(std::string(FLY_TEST_DATA_DIR) + "/ies/isotropic_c_1000cd_lm63-2002.ies"));
  s.addNode({.light = s.addLight(gonio).id});
  const TraceRdb r = buildTraceRdb(s, {.goniometricGammaSteps = 19, .goniometricCSteps = 8});
  ASSERT_EQ(r.goniometricTables.size(), 1u);
  EXPECT_EQ(r.punctualLights[0].type, PunctualType::kGoniometric);
  EXPECT_EQ(r.punctualLights[0].goniometricTable, 0u);
  expectVec(r.punctualLights[0].intensity, Rgb(2.0f, 1.0f, 0.5f));
  EXPECT_EQ(r.goniometricTables[0].candelaCd.size(), 19u * 8u);
  EXPECT_NEAR(r.goniometricTables[0].candelaCd[4 * 19 + 9], 1000.0f, 1e-3f);
}

// Helsinki, true north along −Z unless `grid` says otherwise.
Scene helsinki(const std::string& localTime, sdb::SkyModel model, bool sun, sdb::Site::Grid grid = sdb::Site::Grid::kNone) {
  Scene s;
  sdb::Site site;
  site.latitudeDeg = 60.1699;
  site.longitudeDeg = 24.9384;
  site.elevationM = 10.0;
  site.timeZone = "Europe/Helsinki";
  site.grid = grid;
  site.gridCentralMeridianDeg = 27.0;
  s.setSite(site);
  s.setTime({localTime});
  sdb::SkySettings sky;
  sky.model = model;
  sky.sun = sun;
  s.setSky(sky);
  return s;
}

// The sun's world direction computed here from fly's sun position: ENU east = +X, north = −Z, up = +Y.
dvec3 expectedHelsinkiSunWorld() {
  sunsky::SpaInput spa;
  spa.utc = sunsky::parseTime("2026-06-21T12:00", "Europe/Helsinki");
  spa.latitudeDeg = 60.1699;
  spa.longitudeDeg = 24.9384;
  spa.elevationM = 10.0;
  const sunsky::SunPosition p = sunsky::sunPosition(spa);
  const double az = degToRad(p.azimuthDeg), el = degToRad(p.apparentElevationDeg());
  const double east = std::sin(az) * std::cos(el), north = std::cos(az) * std::cos(el), up = std::sin(el);
  return {east, up, -north};
}

TEST(TraceRdbDaylight, SunDirectionFromSiteAndLocalTime) {
  const TraceRdb r = buildTraceRdb(helsinki("2026-06-21T12:00", sdb::SkyModel::kNone, true));
  ASSERT_TRUE(r.hasSun);
  const dvec3 expected = expectedHelsinkiSunWorld();
  expectVec(r.sun.directionWorld, vec3(expected));
  EXPECT_GT(expected.y, 0.75);  // 50.6° up at 12:00 summer time (solar noon is near 13:20)
  EXPECT_NEAR(r.sun.halfAngleRad, degToRad(0.533 / 2.0), 1e-7);
  EXPECT_GT(luminance(r.sun.normalIlluminanceLux), 70000.0f);  // clear sun at 50.6° elevation, T = 3
  EXPECT_LT(luminance(r.sun.normalIlluminanceLux), 110000.0f);
  EXPECT_EQ(r.sky.resolution, 0u);  // sky model none: no table
  EXPECT_TRUE(r.sky.radianceCdM2.empty());

  // Drawn on ETRS-TM35FIN (central meridian 27° E): the model's −Z is grid north, so true north, and the sun
  // with it, turn about +Y by the meridian convergence γ ≈ −1.787° (negative: clockwise seen from above).
  const TraceRdb g =
      buildTraceRdb(helsinki("2026-06-21T12:00", sdb::SkyModel::kNone, true, sdb::Site::Grid::kTransverseMercator));
  sunsky::NorthReference tm27;
  tm27.kind = sunsky::NorthReference::Kind::kTransverseMercatorGridNorth;
  tm27.centralMeridianDeg = 27.0;
  const double gammaDeg = sunsky::makeSiteFrame(60.1699, 24.9384, tm27).meridianConvergenceDeg();
  const double clockwiseTurnDeg = radToDeg(std::atan2(g.sun.directionWorld.x, -g.sun.directionWorld.z) -
                                           std::atan2(r.sun.directionWorld.x, -r.sun.directionWorld.z));
  std::printf("[ grid     ] gamma %.4f deg; the sun turned %.4f deg clockwise on TM27\n", gammaDeg, clockwiseTurnDeg);
  EXPECT_NEAR(gammaDeg, -1.787, 0.002);
  EXPECT_NEAR(clockwiseTurnDeg, -gammaDeg, 1e-4);
  const double gamma = degToRad(gammaDeg);  // R_y(γ): x' = cos γ·x + sin γ·z, z' = −sin γ·x + cos γ·z
  const dvec3 rotated(std::cos(gamma) * expected.x + std::sin(gamma) * expected.z, expected.y,
                      -std::sin(gamma) * expected.x + std::cos(gamma) * expected.z);
  expectVec(g.sun.directionWorld, vec3(rotated));
}

// Σ luminance(L_cell) · μ̄_j · 2π/res², μ̄_j = 1 − (j + ½)/res the mean μ of row j: the table's horizontal
// illuminance.
double tableHorizontalLux(const TraceSky& t) {
  double sum = 0.0;
  for (uint32_t j = 0; j < t.resolution; ++j) {
    const double mu = 1.0 - (j + 0.5) / t.resolution;
    for (uint32_t i = 0; i < t.resolution; ++i) sum += luminance(t.radianceCdM2[j * t.resolution + i]) * mu;
  }
  return sum * 2.0 * kPi / (double(t.resolution) * t.resolution);
}

TEST(TraceRdbDaylight, SkyTableKeepsTheHorizontalIlluminance) {
  const Scene scene = helsinki("2026-06-21T12:00", sdb::SkyModel::kClear, true);
  const TraceRdb r = buildTraceRdb(scene);
  ASSERT_EQ(r.sky.resolution, 64u);
  ASSERT_EQ(r.sky.radianceCdM2.size(), 4096u);
  const std::optional<SceneDaylight> d = lowerDaylight(scene);
  ASSERT_TRUE(d && d->sky);
  const double clearLux = sunsky::horizontalIlluminanceLux(*d->sky);
  std::printf("[ sky      ] clear: table %.1f lx, sky %.1f lx, ratio %.5f\n", tableHorizontalLux(r.sky), clearLux,
              tableHorizontalLux(r.sky) / clearLux);
  EXPECT_NEAR(tableHorizontalLux(r.sky) / clearLux, 1.0, 0.005);
  // The Hosek–Wilkie level at the sun's elevation: between its values at 45° and 60° (16.8 and 17.6 klx at
  // the mean Earth–Sun distance, turbidity 3), 3.4 % less at the June aphelion.
  EXPECT_GT(d->sunPosition.apparentElevationDeg(), 45.0);
  EXPECT_LT(d->sunPosition.apparentElevationDeg(), 60.0);
  EXPECT_GT(clearLux, 16779.7 * 0.966);
  EXPECT_LT(clearLux, 17643.3 * 0.968);

  // CIE skies in a frame turned by 30°, the sun low in the south-west.
  sunsky::NorthReference north;
  north.angleDeg = 30.0;
  const sunsky::SiteFrame frame = sunsky::makeSiteFrame(60.17, 24.94, north);
  for (int type : {1, 12}) {
    const sunsky::CieSky sky =
        sunsky::makeCieSky(type, 65.0, 220.0, sunsky::CieNormalisation::diffuseHorizontalLux(10000.0));
    const TraceSky t = tabulateSky(sky, frame, 64, 4);
    const double lux = sunsky::horizontalIlluminanceLux(sky);
    std::printf("[ sky      ] CIE %d: table %.1f lx, sky %.1f lx, ratio %.5f\n", type, tableHorizontalLux(t), lux,
                tableHorizontalLux(t) / lux);
    EXPECT_NEAR(tableHorizontalLux(t) / lux, 1.0, 0.005);
  }
}

TEST(TraceRdbDaylight, SkyTableCellsFollowTheWorldMapping) {
  // One direction per cell: its centre φ = 2π(i + ½)/res, μ = 1 − (j + ½)/res, world (sin θ cos φ, μ, sin θ sin φ).
  // With true north along −Z, ENU = (east, north, up) = (x, −z, y).
  const sunsky::CieSky sky =
      sunsky::makeCieSky(12, 60.0, 130.0, sunsky::CieNormalisation::diffuseHorizontalLux(10000.0));
  const uint32_t res = 16;
  const TraceSky t = tabulateSky(sky, sunsky::makeSiteFrame(60.0, 25.0, {}), res, 1);
  for (uint32_t j : {0u, 5u, 15u}) {
    for (uint32_t i : {0u, 3u, 9u, 15u}) {
      const double phi = 2.0 * kPi * (i + 0.5) / res, mu = 1.0 - (j + 0.5) / res;
      const double sinTheta = std::sqrt(1.0 - mu * mu);
      const dvec3 enu(sinTheta * std::cos(phi), -sinTheta * std::sin(phi), mu);
      expectVec(t.radianceCdM2[j * res + i], sky.radianceCdM2(enu), 1e-3f);
    }
  }
}

TEST(TraceRdbDaylight, PerezSkyFromTheWeatherFile) {
  Scene s = helsinki("2026-06-21T12:00", sdb::SkyModel::kPerez, true);
  sdb::SkySettings sky = s.sky();
  sky.weatherFile = std::string(FLY_TEST_DATA_DIR) + "/epw/helsinki-jun21-22.epw";
  s.setSky(sky);
  const TraceRdb r = buildTraceRdb(s);
  const std::optional<SceneDaylight> d = lowerDaylight(s);
  ASSERT_TRUE(d && d->sky && d->sun);
  const auto& perez = dynamic_cast<const sunsky::PerezSky&>(*d->sky);
  std::printf("[ perez    ] diffuse %.1f lx (table %.1f lx), direct normal %.1f lx\n", perez.diffuseHorizontalLux(),
              tableHorizontalLux(r.sky), perez.directNormalLux());
  EXPECT_GT(perez.diffuseHorizontalLux(), 0.0);
  EXPECT_NEAR(tableHorizontalLux(r.sky) / perez.diffuseHorizontalLux(), 1.0, 0.005);
  ASSERT_TRUE(r.hasSun);
  EXPECT_NEAR(luminance(r.sun.normalIlluminanceLux), perez.directNormalLux(), 1e-3 * perez.directNormalLux());
}

TEST(TraceRdbDaylight, CieDefaultLevelsFollowTheIesHandbook) {
  EXPECT_NEAR(cieSkyDefaultDiffuseLux(1, 30.0, 180.0, 3.0), 300.0 + 21000.0 * 0.5, 1e-9);
  EXPECT_NEAR(cieSkyDefaultDiffuseLux(5, 90.0, 180.0, 3.0), 21300.0, 1e-9);
  EXPECT_DOUBLE_EQ(cieSkyDefaultDiffuseLux(12, 30.0, 180.0, 3.0), sunsky::iesClearSkyDiffuseLux(30.0));
  EXPECT_DOUBLE_EQ(cieSkyDefaultDiffuseLux(7, 30.0, 180.0, 3.0), sunsky::iesClearSkyDiffuseLux(30.0));
  // Twilight: below the horizon the level falls monotonically from the sunset value.
  double previous = cieSkyDefaultDiffuseLux(1, 0.0, 180.0, 3.0);
  EXPECT_DOUBLE_EQ(previous, 300.0);
  for (double elevation : {-1.0, -3.0, -6.0, -12.0, -18.0}) {
    const double lux = cieSkyDefaultDiffuseLux(1, elevation, 180.0, 3.0);
    EXPECT_LT(lux, previous) << elevation;
    EXPECT_GT(lux, 0.0) << elevation;
    previous = lux;
  }
}

TEST(TraceRdbDaylight, SunBelowTheHorizonLeavesTheTwilightSky) {
  const TraceRdb r = buildTraceRdb(helsinki("2026-12-21T17:00", sdb::SkyModel::kCie, true));
  EXPECT_FALSE(r.hasSun);
  ASSERT_EQ(r.sky.resolution, 64u);
  const double lux = tableHorizontalLux(r.sky);
  std::printf("[ twilight ] CIE 12 sky at 17:00 on 21 December: %.3f lx\n", lux);
  EXPECT_GT(lux, 0.0);
  EXPECT_LT(lux, 300.0);
}

TEST(TraceRdbDaylight, NoSiteNoSunNoSky) {
  Scene s;
  s.addNode({.meshes = {s.addMesh(quadXZ({})).id}});
  const TraceRdb r = buildTraceRdb(s);
  EXPECT_FALSE(r.hasSun);
  EXPECT_EQ(r.sky.resolution, 0u);
  EXPECT_TRUE(r.sky.radianceCdM2.empty());
  EXPECT_TRUE(r.punctualLights.empty());
  EXPECT_TRUE(r.goniometricTables.empty());
  EXPECT_TRUE(r.emissiveTriangles.empty());
  // A site and time without a sky or sun build no daylight either.
  EXPECT_FALSE(lowerDaylight(helsinki("2026-06-21T12:00", sdb::SkyModel::kNone, false)));
}

// Declared portals reach the baker as triangles, 3 corners each (a quad as (0, 1, 2) and (0, 2, 3)), and are
// no geometry: the triangle arrays and bounds are those of the scene without them.
TEST(TraceRdbPortals, DeclaredPortalsAreTrianglesNotGeometry) {
  Scene s;
  s.addNode({.meshes = {s.addMesh(quadXZ({})).id}});
  const TraceRdb without = buildTraceRdb(s);
  EXPECT_TRUE(without.portalCornersM.empty());
  const std::vector<vec3> quad = {vec3(1.5f, 0.8f, 3), vec3(-1.5f, 0.8f, 3), vec3(-1.5f, 2.3f, 3),
                                  vec3(1.5f, 2.3f, 3)};
  const std::vector<vec3> triangle = {vec3(0, 3, 0), vec3(0, 3, 2), vec3(1, 3, 0)};
  s.setPortals({{"window", quad}, {"roof light", triangle}});
  const TraceRdb r = buildTraceRdb(s);
  ASSERT_EQ(r.portalCornersM.size(), 9u);
  const vec3 expected[9] = {quad[0], quad[1], quad[2], quad[0], quad[2], quad[3],
                            triangle[0], triangle[1], triangle[2]};
  for (size_t i = 0; i < 9; ++i) expectVec(r.portalCornersM[i], expected[i], 0.0f);
  EXPECT_EQ(r.positionsM, without.positionsM);
  EXPECT_EQ(r.indices, without.indices);
  expectVec(r.boundsM.min, without.boundsM.min, 0.0f);
  expectVec(r.boundsM.max, without.boundsM.max, 0.0f);
}

TEST(TraceRdbDaylight, BadTimeOrZoneIsAnInputErrorThatNamesIt) {
  Scene badZone = helsinki("2026-06-21T12:00", sdb::SkyModel::kClear, true);
  sdb::Site site = badZone.site();
  site.timeZone = "Mars/Olympus_Mons";
  badZone.setSite(site);
  try {
    buildTraceRdb(badZone);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Mars/Olympus_Mons"), std::string::npos) << e.what();
  }
  try {
    buildTraceRdb(helsinki("2026-13-21T12:00", sdb::SkyModel::kClear, true));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("month 13"), std::string::npos) << e.what();
  }
}

TEST(TraceRdbBuild, IsDeterministic) {
  Scene s = helsinki("2026-06-21T15:30", sdb::SkyModel::kClear, true);
  s.addNode({.meshes = {s.addMesh(quadXZ({})).id}});
  sdb::Light point;
  point.intensity = 50.0f;
  s.addNode({.parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 2, 0)),
             .light = s.addLight(point).id});
  const TraceRdb a = buildTraceRdb(s), b = buildTraceRdb(s);
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  EXPECT_TRUE(same(a.positionsM, b.positionsM));
  EXPECT_TRUE(same(a.normals, b.normals));
  EXPECT_TRUE(same(a.indices, b.indices));
  EXPECT_TRUE(same(a.sky.radianceCdM2, b.sky.radianceCdM2));
  EXPECT_EQ(std::memcmp(&a.sun.directionWorld, &b.sun.directionWorld, sizeof(vec3)), 0);
  EXPECT_EQ(std::memcmp(&a.sun.normalIlluminanceLux, &b.sun.normalIlluminanceLux, sizeof(Rgb)), 0);
  ASSERT_EQ(a.punctualLights.size(), 1u);
  EXPECT_EQ(std::memcmp(&a.punctualLights[0].positionM, &b.punctualLights[0].positionM, sizeof(vec3)), 0);
}

TEST(TraceRdbBuild, LowersTheSampleHouse) {
  const Scene scene = sdb::loadScene(std::string(FLY_SOURCE_DIR) + "/scenes/house/house.json");
  const TraceRdb r = buildTraceRdb(scene);
  std::printf("[ house    ] %zu triangles (%zu skipped), %zu vertices, %zu materials, sun %.0f lx, %zu sky cells\n",
              r.triangleCount(), r.skippedTriangles, r.positionsM.size(), r.materials.size(),
              double(luminance(r.sun.normalIlluminanceLux)), r.sky.radianceCdM2.size());
  ASSERT_GT(r.triangleCount(), 0u);
  EXPECT_EQ(r.normals.size(), r.positionsM.size());
  EXPECT_EQ(r.triangleMaterial.size(), r.triangleCount());
  for (uint32_t v : r.indices) ASSERT_LT(v, r.positionsM.size());
  for (uint32_t m : r.triangleMaterial) ASSERT_LT(m, r.materials.size());
  for (const vec3& n : r.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
  for (const Rgb& l : r.sky.radianceCdM2) ASSERT_TRUE(isFinite(l) && l.r >= 0.0f && l.g >= 0.0f && l.b >= 0.0f);
  EXPECT_TRUE(r.hasSun);  // 15:00 on midsummer day
  EXPECT_EQ(r.sky.resolution, 64u);
  ASSERT_EQ(r.punctualLights.size(), 1u);
  EXPECT_EQ(r.punctualLights[0].type, PunctualType::kGoniometric);
  expectVec(r.punctualLights[0].directionWorld, vec3(0, -1, 0), 1e-6f);
  expectVec(r.punctualLights[0].positionM, vec3(0.0f, 2.74f, 0.0f), 1e-6f);
  EXPECT_EQ(r.goniometricTables.size(), 1u);
  const auto glass = std::find_if(r.materials.begin(), r.materials.end(), [&](const TraceMaterial& m) {
    return m.sdbMaterialId == scene.findMaterial("Glass").value;
  });
  ASSERT_NE(glass, r.materials.end());
  expectVec(glass->diffuse, Rgb(0.0f));
  expectVec(glass->transmission, Rgb(1.0f));
}

}  // namespace
}  // namespace fly::rdb
