// The sun's shadows (raster/sun_shadows.h) against shadow rays: each scene is rendered with and without the
// shadows, and every pixel whose surface faces the sun is classified as shadowed where the shadowed frame is
// darker; an exact ray–triangle test on the CPU (Möller and Trumbore 1997) traces the pixel's centre into the
// scene and a shadow ray from the point it hits towards the sun. They must agree except within one pixel of a
// shadow or geometry edge, where a neighbouring pixel shows what the rays expect (an edge may move by a pixel
// between the CPU's arithmetic and the GPU's).
#include "raster/sun_shadows.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "../support/helsinki_daylight.h"
#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/camera.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

// The casters of `r` as world triangles (glass and blended surfaces cast no shadow), and exact ray queries.
class CpuTracer {
 public:
  explicit CpuTracer(const rdb::RasterRdb& r) {
    for (uint32_t m = 0; m < r.meshes.size(); ++m) {
      const rdb::RasterMesh& mesh = r.meshes[m];
      const rdb::RasterMaterial& mat = r.materials[mesh.material];
      const bool casts =
          maxComponent(mat.transmission) == 0.0f && mat.alphaMode != rdb::RasterAlphaMode::kBlend;
      for (uint32_t i = mesh.firstIndex; i < mesh.firstIndex + mesh.indexCount; i += 3) {
        tris_.push_back({dvec3(r.positionsM[r.indices[i]]), dvec3(r.positionsM[r.indices[i + 1]]),
                         dvec3(r.positionsM[r.indices[i + 2]]), m, casts, mesh.twoSided});
      }
    }
  }
  struct Hit {
    double t;
    uint32_t triangle;
    dvec3 point, normal;  // geometric normal, unit, the triangle's winding
  };
  std::optional<Hit> first(const dvec3& o, const dvec3& d) const {
    std::optional<Hit> best;
    for (uint32_t k = 0; k < tris_.size(); ++k) {
      const double t = intersect(tris_[k], o, d);
      if (t > 0.0 && (!best || t < best->t)) best = Hit{t, k, o + t * d, {}};
    }
    if (best) {
      const Tri& tr = tris_[best->triangle];
      best->normal = glm::normalize(glm::cross(tr.b - tr.a, tr.c - tr.a));
    }
    return best;
  }
  bool occluded(const dvec3& o, const dvec3& d) const {
    return std::any_of(tris_.begin(), tris_.end(),
                       [&](const Tri& tr) { return tr.casts && intersect(tr, o, d) > 0.0; });
  }
  uint32_t mesh(uint32_t triangle) const { return tris_[triangle].mesh; }
  bool twoSided(uint32_t triangle) const { return tris_[triangle].twoSided; }

 private:
  struct Tri {
    dvec3 a, b, c;
    uint32_t mesh;
    bool casts, twoSided;
  };
  static double intersect(const Tri& tr, const dvec3& o, const dvec3& d) {
    const dvec3 e1 = tr.b - tr.a, e2 = tr.c - tr.a, p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-14) return -1.0;
    const dvec3 s = o - tr.a;
    const double u = glm::dot(s, p) / det;
    if (u < 0.0 || u > 1.0) return -1.0;
    const dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) / det;
    if (v < 0.0 || u + v > 1.0) return -1.0;
    return glm::dot(e2, q) / det;
  }
  std::vector<Tri> tris_;
};

View lookAt(const vec3& eye, const vec3& target) { return test::lookAtView(eye, target, 200.0f); }

struct MaskCheck {
  size_t lit = 0, shadowed = 0;  // pixels compared, by the rays' verdict
  size_t edgeMismatches = 0;     // disagreements within one pixel of an edge (allowed)
  size_t mismatches = 0;         // elsewhere
};

