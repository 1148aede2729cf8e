// The light-texture baker against exact answers: texel-footprint averages of a point light's
// irradiance, no leaks under a wall, consistent seams, dilation; and the TraceRdb's choice of meshes that get
// a light texture unasked.
#include "raytracer/texel_baker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <vector>

#include "raytracer/baker.h"
#include "rdb/lightmap_uv.h"
#include "rdb/trace_rdb_build.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::raytracer {
namespace {

using MeshBuilder = rdb::TraceRdbBuilder;

constexpr uint32_t kTestReplicates = 64;  // as baker_test.cpp: a 4σ bound per texel with an honest σ

VertexLightMaps bake(const rdb::TraceRdb& rdb, uint32_t samples) {
  const EmbreeScene scene(rdb);
  BakeSettings settings;
  settings.estimate.firstPassSamples = kTestReplicates;
  settings.estimate.maxSamples = samples;
  settings.estimate.replicates = kTestReplicates;
  return bakeVertexLightMaps(rdb, scene, settings);
}

// A light texture for mesh `mesh` of b.rdb, width × height texels, each triangle corner's UV in texel units
// given by `texelOf(triangle within the mesh, corner)`.
void addLightTexture(MeshBuilder& b, uint32_t mesh, uint32_t width, uint32_t height, float texelsPerMetre,
                     const std::function<vec2(uint32_t, uint32_t)>& texelOf) {
  rdb::TraceLightTexture lt;
  lt.mesh = mesh;
  lt.width = width;
  lt.height = height;
  lt.texelsPerMetre = texelsPerMetre;
  for (uint32_t t = 0; t < b.rdb.meshes[mesh].triangleCount; ++t) {
    for (uint32_t c = 0; c < 3; ++c) lt.cornerUv.push_back(texelOf(t, c) / vec2(float(width), float(height)));
  }
  b.rdb.meshes[mesh].lightTexture = uint32_t(b.rdb.lightTextures.size());
  b.rdb.lightTextures.push_back(std::move(lt));
}

// ground(1, 1): a 2 m floor of 2 triangles, grid vertex (i, j) at x = −1 + 2j, z = −1 + 2i. Its light
// texture: 12 × 12 texels, the floor on texels 1 … 10 in both directions (one texel of padding around it),
// texel (i, j) covering x ∈ [−1 + 0.2(i − 1), −1 + 0.2 i], z likewise with j: 5 texels/m.
void floorTexture(MeshBuilder& b, uint32_t mesh) {
  const rdb::TraceMesh& m = b.rdb.meshes[mesh];
  const rdb::TraceRdb& r = b.rdb;
  addLightTexture(b, mesh, 12, 12, 5.0f, [&r, m](uint32_t t, uint32_t c) {
    const vec3& p = r.positionsM[r.indices[3 * size_t{m.firstTriangle + t} + c]];
    return vec2(1.0f + 5.0f * (p.x + 1.0f), 1.0f + 5.0f * (p.z + 1.0f));
  });
}

// Bilinear lookup with the texel-centre convention of rdb/lightmap_uv.h (clamped at the border).
Rgb lookup(const LightTexture& tex, const std::vector<Rgb>& values, const vec2& uv) {
  const float x = uv.x * float(tex.width) - 0.5f, y = uv.y * float(tex.height) - 0.5f;
  const float x0 = std::floor(x), y0 = std::floor(y);
  const float fx = x - x0, fy = y - y0;
  auto at = [&](float i, float j) {
    const uint32_t ci = uint32_t(std::clamp(i, 0.0f, float(tex.width - 1)));
    const uint32_t cj = uint32_t(std::clamp(j, 0.0f, float(tex.height - 1)));
    return values[cj * tex.width + ci];
  };
  return (1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x0 + 1, y0) + (1 - fx) * fy * at(x0, y0 + 1) +
         fx * fy * at(x0 + 1, y0 + 1);
}

// E = I·cos θ/d² = I·h/d³ averaged over each 0.2 m texel footprint by the midpoint rule on 64² cells: each
// texel's estimate lies within 4 of its standard errors.
TEST(TexelBaker, PointLightOverFloorIsTheTexelFootprintAverage) {
  MeshBuilder b;
  b.ground(1.0f, 1, b.material(Rgb(0.0f)));  // black: direct light only, the exact answer
  const vec3 light(0.3f, 0.5f, -0.2f);
  const Rgb intensity(10.0f, 20.0f, 5.0f);
  b.pointLight(light, intensity);
  floorTexture(b, 0);
  const VertexLightMaps maps = bake(b.rdb, 1024);
  ASSERT_EQ(maps.lightTextures.size(), 1u);
  const LightTexture& tex = maps.lightTextures[0];
  EXPECT_EQ(tex.bakedTexels, 100u);
  EXPECT_EQ(tex.emptyTexels, 0u);
  EXPECT_TRUE(tex.backLux.empty());
  double worst = 0.0;
  for (uint32_t j = 1; j <= 10; ++j) {
    for (uint32_t i = 1; i <= 10; ++i) {
      const double x0 = -1.0 + 0.2 * (i - 1), z0 = -1.0 + 0.2 * (j - 1);
      constexpr int n = 64;
      double sum = 0.0;
      for (int a = 0; a < n; ++a) {
        for (int c = 0; c < n; ++c) {
          const dvec3 p(x0 + 0.2 * (a + 0.5) / n, 0.0, z0 + 0.2 * (c + 0.5) / n);
          const double d = glm::length(dvec3(light) - p);
          sum += double{light.y} / (d * d * d);
        }
      }
      const double average = sum / (n * n);
      const uint32_t t = j * 12 + i;
      for (int ch = 0; ch < 3; ++ch) {
        const double exact = intensity[ch] * average;
        const float mean = tex.frontLux[t][ch], sigma = tex.frontStdErrorLux[t][ch];
        EXPECT_LE(std::abs(mean - exact), 4.0 * sigma + 1e-5 * exact) << "texel " << i << "," << j;
        EXPECT_LE(sigma, 0.01 * exact) << "texel " << i << "," << j;
        if (sigma > 0.0f) worst = std::max(worst, std::abs(mean - exact) / sigma);
      }
    }
  }
  // The footprint average differs from the value at the texel centre: the test tells them apart.
  const dvec3 centre(-1.0 + 0.2 * 6.5, 0.0, -1.0 + 0.2 * 4.5);  // texel (7, 5), under the light
  const double d = glm::length(dvec3(light) - centre);
  EXPECT_GT(std::abs(tex.frontLux[5 * 12 + 7].g - intensity.g * light.y / (d * d * d)),
            10.0 * tex.frontStdErrorLux[5 * 12 + 7].g);
  std::cout << "[ texels   ] point light: 100 texels, worst error " << worst << " σ\n";

  // Dilation: every padding texel is the mean of its baked 8-neighbours (it has at least one), finite, > 0.
  for (uint32_t j = 0; j < 12; ++j) {
    for (uint32_t i = 0; i < 12; ++i) {
      if (i >= 1 && i <= 10 && j >= 1 && j <= 10) continue;
      Rgb sum(0.0f);
      int count = 0;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          const int x = int(i) + di, y = int(j) + dj;
          if (x < 1 || y < 1 || x > 10 || y > 10) continue;
          sum += tex.frontLux[size_t(y) * 12 + size_t(x)];
          ++count;
        }
      }
      ASSERT_GT(count, 0);
      const Rgb& v = tex.frontLux[j * 12 + i];
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_TRUE(std::isfinite(v[ch]) && v[ch] > 0.0f) << "padding texel " << i << "," << j;
        EXPECT_NEAR(v[ch], sum[ch] / float(count), 1e-5f * sum[ch]) << "padding texel " << i << "," << j;
      }
    }
  }
}

