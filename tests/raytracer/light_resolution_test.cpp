// Where vertices cannot carry the light (raytracer/light_resolution.h): against direct light computed here in
// closed form, and the automatic light textures that follow from it.
#include "raytracer/light_resolution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rdb/trace_rdb_build.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::raytracer {
namespace {

using Builder = rdb::TraceRdbBuilder;

std::vector<MeshLightResolution> analyse(const rdb::TraceRdb& rdb, float largeEdgeM = 1.0f) {
  const EmbreeScene scene(rdb);
  IntegratorSettings is;
  is.litPatches = false;
  const Integrator integrator(rdb, scene, is);
  LightResolutionSettings s;
  s.largeTriangleEdgeM = largeEdgeM;
  uint64_t rays = 0;
  auto out = analyseLightResolution(rdb, scene, integrator, s, rays);
  if (rdb.hasSun || !rdb.punctualLights.empty()) {
    EXPECT_GT(rays, 0u);
  }
  return out;
}

// A floor of 6 × 6 m in 0.5 m tiles with vertices of their own (edges up to 0.71 m, below the large-triangle
// edge of 1 m).
void floorTiles(Builder& b, uint32_t mat) {
  b.tiles(vec3(-3, 0, -3), vec3(0, 0, 6), vec3(6, 0, 0), 12, mat);
}

// Uniform sunlight is linear (constant) over every triangle: nothing to resolve.
TEST(LightResolution, UniformSunNeedsNoTexels) {
  Builder b;
  floorTiles(b, b.material(Rgb(0.5f)));
  b.sun(vec3(1, 1, 0.3f), Rgb(80000.0f));
  const auto r = analyse(b.rdb);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_FALSE(r[0].needsTexels);
  EXPECT_EQ(r[0].directVariationAreaM2, 0.0);
  EXPECT_NEAR(r[0].areaM2, 36.0, 1e-3);
  for (float e : r[0].directInterpolationError) EXPECT_LT(e, 1e-4f);
}

// A 1 m square blocker 1 m above the floor under a sun straight above casts a 1 m square shadow on
// x, z ∈ [0, 1]: the triangles that the shadow's outline crosses need texels, and only those.
TEST(LightResolution, ShadowEdgesNeedTexels) {
  Builder b;
  const uint32_t mat = b.material(Rgb(0.5f));
  floorTiles(b, mat);
  b.grid(vec3(0.02f, 1, 0.02f), vec3(0.96f, 0, 0), vec3(0, 0, 0.96f), 1, mat);  // faces −Y; blocks either way
  b.sun(vec3(0, 1, 0), Rgb(80000.0f));
  const auto r = analyse(b.rdb);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_TRUE(r[0].needsTexels);
  EXPECT_NE(r[0].reason.find("sun patches"), std::string::npos) << r[0].reason;
  // The outline x or z = 0.02 or 0.98 crosses the tiles [0, 0.5] and [0.5, 1] in each coordinate: every
  // flagged triangle touches it, and the 8 tiles along it (16 triangles, 2 m²) at most are flagged.
  const rdb::TraceMesh& floor = b.rdb.meshes[0];
  size_t flagged = 0;
  for (uint32_t k = 0; k < floor.triangleCount; ++k) {
    if (!(r[0].directInterpolationError[k] > 0.05f)) continue;
    ++flagged;
    vec3 lo(1e9f), hi(-1e9f);
    for (int c = 0; c < 3; ++c) {
      const vec3& p = b.rdb.positionsM[b.rdb.indices[3 * size_t(floor.firstTriangle + k) + size_t(c)]];
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    EXPECT_TRUE(lo.x < 1.0f && hi.x > 0.0f && lo.z < 1.0f && hi.z > 0.0f) << "triangle " << k;
  }
  EXPECT_GE(flagged, 8u);
  EXPECT_LE(r[0].directVariationAreaM2, 2.0 + 1e-3);
}

// A point lamp 1 m above the floor: E = I h / d³ falls off faster than linearly across 0.5 m tiles. The
// analysis's error inside the tile under the lamp is at least the error at one of its lattice points,
// computed here in closed form.
TEST(LightResolution, LampPoolsNeedTexels) {
  Builder b;
  floorTiles(b, b.material(Rgb(0.5f)));
  const float intensityCd = 1000.0f;
  b.pointLight(vec3(0.0f, 1.0f, 0.0f), Rgb(intensityCd));
  const auto r = analyse(b.rdb);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(r[0].needsTexels);
  EXPECT_NE(r[0].reason.find("lamp pools"), std::string::npos) << r[0].reason;
  auto lux = [&](const vec3& p) {
    const vec3 d = vec3(0, 1, 0) - p;
    return intensityCd * d.y / std::pow(glm::length(d), 3.0f);
  };
  const rdb::TraceMesh& floor = b.rdb.meshes[0];
  size_t checked = 0;
  for (uint32_t k = 0; k < floor.triangleCount; ++k) {
    const uint32_t* v = &b.rdb.indices[3 * size_t(floor.firstTriangle + k)];
    const vec3 p[3] = {b.rdb.positionsM[v[0]], b.rdb.positionsM[v[1]], b.rdb.positionsM[v[2]]};
    if (!(glm::length(p[0]) < 1e-6f)) continue;  // the triangles with a corner under the lamp
    // The lattice point at barycentric (2/3, 1/6, 1/6) (k = 2: the first sub-triangle's centroid).
    const vec3 q = (2.0f / 3.0f) * p[0] + (1.0f / 6.0f) * p[1] + (1.0f / 6.0f) * p[2];
    const float interpolated = (2.0f / 3.0f) * lux(p[0]) + (1.0f / 6.0f) * (lux(p[1]) + lux(p[2]));
    const float exact = lux(q);
    const float relative = std::abs(exact - interpolated) / std::max(exact, interpolated);
    EXPECT_GT(relative, 0.05f);
    EXPECT_GE(r[0].directInterpolationError[k], relative * 0.98f) << "triangle " << k;
    ++checked;
  }
  EXPECT_GE(checked, 1u);
}

// An emitter (a 20 cm luminous panel 1 m above the floor, facing down) pools its light like a lamp: the tiles
// under it need texels; without the panel nothing does.
TEST(LightResolution, EmitterPoolsNeedTexels) {
  for (bool withPanel : {true, false}) {
    Builder b;
    floorTiles(b, b.material(Rgb(0.5f)));
    if (withPanel) {
      const uint32_t panel = b.material(Rgb(0.0f), Rgb(10000.0f));
      b.grid(vec3(-0.1f, 1.0f, -0.1f), vec3(0.2f, 0, 0), vec3(0, 0, 0.2f), 1, panel);  // faces −Y
    }
    const auto r = analyse(b.rdb);
    ASSERT_GE(r.size(), 1u);
    EXPECT_EQ(r[0].needsTexels, withPanel);
    if (withPanel) {
      EXPECT_NE(r[0].reason.find("lamp pools"), std::string::npos) << r[0].reason;
    }
  }
}

// Without direct light, triangles with an edge ≥ 1 m need texels (sky and reflected light vary over such
// distances); 5 cm detail is never examined; "lightTexture": false keeps a mesh out.
TEST(LightResolution, LargeTrianglesAndDetail) {
  Builder b;
  const uint32_t mat = b.material(Rgb(0.5f));
  b.ground(5.0f, 1, mat);                                                     // 2 triangles, 10 m
  b.grid(vec3(0, 1, 0), vec3(0, 0, 0.5f), vec3(0.5f, 0, 0), 10, mat);         // 5 cm quads
  b.ground(5.0f, 1, mat);
  b.rdb.meshes[2].automaticLightTextureAllowed = false;
  b.uniformSky(Rgb(1000.0f));
  const auto r = analyse(b.rdb);
  ASSERT_EQ(r.size(), 2u);  // the third mesh is not examined
  EXPECT_TRUE(r[0].needsTexels);
  EXPECT_NEAR(r[0].largeTriangleAreaM2, 100.0, 1e-2);
  EXPECT_NE(r[0].reason.find("1 m edges"), std::string::npos) << r[0].reason;
  EXPECT_FALSE(r[1].needsTexels);
  EXPECT_EQ(r[1].largeTriangleAreaM2, 0.0);
}

// addNeededLightTextures gives the meshes that need one an automatic light texture at the density asked,
// keeping TraceRdb::lightTextures in mesh order behind one asked for.
TEST(LightResolution, AddsAutomaticLightTexturesInMeshOrder) {
  Builder b;
  const uint32_t mat = b.material(Rgb(0.5f));
  b.grid(vec3(0, 1, 0), vec3(0, 0, 0.5f), vec3(0.5f, 0, 0), 10, mat);  // detail: none
  b.ground(5.0f, 1, mat);                                               // large: automatic
  b.ground(1.0f, 1, mat);                                               // asked for: kept
  rdb::TraceLightTexture asked;
  asked.mesh = 2;
  asked.width = asked.height = 8;
  asked.texelsPerMetre = 4.0f;
  asked.cornerUv.assign(6, vec2(0.5f));
  b.rdb.lightTextures.push_back(asked);
  b.rdb.meshes[2].lightTexture = 0;
  b.uniformSky(Rgb(1000.0f));
  const EmbreeScene scene(b.rdb);
  LightResolutionSettings s;
  s.texelsPerMetre = 10.0f;
  const auto r = addNeededLightTextures(b.rdb, scene, s);
  EXPECT_EQ(r.size(), 2u);
  ASSERT_EQ(b.rdb.lightTextures.size(), 2u);
  EXPECT_EQ(b.rdb.lightTextures[0].mesh, 1u);
  EXPECT_TRUE(b.rdb.lightTextures[0].automatic);
  EXPECT_FALSE(b.rdb.lightTextures[0].automaticReason.empty());
  EXPECT_EQ(b.rdb.lightTextures[0].texelsPerMetre, 10.0f);
  EXPECT_GE(b.rdb.lightTextures[0].width, 100u);  // 10 m at 10 texels/m
  EXPECT_EQ(b.rdb.lightTextures[0].cornerUv.size(), 6u);
  EXPECT_EQ(b.rdb.lightTextures[1].mesh, 2u);
  EXPECT_FALSE(b.rdb.lightTextures[1].automatic);
  EXPECT_EQ(b.rdb.meshes[0].lightTexture, rdb::TraceMesh::kNoLightTexture);
  EXPECT_EQ(b.rdb.meshes[1].lightTexture, 0u);
  EXPECT_EQ(b.rdb.meshes[2].lightTexture, 1u);
}

// Within an automatic light texture, a chart whose triangles are denser than its texels (fewer than
// kMinTexelsPerTriangle each: a bevel, a curved detail) stays on the vertex light map: its corners get
// noLightTextureUv(); the large chart is in the atlas. A mesh with only such charts gets no texture.
TEST(LightResolution, ChartsFinerInVerticesThanTexelsKeepTheirVertexMaps) {
  Builder b;
  const uint32_t mat = b.material(Rgb(0.5f));
  b.ground(2.0f, 1, mat);  // a 4 m floor of 2 triangles: 6 400 texels at 20 texels/m
  rdb::TraceMesh& floor = b.rdb.meshes[0];
  // A vertical strip of 10 × 10 quads, 1 cm each, standing on the floor, in the same mesh: a chart of its
  // own (perpendicular to the floor) with 0.02 texels per triangle.
  const uint32_t first = uint32_t(b.rdb.positionsM.size());
  for (uint32_t j = 0; j <= 10; ++j)
    for (uint32_t i = 0; i <= 10; ++i) {
      b.rdb.positionsM.push_back(vec3(0.01f * float(i), 0.01f * float(j), 0.0f));
      b.rdb.normals.push_back(vec3(0, 0, 1));
    }
  for (uint32_t j = 0; j < 10; ++j)
    for (uint32_t i = 0; i < 10; ++i) {
      const uint32_t v = first + j * 11 + i;
      b.rdb.indices.insert(b.rdb.indices.end(), {v, v + 1, v + 12, v, v + 12, v + 11});
      b.rdb.triangleMaterial.insert(b.rdb.triangleMaterial.end(), {mat, mat});
    }
  floor.vertexCount = uint32_t(b.rdb.positionsM.size()) - floor.firstVertex;
  floor.triangleCount = uint32_t(b.rdb.triangleCount()) - floor.firstTriangle;
  const rdb::TraceLightTexture* lt = rdb::addAutomaticLightTexture(b.rdb, 0, 20.0f, 512, 2);
  ASSERT_NE(lt, nullptr);
  for (uint32_t t = 0; t < floor.triangleCount; ++t) {
    for (uint32_t c = 0; c < 3; ++c) {
      const vec2 uv = lt->cornerUv[3 * size_t(t) + c];
      if (t < 2) {
        EXPECT_TRUE(rdb::inLightTexture(uv) && uv.x < 1.0f && uv.y > 0.0f && uv.y < 1.0f) << "floor " << t;
      } else {
        EXPECT_EQ(uv, rdb::noLightTextureUv()) << "strip triangle " << t;
      }
    }
  }
  EXPECT_GE(lt->width, 80u);  // 4 m at 20 texels/m
  // The strip alone: no texture at all.
  Builder strip;
  strip.grid(vec3(0.0f), vec3(0.1f, 0, 0), vec3(0, 0.1f, 0), 10, strip.material(Rgb(0.5f)));
  EXPECT_EQ(rdb::addAutomaticLightTexture(strip.rdb, 0, 20.0f, 512, 2), nullptr);
  EXPECT_TRUE(strip.rdb.lightTextures.empty());
}

}  // namespace
}  // namespace fly::raytracer