// Renders `r` from `view` in `mode` with the sun's shadows and without, and compares the shadow mask with the
// CPU's shadow rays (see the top of the file).
MaskCheck checkShadowMask(const rdb::RasterRdb& r, const View& view, RenderMode mode, uint32_t w, uint32_t h,
                          const SunShadowSettings& settings = {SunShadowMode::kVisibilityMap}) {
  Renderer renderer;
  renderer.upload(r);
  renderer.setSunShadows({SunShadowMode::kOff});
  renderer.render(view, mode, w, h);
  const std::vector<float> full = renderer.luminanceRgb();
  renderer.setSunShadows(settings);
  renderer.render(view, mode, w, h);
  const std::vector<float> shadowedImage = renderer.luminanceRgb();
  EXPECT_EQ(renderer.stats().shadowPasses, 1);

  const CpuTracer tracer(r);
  const dvec3 sun = glm::normalize(dvec3(r.sky->sunDirWorld));
  const dvec3 eye(view.worldFromCamera[3]);
  const glm::dmat3 rot(view.worldFromCamera);
  const double tanY = std::tan(0.5 * double(view.yfovRad)), aspect = double(w) / double(h);
  // Per pixel: −1 not compared (background, back faces, surfaces nearly edge-on to the sun), else the rays'
  // verdict (1 shadowed, 0 lit); and the triangle's mesh seen there.
  std::vector<int> expected(size_t(w) * h, -1), rendered(size_t(w) * h, -1);
  std::vector<int64_t> meshAt(size_t(w) * h, -1);
  for (uint32_t j = 0; j < h; ++j) {
    for (uint32_t i = 0; i < w; ++i) {
      const double x = (2.0 * (i + 0.5) / w - 1.0) * tanY * aspect, y = (1.0 - 2.0 * (j + 0.5) / h) * tanY;
      const dvec3 d = glm::normalize(rot * dvec3(x, y, -1.0));
      const auto hit = tracer.first(eye, d);
      if (!hit) continue;
      const size_t p = size_t(j) * w + i;
      meshAt[p] = hit->triangle;
      dvec3 n = hit->normal;
      if (glm::dot(n, d) > 0.0) {
        if (!tracer.twoSided(hit->triangle)) continue;  // the back of a one-sided surface shows black
        n = -n;
      }
      if (glm::dot(n, sun) < 0.2) continue;  // too little sun to tell shadow from light
      const dvec3 origin = hit->point + 1e-6 * n;
      expected[p] = tracer.occluded(origin, sun) ? 1 : 0;
      const float lFull = luminance(Rgb(full[3 * p], full[3 * p + 1], full[3 * p + 2]));
      const float lShadow =
          luminance(Rgb(shadowedImage[3 * p], shadowedImage[3 * p + 1], shadowedImage[3 * p + 2]));
      rendered[p] = lShadow < 0.95f * lFull ? 1 : 0;
    }
  }
  MaskCheck c;
  for (uint32_t j = 0; j < h; ++j) {
    for (uint32_t i = 0; i < w; ++i) {
      const size_t p = size_t(j) * w + i;
      if (expected[p] < 0) continue;
      (expected[p] ? c.shadowed : c.lit) += 1;
      if (expected[p] == rendered[p]) continue;
      // Excused only beside an edge (a neighbour differs in the rays' verdict or in what it sees) and where a
      // neighbour shows what the rays expect here: an edge moved by at most a pixel, not a missing shadow.
      bool besideEdge = false, shownNearby = false;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          const int ii = int(i) + di, jj = int(j) + dj;
          if (ii < 0 || jj < 0 || ii >= int(w) || jj >= int(h)) continue;
          const size_t q = size_t(jj) * w + size_t(ii);
          besideEdge |= expected[q] != expected[p] || meshAt[q] != meshAt[p];
          shownNearby |= rendered[q] == expected[p];
        }
      }
      const bool nearEdge = besideEdge && shownNearby;
      (nearEdge ? c.edgeMismatches : c.mismatches) += 1;
      if (!nearEdge && c.mismatches <= 5) {
        ADD_FAILURE() << "pixel " << i << "," << j << ": rays say " << (expected[p] ? "shadowed" : "lit")
                      << ", the frame " << (rendered[p] ? "shadowed" : "lit");
      }
    }
  }
  return c;
}