// A wall standing on the floor, the sun (a directional light) shining at 45° from −x: the floor beyond the
// wall (x > wall) is in its shadow up to 1 m away, i.e. all of it. Texel column i = 6 covers x ∈ [0, 0.2]
// and its footprint crosses the wall; its centre lies on the shaded side. Without leak prevention a quarter
// (thin wall at x = 0.05) of its samples would see the sun; with it the texel is exactly dark. The lit
// neighbour column is exactly E·cos 45°.
void expectNoLeak(bool thickWall) {
  MeshBuilder b;
  const uint32_t black = b.material(Rgb(0.0f));
  b.ground(1.0f, 1, black);
  if (thickWall) {
    // A one-sided box x ∈ [0.03, 0.15], y ∈ [0, 1], faces outwards: the texel's centre x = 0.1 lies inside
    // it, nearer its +x face (the shaded side), where the probes move the anchor.
    b.grid(vec3(0.15f, 0.0f, -1.0f), vec3(0, 1, 0), vec3(0, 0, 2), 1, black);      // +x face
    b.grid(vec3(0.03f, 0.0f, -1.0f), vec3(0, 0, 2), vec3(0, 1, 0), 1, black);      // −x face
    b.grid(vec3(0.03f, 1.0f, -1.0f), vec3(0, 0, 2), vec3(0.12f, 0, 0), 1, black);  // top
  } else {
    b.grid(vec3(0.05f, 0.0f, -1.0f), vec3(0, 0, 2), vec3(0, 1, 0), 1, black, true);  // thin, two-sided
  }
  const Rgb lux(1000.0f, 2000.0f, 500.0f);
  b.directionalLight(vec3(-1.0f, 1.0f, 0.0f), lux);
  floorTexture(b, 0);
  const VertexLightMaps maps = bake(b.rdb, 256);
  const LightTexture& tex = maps.lightTextures[0];
  for (uint32_t j = 1; j <= 10; ++j) {
    const Rgb& shaded = tex.frontLux[j * 12 + 6];
    const Rgb& lit = tex.frontLux[j * 12 + 5];  // x ∈ [−0.2, 0]
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_EQ(shaded[ch], 0.0f) << "row " << j << (thickWall ? " (thick wall)" : " (thin wall)");
      EXPECT_NEAR(lit[ch], lux[ch] * std::sqrt(0.5f), 1e-4f * lux[ch]) << "row " << j;
    }
    for (uint32_t i = 7; i <= 10; ++i) EXPECT_EQ(tex.frontLux[j * 12 + i], Rgb(0.0f));
  }
}