// A scene with daylight (Helsinki, clear sky) whose sun is then turned to `sunDir`.
rdb::RasterRdb withSun(const sdb::Scene& scene, const vec3& sunDir) {
  rdb::RasterRdb r = rdb::buildRasterRdb(scene, nullptr, {32, 16});
  EXPECT_TRUE(r.variants.sun);
  r.sky->sunDirWorld = glm::normalize(sunDir);
  return r;
}

sdb::Mesh ground(float halfM, sdb::MaterialId material) {
  sdb::Mesh g;
  g.name = "ground";
  g.positions = {{-halfM, 0, -halfM}, {halfM, 0, -halfM}, {halfM, 0, halfM}, {-halfM, 0, halfM}};
  g.normals.assign(4, vec3(0, 1, 0));
  g.indices = {0, 2, 1, 0, 3, 2};
  g.material = material;
  return g;
}

// A fence of 24 bars, 2.5 cm square and 1.5 m tall, 16 cm apart, on a 10 m ground: with a 64² visibility map
// (texels ≈ 22 cm) every bar is far below a texel, so the map alone would miss most of them. Beside it a
// 2 × 2 m slab 1 m up with a 2 cm cube on the ground under it (in the sun's view: the slab hides it).
sdb::Scene fence(sdb::MaterialId* material = nullptr) {
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.6f);
  const sdb::MaterialId mat = s.addMaterial(m).id;
  if (material) *material = mat;
  s.addNode({.name = "ground", .meshes = {s.addMesh(ground(5.0f, mat)).id}});
  for (int k = 0; k < 24; ++k) {
    const float x = -1.9f + 0.16f * float(k);
    s.addNode(
        {.name = "bar",
         .meshes = {s.addMesh(test::box(vec3(x, 0.0f, -0.0125f), vec3(x + 0.025f, 1.5f, 0.0125f), mat)).id}});
  }
  s.addNode({.name = "slab",
             .meshes = {s.addMesh(test::box(vec3(-3.0f, 1.0f, 1.0f), vec3(-1.0f, 1.1f, 3.0f), mat)).id}});
  s.addNode(
      {.name = "cube",
       .meshes = {s.addMesh(test::box(vec3(-1.91f, 0.0f, 2.39f), vec3(-1.89f, 0.02f, 2.41f), mat)).id}});
  fly::test::setHelsinkiClearSky(s, "2026-06-21T13:00");
  return s;
}

TEST(SunShadows, FenceOfSubTexelBarsCastsEveryBarsShadow) {
  context();
  const rdb::RasterRdb r = withSun(fence(), vec3(0.3f, 0.8f, -0.6f));
  const MaskCheck c = checkShadowMask(r, lookAt(vec3(0.5f, 4.0f, 5.0f), vec3(0.0f, 0.0f, 1.0f)),
                                      RenderMode::kSimple, 320, 180, {SunShadowMode::kVisibilityMap, 64});
  EXPECT_EQ(c.mismatches, 0u);
  EXPECT_GT(c.shadowed, 500u);  // 24 stripes
  EXPECT_GT(c.lit, 1000u);
  EXPECT_LT(c.edgeMismatches, (c.shadowed + c.lit) / 10);
}