TEST(TexelBaker, NoLightLeaksUnderAThinWall) {
  expectNoLeak(false);
}
TEST(TexelBaker, NoLightLeaksFromInsideAThickWall) {
  expectNoLeak(true);
}

// The floor's two triangles in separate charts: triangle 0 in the left half of a 24 × 12 atlas, triangle 1
// in the right, so their shared diagonal appears twice. Bilinear lookups along both copies agree within the
// estimates' error after the seam pass (the baked values alone differ by noise and by the different
// footprints along the two copies).
TEST(TexelBaker, LookupsOnBothSidesOfASeamAgree) {
  MeshBuilder b;
  b.ground(1.0f, 1, b.material(Rgb(0.0f)), true);  // two-sided: the back's seam too (no light: 0 = 0)
  const vec3 light(0.3f, 0.5f, -0.2f);
  b.pointLight(light, Rgb(10.0f));
  const rdb::TraceRdb& r = b.rdb;
  addLightTexture(b, 0, 24, 12, 5.0f, [&r](uint32_t t, uint32_t c) {
    const vec3& p = r.positionsM[r.indices[3 * size_t{t} + c]];
    return vec2((t == 0 ? 1.0f : 13.0f) + 5.0f * (p.x + 1.0f), 1.0f + 5.0f * (p.z + 1.0f));
  });
  const VertexLightMaps maps = bake(b.rdb, 256);
  const LightTexture& tex = maps.lightTextures[0];
  EXPECT_EQ(tex.seamEdges, 1u);
  ASSERT_EQ(tex.backLux.size(), tex.frontLux.size());
  // The diagonal from grid vertex (0, 0) at (−1, −1) to (1, 1) at (1, 1) (x, z): texel coordinates
  // (1, 1) → (11, 11) in the left chart and (13, 1) → (23, 11) in the right.
  float maxSigma = 0.0f;
  for (const Rgb& s : tex.frontStdErrorLux) maxSigma = std::max(maxSigma, s.g);
  for (int q = 0; q <= 40; ++q) {
    const float s = float(q) / 40.0f;
    const vec2 left = vec2(1.0f + 10.0f * s, 1.0f + 10.0f * s) / vec2(24.0f, 12.0f);
    const vec2 right = vec2(13.0f + 10.0f * s, 1.0f + 10.0f * s) / vec2(24.0f, 12.0f);
    const Rgb a = lookup(tex, tex.frontLux, left), c = lookup(tex, tex.frontLux, right);
    EXPECT_GT(a.g, 0.0f);
    EXPECT_LE(std::abs(a.g - c.g), 0.5f * maxSigma) << "at s = " << s << ": " << a.g << " vs " << c.g;
    EXPECT_EQ(lookup(tex, tex.backLux, left), lookup(tex, tex.backLux, right));
  }
}