// The same fence's counts: every bar is kept (its sun-facing triangles; its averted ones cannot be seen in a
// closed, outward mesh), although the map shows few of them; the cube under the slab is not (its footprint
// lies where the map shows the slab's top, nearer the sun).
TEST(SunShadows, SubTexelTrianglesThatCanBeSeenAreKept) {
  context();
  const rdb::RasterRdb r = withSun(fence(), vec3(0.3f, 0.8f, -0.6f));
  Renderer renderer;
  renderer.upload(r);
  renderer.setSunShadows({SunShadowMode::kVisibilityMap, 64});
  renderer.render(lookAt(vec3(0.5f, 4.0f, 5.0f), vec3(0.0f, 0.0f, 1.0f)), RenderMode::kSimple, 64, 36);
  const SunShadowCounts c = renderer.sunShadowCounts();
  EXPECT_EQ(c.casterTriangles, 2u + 24u * 12u + 2u * 12u);
  // Square texels over the casters' bounds seen from the sun: at least the ground's 10 m across, at most the
  // bounding box's diagonal.
  EXPECT_GE(c.texelSizeM, 10.0f / 64.0f);
  EXPECT_LE(c.texelSizeM, 1.002f * std::sqrt(200.0f + 1.5f * 1.5f) / 64.0f);
  // Each bar faces the sun with 3 of its faces (top, +x, −z): 6 triangles; the slab 6, the ground 2.
  EXPECT_EQ(c.keptTriangles, 24u * 6u + 6u + 2u);
  EXPECT_LT(c.visibleTriangles, c.keptTriangles);
  // Each box's silhouette: the 6 edges between its sun-facing and averted faces; the ground's 4 open edges.
  EXPECT_EQ(c.silhouetteEdges, 25u * 6u + 4u);
  EXPECT_EQ(c.sideTriangles, c.silhouetteEdges);
}

// An open quad through four corners (two triangles, wound p0 p1 p2 and p0 p2 p3).
sdb::Mesh quad(const vec3& p0, const vec3& p1, const vec3& p2, const vec3& p3, sdb::MaterialId material) {
  sdb::Mesh m;
  m.name = "quad";
  m.positions = {p0, p1, p2, p3};
  const vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
  m.normals = {n, n, n, n};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  return m;
}

// The sun-lit sliver (the house's living room): a 2 × H m wall, an open quad facing the sun (at 45°, from
// +z), under a slab at its top's height that starts 4 cm in front of it, so the sun sees only a strip of the
// wall 4 cm high along its top, 2.8 cm across in the sun's view — far thinner than a texel (64² over the 8 m
// ground: about 15 cm), beside the slab on one side and the floor behind the wall, which the sun sees past
// the wall's top, on the other. The wall is large (its projected inradius is some 2 texels), so without the
// depth test it was dropped whenever no texel centre fell in the strip, and its shadow — a streak 4 cm wide
// on the floor behind it — went missing. Five heights move the strip across the texel rows.
TEST(SunShadows, SunLitSliverOfALargeWallKeepsItsShadow) {
  context();
  for (int k = 0; k < 5; ++k) {
    const float heightM = 1.0f + 0.03f * float(k);
    sdb::Scene s;
    sdb::Material m;
    m.diffuseColor = Rgb(0.6f);
    const sdb::MaterialId mat = s.addMaterial(m).id;
    s.addNode({.name = "ground", .meshes = {s.addMesh(ground(4.0f, mat)).id}});
    s.addNode({.name = "wall",
               .meshes = {s.addMesh(quad(vec3(-1.0f, 0.0f, 0.0f), vec3(1.0f, 0.0f, 0.0f),
                                         vec3(1.0f, heightM, 0.0f), vec3(-1.0f, heightM, 0.0f), mat))
                              .id}});
    s.addNode({.name = "slab",
               .meshes = {s.addMesh(quad(vec3(-1.5f, heightM, 0.04f), vec3(-1.5f, heightM, 2.0f),
                                         vec3(1.5f, heightM, 2.0f), vec3(1.5f, heightM, 0.04f), mat))
                              .id}});
    fly::test::setHelsinkiClearSky(s, "2026-06-21T13:00");
    const rdb::RasterRdb r = withSun(s, vec3(0.0f, 1.0f, 1.0f));
    const View view = lookAt(vec3(0.0f, 1.5f, -2.6f), vec3(0.0f, 0.0f, -1.0f));
    const MaskCheck c =
        checkShadowMask(r, view, RenderMode::kSimple, 320, 180, {SunShadowMode::kVisibilityMap, 64});
    EXPECT_EQ(c.mismatches, 0u) << "wall " << heightM << " m high";
    EXPECT_GT(c.shadowed, 1000u);
    EXPECT_GT(c.lit, 1000u);
  }
}

// A closed car-like body (a box with a cabin on top) with seats, a dashboard and a steering column inside it,
// and wheels under it, on the ground. The interior is out of the sun's sight: the map prunes it, where the
// classic method keeps every sun-facing triangle, interior ones included.
sdb::Scene car() {
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f);
  const sdb::MaterialId mat = s.addMaterial(m).id;
  s.addNode({.name = "ground", .meshes = {s.addMesh(ground(8.0f, mat)).id}});
  // The body: one closed mesh, the lower box and the cabin sharing no vertices but closed each.
  sdb::Mesh body = test::box(vec3(-2.0f, 0.3f, -0.9f), vec3(2.0f, 1.0f, 0.9f), mat);
  const sdb::Mesh cabin = test::box(vec3(-1.0f, 1.0f, -0.8f), vec3(1.2f, 1.6f, 0.8f), mat);
  const uint32_t base = uint32_t(body.positions.size());
  body.positions.insert(body.positions.end(), cabin.positions.begin(), cabin.positions.end());
  body.normals.insert(body.normals.end(), cabin.normals.begin(), cabin.normals.end());
  for (uint32_t i : cabin.indices) body.indices.push_back(base + i);
  s.addNode({.name = "body", .meshes = {s.addMesh(body).id}});
  for (float z : {-0.5f, 0.5f}) {
    for (float x : {-0.6f, 0.5f}) {
      s.addNode(
          {.name = "seat",
           .meshes = {
               s.addMesh(test::box(vec3(x, 0.4f, z - 0.25f), vec3(x + 0.5f, 1.3f, z + 0.25f), mat)).id}});
    }
  }
  s.addNode({.name = "dashboard",
             .meshes = {s.addMesh(test::box(vec3(1.3f, 0.5f, -0.8f), vec3(1.6f, 0.9f, 0.8f), mat)).id}});
  s.addNode({.name = "column",
             .meshes = {s.addMesh(test::box(vec3(1.1f, 0.6f, -0.45f), vec3(1.3f, 0.95f, -0.35f), mat)).id}});
  for (float z : {-0.95f, 0.75f}) {
    for (float x : {-1.6f, 1.1f}) {
      s.addNode({.name = "wheel",
                 .meshes = {s.addMesh(test::box(vec3(x, 0.0f, z), vec3(x + 0.5f, 0.6f, z + 0.2f), mat)).id}});
    }
  }
  fly::test::setHelsinkiClearSky(s, "2026-06-21T13:00");
  return s;
}

TEST(SunShadows, ClosedCarWithInteriorMatchesShadowRaysAndPrunesTheInterior) {
  context();
  const rdb::RasterRdb r = withSun(car(), vec3(-0.5f, 0.7f, 0.5f));
  const View view = lookAt(vec3(-6.0f, 3.5f, -5.0f), vec3(0.0f, 0.3f, 0.5f));
  const MaskCheck c = checkShadowMask(r, view, RenderMode::kSunlight, 320, 180);
  EXPECT_EQ(c.mismatches, 0u);
  EXPECT_GT(c.shadowed, 1000u);
  EXPECT_GT(c.lit, 1000u);
  EXPECT_LT(c.edgeMismatches, (c.shadowed + c.lit) / 10);
  // The classic method (the default) too.
  const MaskCheck k = checkShadowMask(r, view, RenderMode::kSunlight, 320, 180, {SunShadowMode::kSunFacing});
  EXPECT_EQ(k.mismatches, 0u);
  EXPECT_LT(k.edgeMismatches, (k.shadowed + k.lit) / 10);

  SunShadowCounts counts[2];
  uint64_t fill[2];
  for (int classic = 0; classic < 2; ++classic) {
    Renderer renderer;
    renderer.upload(r);
    renderer.setSunShadows({classic ? SunShadowMode::kSunFacing : SunShadowMode::kVisibilityMap, 1024});
    renderer.render(view, RenderMode::kSunlight, 160, 90);
    counts[classic] = renderer.sunShadowCounts();
    fill[classic] = renderer.shadowVolumeFill();
  }
  // 2 + 12 · (2 body parts + 4 seats + dashboard + column + 4 wheels).
  EXPECT_EQ(counts[0].casterTriangles, 2u + 12u * 12u);
  // Classic: every sun-facing triangle, 6 of each box, the interior's too; its silhouette the ground's 4 open
  // edges and 6 per box. Pruned: the ground, the body's two boxes and all four wheels, each box's whole
  // sun-facing side (closed shells): the two wheels on the sun's side are seen, the other two, hidden under
  // the body's far side, poke out 5 cm beyond it within √2 texels of the ground the sun sees past the body,
  // and the depth test keeps them (it cannot tell them from a sun-lit sliver). The interior is dropped.
  EXPECT_EQ(counts[1].keptTriangles, 2u + 6u * 12u);
  EXPECT_EQ(counts[1].silhouetteEdges, 4u + 6u * 12u);
  EXPECT_EQ(counts[0].keptTriangles, 2u + 6u * 6u);
  EXPECT_EQ(counts[0].silhouetteEdges, 4u + 6u * 6u);
  EXPECT_LT(fill[0], fill[1]);
  EXPECT_GT(fill[0], 0u);
}