// A folded sheet: a floor and a wall of 1 m × 1 m meeting at a shared edge (shared vertices, so the shading
// is continuous across it), with generated light-map UVs (rdb/lightmap_uv.h), which cut it into two charts at
// the 90° fold. Under a point light, lookups along both copies of the fold agree.
TEST(TexelBaker, GeneratedChartsAgreeAlongTheirSharedEdge) {
  MeshBuilder b;
  const uint32_t black = b.material(Rgb(0.0f));
  rdb::TraceRdb& r = b.rdb;
  // Vertices 0, 1 on the fold (x = 0 … 1, y = 0, z = 0), 2, 3 on the floor at z = 1, 4, 5 on the wall at y
  // = 1.
  r.positionsM = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, {1, 1, 0}, {0, 1, 0}};
  const vec3 diagonal = glm::normalize(vec3(0, 1, 1));
  r.normals = {diagonal, diagonal, {0, 1, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}};
  r.indices = {0, 3, 2, 0, 2, 1, 0, 1, 4, 0, 4, 5};  // floor facing +Y, wall facing +Z
  r.triangleMaterial.assign(4, black);
  r.meshes.push_back({.firstVertex = 0, .vertexCount = 6, .firstTriangle = 0, .triangleCount = 4});
  b.pointLight(vec3(0.3f, 0.6f, 0.7f), Rgb(5.0f));
  const rdb::LightmapUv uv = rdb::generateLightmapUv(r.positionsM, r.indices, {.texelsPerMetre = 16.0f});
  ASSERT_EQ(uv.chartCount, 2u);
  std::vector<vec2> cornerUv;
  for (uint32_t i : uv.indices) cornerUv.push_back(uv.uv[i]);
  addLightTexture(b, 0, uv.width, uv.height, uv.texelsPerMetre, [&](uint32_t t, uint32_t c) {
    return cornerUv[3 * t + c] * vec2(float(uv.width), float(uv.height));
  });
  const VertexLightMaps maps = bake(b.rdb, 256);
  const LightTexture& tex = maps.lightTextures[0];
  EXPECT_EQ(tex.seamEdges, 1u);
  // The fold: edge 0–1 is corners (0, 2) of triangle 1 (floor) and (0, 1) of triangle 2 (wall).
  const vec2 floor0 = cornerUv[3], floor1 = cornerUv[5], wall0 = cornerUv[6], wall1 = cornerUv[7];
  float maxSigma = 0.0f;
  for (const Rgb& e : tex.frontStdErrorLux) maxSigma = std::max(maxSigma, e.g);
  for (int q = 0; q <= 32; ++q) {
    const float s = float(q) / 32.0f;
    const Rgb a = lookup(tex, tex.frontLux, glm::mix(floor0, floor1, s));
    const Rgb c = lookup(tex, tex.frontLux, glm::mix(wall0, wall1, s));
    EXPECT_GT(a.g, 0.0f);
    EXPECT_LE(std::abs(a.g - c.g), 0.5f * maxSigma) << "at s = " << s << ": " << a.g << " vs " << c.g;
  }
}

// A triangle with zero area in texture space but not in the world (a broken TEXCOORD_1): the texel it lies
// in has nothing to sample; it is reported and filled from its neighbours.
TEST(TexelBaker, TexelsWithoutAreaAreReportedAndFilled) {
  MeshBuilder b;
  b.ground(1.0f, 1, b.material(Rgb(0.0f)));
  b.uniformSky(Rgb(1.0f));
  const rdb::TraceRdb& r = b.rdb;
  addLightTexture(b, 0, 8, 8, 5.0f, [&r](uint32_t t, uint32_t c) {
    if (t == 1) return vec2(6.5f, 6.5f);  // all three corners at one point of texel (6, 6)
    const vec3& p = r.positionsM[r.indices[3 * size_t{t} + c]];
    return vec2(1.0f + 2.0f * (p.x + 1.0f), 1.0f + 2.0f * (p.z + 1.0f));
  });
  const VertexLightMaps maps = bake(b.rdb, 64);
  const LightTexture& tex = maps.lightTextures[0];
  EXPECT_EQ(tex.emptyTexels, 1u);
  // Triangle 0 covers half of texels 1 … 4 squared: 4 diagonal texels in part, 6 below the diagonal in full.
  EXPECT_EQ(tex.bakedTexels, 10u);
  for (const Rgb& v : tex.frontLux) EXPECT_NEAR(v.g, kPiF, 0.05f * kPiF);  // uniform sky: π·L everywhere
}