// The camera stands in the car's shadow, inside its shadow volume, looking at the car and the ground behind
// it (z-fail counts only what lies behind the visible surface; z-pass would be wrong here).
TEST(SunShadows, CameraInsideAShadowVolume) {
  context();
  const rdb::RasterRdb r = withSun(car(), vec3(-0.5f, 0.7f, 0.5f));
  const vec3 eye(2.2f, 0.4f, -0.4f);
  const CpuTracer tracer(r);
  ASSERT_TRUE(tracer.occluded(dvec3(eye), glm::normalize(dvec3(r.sky->sunDirWorld))));
  const View inside = lookAt(eye, vec3(4.5f, 0.0f, -2.5f));
  const MaskCheck c = checkShadowMask(r, inside, RenderMode::kSimple, 320, 180);
  EXPECT_EQ(c.mismatches, 0u);
  EXPECT_GT(c.shadowed, 1000u);
  EXPECT_GT(c.lit, 1000u);
  EXPECT_EQ(checkShadowMask(r, inside, RenderMode::kSimple, 320, 180, {SunShadowMode::kSunFacing}).mismatches, 0u);
  // The stencil pass took z-fail here (the near plane lies in a volume), z-pass from the sunlit viewpoint.
  Renderer renderer;
  renderer.upload(r);
  renderer.render(inside, RenderMode::kSimple, 160, 90);
  EXPECT_TRUE(renderer.sunShadowCounts().lastFrameZFail);
  renderer.render(lookAt(vec3(-6.0f, 3.5f, -5.0f), vec3(0.0f, 0.3f, 0.5f)), RenderMode::kSimple, 160, 90);
  EXPECT_FALSE(renderer.sunShadowCounts().lastFrameZFail);
}

// An open roof on four posts: one-sided panels facing down (a ceiling: the sun sees their backs, and they
// block it all the same) and a two-sided awning, over a ground that is lit around their shadows.
TEST(SunShadows, OpenRoofAndTwoSidedAwningShadowFromEitherSide) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f);
  const sdb::MaterialId mat = s.addMaterial(m).id;
  s.addNode({.name = "ground", .meshes = {s.addMesh(ground(8.0f, mat)).id}});
  sdb::Mesh roof;
  roof.name = "ceiling";
  roof.positions = {{-1.5f, 2.5f, -1.0f}, {1.5f, 2.5f, -1.0f}, {1.5f, 2.5f, 1.0f}, {-1.5f, 2.5f, 1.0f}};
  roof.normals.assign(4, vec3(0, -1, 0));
  roof.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from below
  roof.material = mat;
  s.addNode({.name = "roof", .meshes = {s.addMesh(roof).id}});
  for (float x : {-1.4f, 1.3f}) {
    for (float z : {-0.9f, 0.8f}) {
      s.addNode({.name = "post",
                 .meshes = {s.addMesh(test::box(vec3(x, 0.0f, z), vec3(x + 0.1f, 2.5f, z + 0.1f), mat)).id}});
    }
  }
  sdb::Mesh awning = test::quadXY(mat);  // 2 × 1 m, tilted 30° from vertical, beside the roof
  awning.twoSided = true;
  s.addNode({.name = "awning",
             .parentFromLocal = glm::translate(mat4(1.0f), vec3(3.0f, 1.8f, 0.0f)) *
                                glm::rotate(mat4(1.0f), float(kPi / 3.0), vec3(1, 0, 0)),
             .meshes = {s.addMesh(awning).id}});
  fly::test::setHelsinkiClearSky(s, "2026-06-21T13:00");
  for (const vec3& sun : {vec3(0.4f, 0.8f, 0.3f), vec3(-0.3f, 0.6f, -0.5f)}) {
    const rdb::RasterRdb r = withSun(s, sun);
    // Both methods: the visibility map's and the classic one (the default), which must keep the ceiling's
    // triangles although their fronts face away from the sun.
    for (const SunShadowMode mode : {SunShadowMode::kVisibilityMap, SunShadowMode::kSunFacing}) {
      const MaskCheck c = checkShadowMask(r, lookAt(vec3(-2.0f, 6.0f, 7.0f), vec3(0.8f, 0.0f, 0.0f)),
                                          RenderMode::kSimple, 320, 180, {mode});
      EXPECT_EQ(c.mismatches, 0u) << "sun " << sun.x << "," << sun.y << "," << sun.z << ", mode " << int(mode);
      EXPECT_GT(c.shadowed, 1000u);
      EXPECT_GT(c.lit, 1000u);
    }
  }
}

// Clear glass casts no shadow (its T(θ) is not drawn): a pane between the sun and the ground leaves it lit.
TEST(SunShadows, ClearGlassCastsNoShadow) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f);
  const sdb::MaterialId mat = s.addMaterial(m).id;
  sdb::Material glass;
  glass.diffuseColor = Rgb(0.0f);
  glass.reflectionColor = Rgb(1.0f);
  glass.transmissionColor = Rgb(0.9f);
  glass.transmissionGlossiness = 0.0f;
  const sdb::MaterialId glassId = s.addMaterial(glass).id;
  s.addNode({.name = "ground", .meshes = {s.addMesh(ground(5.0f, mat)).id}});
  s.addNode({.name = "post",
             .meshes = {s.addMesh(test::box(vec3(0.5f, 0, 0.5f), vec3(1.0f, 2.0f, 1.0f), mat)).id}});
  sdb::Mesh pane = test::quadXY(glassId);
  s.addNode({.name = "pane",
             .parentFromLocal = glm::translate(mat4(1.0f), vec3(-1.0f, 1.5f, 0.0f)) *
                                glm::rotate(mat4(1.0f), float(-kPi / 2.0), vec3(1, 0, 0)),
             .meshes = {s.addMesh(pane).id}});
  fly::test::setHelsinkiClearSky(s, "2026-06-21T13:00");
  const rdb::RasterRdb r = withSun(s, vec3(0.4f, 0.8f, 0.4f));
  ASSERT_TRUE(r.variants.glass);
  const MaskCheck c = checkShadowMask(r, lookAt(vec3(0.0f, 6.0f, 5.0f), vec3(0.0f, 0.0f, 0.0f)),
                                      RenderMode::kSimple, 320, 180);
  EXPECT_EQ(c.mismatches, 0u);
  EXPECT_GT(c.shadowed, 100u);  // the post's shadow
  EXPECT_GT(c.lit, 1000u);

  // Glass alone: nothing casts, nothing is drawn.
  sdb::Scene panes;
  panes.addNode({.name = "pane", .meshes = {panes.addMesh(test::quadXY(panes.addMaterial(glass).id)).id}});
  fly::test::setHelsinkiClearSky(panes, "2026-06-21T13:00");
  const rdb::RasterRdb g = withSun(panes, vec3(0.2f, 0.9f, 0.3f));
  Renderer renderer;
  renderer.upload(g);
  renderer.render(lookAt(vec3(0.0f, 1.0f, 4.0f), vec3(0.0f)), RenderMode::kSimple, 64, 36);
  EXPECT_EQ(renderer.stats().shadowBuilds, 1);
  EXPECT_EQ(renderer.sunShadowCounts().casterTriangles, 0u);
  EXPECT_EQ(renderer.sunShadowCounts().keptTriangles, 0u);
}