// Lowering marks which meshes the bake may give an automatic light texture (raytracer/light_resolution.h)
// and gives none itself; "lightTexture": false (allowAutomatic = false) keeps a mesh out, and one asked for
// is made at once.
TEST(TexelBaker, LoweringMarksMeshesForAutomaticLightTextures) {
  sdb::Scene s;
  sdb::Mesh floor;
  floor.name = "floor";
  floor.positions = {{-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}};
  floor.indices = {0, 1, 2, 0, 2, 3};
  sdb::Mesh forbidden = floor;
  forbidden.name = "forbidden";
  forbidden.lightTexture.allowAutomatic = false;
  sdb::Mesh asked = floor;
  asked.name = "asked";
  asked.lightTexture = {true, 4.0f};
  sdb::Node node;
  node.meshes = {s.addMesh(floor).id, s.addMesh(forbidden).id, s.addMesh(asked).id};
  s.addNode(node);
  const rdb::TraceRdb r = rdb::buildTraceRdb(s);
  ASSERT_EQ(r.meshes.size(), 3u);
  EXPECT_TRUE(r.meshes[0].automaticLightTextureAllowed);
  EXPECT_FALSE(r.meshes[1].automaticLightTextureAllowed);
  EXPECT_FALSE(r.meshes[2].automaticLightTextureAllowed);
  ASSERT_EQ(r.lightTextures.size(), 1u);
  EXPECT_EQ(r.lightTextures[0].mesh, 2u);
  EXPECT_FALSE(r.lightTextures[0].automatic);
  EXPECT_EQ(r.meshes[2].lightTexture, 0u);
  EXPECT_EQ(r.lightTextures[0].texelsPerMetre, 4.0f);
}

// A scene of one mesh with TEXCOORD_1 that asks for a light texture of 10 texels/m, lowered.
rdb::TraceRdb lowerMeshWithTexcoord1(std::vector<vec3> positions, std::vector<uint32_t> indices,
                                     std::vector<vec2> uv1) {
  sdb::Scene s;
  sdb::Mesh m;
  m.name = "panel";
  m.positions = std::move(positions);
  m.indices = std::move(indices);
  m.uv1 = std::move(uv1);
  m.lightTexture = {true, 10.0f};
  sdb::Node node;
  node.meshes = {s.addMesh(m).id};
  s.addNode(node);
  return rdb::buildTraceRdb(s);
}

// TEXCOORD_1 that overlaps itself (two quads mapped onto the same square, as a mirrored texture layout does)
// cannot hold a light texture: fly warns and generates light-map UVs, which never overlap.
TEST(TexelBaker, OverlappingTexcoord1IsReplacedByGeneratedUvs) {
  const std::vector<vec2> square = {{0.1f, 0.1f}, {0.1f, 0.9f}, {0.9f, 0.9f}, {0.9f, 0.1f}};
  std::vector<vec2> uv1 = square;
  uv1.insert(uv1.end(), square.begin(), square.end());
  const rdb::TraceRdb r = lowerMeshWithTexcoord1(
      {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, {2, 0, 0}, {2, 0, 1}, {3, 0, 1}, {3, 0, 0}},
      {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7}, uv1);
  ASSERT_EQ(r.lightTextures.size(), 1u);
  const rdb::TraceLightTexture& lt = r.lightTextures[0];
  EXPECT_FALSE(lt.fromTexcoord1);
  EXPECT_EQ(lt.cornerUv.size(), 12u);
  // The generated atlas keeps the two quads apart: no corner UV of one lies inside the other's box.
  vec2 lo0(1.0f), hi0(0.0f);
  for (size_t c = 0; c < 6; ++c) {
    lo0 = glm::min(lo0, lt.cornerUv[c]);
    hi0 = glm::max(hi0, lt.cornerUv[c]);
  }
  for (size_t c = 6; c < 12; ++c) {
    const vec2 uv = lt.cornerUv[c];
    EXPECT_FALSE(uv.x > lo0.x && uv.x < hi0.x && uv.y > lo0.y && uv.y < hi0.y) << c;
  }
}

// TEXCOORD_1 is used as given: a square atlas with the requested mean density.
TEST(TexelBaker, Texcoord1IsUsedWhenPresent) {
  // 1 m², facing up, over a quarter of the atlas.
  const rdb::TraceRdb r = lowerMeshWithTexcoord1({{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {0, 1, 2, 0, 2, 3},
                                                 {{0.0f, 0.0f}, {0.0f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.0f}});
  ASSERT_EQ(r.lightTextures.size(), 1u);
  const rdb::TraceLightTexture& lt = r.lightTextures[0];
  EXPECT_TRUE(lt.fromTexcoord1);
  EXPECT_FALSE(lt.automatic);
  EXPECT_EQ(lt.width, 20u);  // 1 m over half the side at 10 texels/m
  EXPECT_EQ(lt.height, 20u);
  EXPECT_FLOAT_EQ(lt.texelsPerMetre, 10.0f);
  EXPECT_EQ(lt.cornerUv[4], vec2(0.5f, 0.5f));
}

}  // namespace
}  // namespace fly::raytracer