// The volumes are built once per sun direction (and geometry), nothing without a sun above the horizon.
TEST(SunShadows, BuiltOnlyWhenTheSunMovesAndNeverWithoutASun) {
  context();
  rdb::RasterRdb r = withSun(fence(), vec3(0.3f, 0.8f, -0.6f));
  Renderer renderer;
  renderer.upload(r);
  const View view = lookAt(vec3(0.5f, 4.0f, 5.0f), vec3(0.0f, 0.0f, 1.0f));
  renderer.render(view, RenderMode::kSimple, 64, 36);
  renderer.render(view, RenderMode::kSunlight, 64, 36);
  EXPECT_EQ(renderer.stats().shadowBuilds, 1);
  EXPECT_EQ(renderer.stats().shadowGeometryUploads, 1);
  EXPECT_EQ(renderer.stats().shadowPasses, 2);
  r.sky->sunDirWorld = glm::normalize(vec3(0.35f, 0.8f, -0.6f));
  renderer.render(view, RenderMode::kSimple, 64, 36);
  EXPECT_EQ(renderer.stats().shadowBuilds, 2);
  EXPECT_EQ(renderer.stats().shadowGeometryUploads, 1);

  // A material edit that leaves the casters as they are rebuilds nothing; one that turns them to glass
  // re-makes the caster tables (now empty).
  sdb::MaterialId paint;
  sdb::Scene scene = fence(&paint);
  rdb::RasterRdb edited = withSun(scene, vec3(0.3f, 0.8f, -0.6f));
  Renderer editing;
  editing.upload(edited);
  editing.render(view, RenderMode::kSimple, 64, 36);
  sdb::Material m = scene.material(paint);
  m.diffuseColor = Rgb(0.3f);
  editing.update(edited, rdb::updateRasterRdb(edited, scene, scene.setMaterial(paint, m), nullptr, {32, 16}));
  editing.render(view, RenderMode::kSimple, 64, 36);
  EXPECT_EQ(editing.stats().materialBlockUploads, 1);
  EXPECT_EQ(editing.stats().shadowGeometryUploads, 1);
  EXPECT_EQ(editing.stats().shadowBuilds, 1);
  m.transmissionColor = Rgb(0.9f);
  m.transmissionGlossiness = 0.0f;
  editing.update(edited, rdb::updateRasterRdb(edited, scene, scene.setMaterial(paint, m), nullptr, {32, 16}));
  editing.render(view, RenderMode::kSimple, 64, 36);
  EXPECT_EQ(editing.stats().shadowGeometryUploads, 2);
  EXPECT_EQ(editing.stats().shadowBuilds, 2);
  EXPECT_EQ(editing.sunShadowCounts().casterTriangles, 0u);

  sdb::Scene night = fence();
  fly::test::setHelsinkiClearSky(night, "2026-12-21T23:00");
  const rdb::RasterRdb n = rdb::buildRasterRdb(night, nullptr, {32, 16});
  ASSERT_FALSE(n.variants.sun);
  Renderer dark;
  dark.upload(n);
  dark.render(view, RenderMode::kSunlight, 64, 36);
  dark.render(view, RenderMode::kSimple, 64, 36);
  EXPECT_EQ(dark.stats().shadowBuilds, 0);
  EXPECT_EQ(dark.stats().shadowPasses, 0);
  for (const std::string& p : dark.stats().programs) EXPECT_EQ(p.find("shadow"), std::string::npos) << p;
}

}  // namespace
}  // namespace fly::raster
