// The lux probe's pure logic: pick rays through the renderer's projection, the nearest triangle hit, and the
// baked illuminance and standard error interpolated with the hit's barycentric coordinates.
#include "raster/lux_probe.h"
#include "raster/viewer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sdb/camera.h"

namespace fly::raster {
namespace {

// Baked illuminance that is an affine function of the position on the floor, E(x, z) = 200 + 40x − 25z lux
// (per channel times (1, 0.8, 0.5)): barycentric interpolation reproduces an affine function exactly, so the
// value at any point of a triangle is E at that point.
Rgb affineLux(const vec3& p) {
  const float e = 200.0f + 40.0f * p.x - 25.0f * p.z;
  return Rgb(e, 0.8f * e, 0.5f * e);
}

// Standard errors per vertex (lux per channel), different at each vertex.
Rgb vertexStdError(uint32_t v) {
  return Rgb(1.0f + float(v), 2.0f + float(v), 3.0f);
}

// A floor triangle at y = 0, (0,0,0), (2,0,0), (0,0,−3), normals +Y, with a light map (front and back, two-
// sided), and a triangle without one 1 m above it at (5, 1, 0) … out of the floor's way; store with the
// standard errors.
struct Scene {
  rdb::RasterRdb rdb;
  rdb::LightMapStore store;
};

Scene floorScene() {
  Scene s;
  rdb::RasterRdb& r = s.rdb;
  r.positionsM = {{0, 0, 0}, {2, 0, 0}, {0, 0, -3}, {5, 1, 0}, {7, 1, 0}, {5, 1, -3}};
  r.normals.assign(6, vec3(0, 1, 0));
  r.indices = {0, 1, 2, 3, 4, 5};
  rdb::RasterMesh floor;
  floor.sdbNodeId = 7;
  floor.sdbMeshId = 3;
  floor.firstVertex = 0;
  floor.vertexCount = 3;
  floor.firstIndex = 0;
  floor.indexCount = 3;
  floor.twoSided = true;
  floor.hasLightMap = true;
  rdb::RasterMesh shelf = floor;
  shelf.sdbNodeId = 8;
  shelf.firstVertex = 3;
  shelf.firstIndex = 3;
  shelf.twoSided = false;
  shelf.hasLightMap = false;
  r.meshes = {floor, shelf};
  r.variants.lightMap = true;
  rdb::MeshLightMap map;
  map.sdbNodeId = 7;
  map.sdbMeshId = 3;
  for (uint32_t v = 0; v < 6; ++v) {
    r.frontLux.push_back(v < 3 ? affineLux(r.positionsM[v]) : Rgb(0.0f));
    r.backLux.push_back(v < 3 ? Rgb(5.0f + float(v)) : Rgb(0.0f));
    if (v < 3) {
      map.frontLux.push_back(r.frontLux[v]);
      map.backLux.push_back(r.backLux[v]);
      map.frontStdErrorLux.push_back(vertexStdError(v));
      map.backStdErrorLux.push_back(Rgb(0.5f));
    }
  }
  s.store.meshes.push_back(map);
  return s;
}

PickRay down(float x, float z) {
  return PickRay{vec3(x, 4.0f, z), vec3(0, -1, 0)};
}

TEST(LuxProbe, AtAVertexReadsItsBakedValue) {
  const Scene s = floorScene();
  for (uint32_t v = 0; v < 3; ++v) {
    const vec3 p = s.rdb.positionsM[v];
    const std::optional<SurfaceHit> hit = pickSurface(s.rdb, down(p.x, p.z));
    ASSERT_TRUE(hit) << "vertex " << v;
    EXPECT_EQ(hit->mesh, 0u);
    EXPECT_NEAR(hit->barycentric[int(v)], 1.0f, 1e-6f);
    const std::optional<LuxReading> r = probeIlluminance(s.rdb, &s.store, *hit);
    ASSERT_TRUE(r);
    EXPECT_FALSE(r->back);
    EXPECT_EQ(r->sdbNodeId, 7u);
    const Rgb baked = s.rdb.frontLux[v];
    EXPECT_NEAR(r->illuminanceLux.r, baked.r, 1e-5f * baked.r);
    EXPECT_NEAR(r->illuminanceLux.g, baked.g, 1e-5f * baked.g);
    EXPECT_NEAR(r->illuminanceLux.b, baked.b, 1e-5f * baked.b);
    EXPECT_NEAR(r->illuminanceLuminanceLux, luminance(baked), 1e-5f * luminance(baked));
    ASSERT_TRUE(r->stdErrorLuminanceLux);
    EXPECT_NEAR(*r->stdErrorLuminanceLux, luminance(vertexStdError(v)), 1e-5f);
  }
}

TEST(LuxProbe, InsideATriangleInterpolatesWithBarycentrics) {
  const Scene s = floorScene();
  const vec3 p(0.5f, 0.0f, -1.0f);  // inside: x/2 + (−z)/3 = 0.583 < 1
  const std::optional<SurfaceHit> hit = pickSurface(s.rdb, down(p.x, p.z));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distanceM, 4.0f, 1e-5f);
  EXPECT_NEAR(glm::length(hit->pointWorld - p), 0.0f, 1e-5f);
  // Barycentrics by areas (independently of the probe's Möller–Trumbore): w1 = x/2, w2 = −z/3.
  const double w1 = 0.5 / 2.0, w2 = 1.0 / 3.0, w0 = 1.0 - w1 - w2;
  EXPECT_NEAR(hit->barycentric.x, w0, 1e-6);
  EXPECT_NEAR(hit->barycentric.y, w1, 1e-6);
  EXPECT_NEAR(hit->barycentric.z, w2, 1e-6);
  const std::optional<LuxReading> r = probeIlluminance(s.rdb, &s.store, *hit);
  ASSERT_TRUE(r);
  // E(0.5, −1) = 200 + 20 + 25 = 245 lux on the red channel; luminance 245 · (0.2126 + 0.7152·0.8 +
  // 0.0722·0.5).
  EXPECT_NEAR(r->illuminanceLux.r, 245.0f, 1e-3f);
  EXPECT_NEAR(r->illuminanceLuminanceLux, 245.0 * (0.2126 + 0.7152 * 0.8 + 0.0722 * 0.5), 1e-3);
  // The interpolation's standard error: √(Σ wᵢ² σᵢ²) of the vertices' luminance errors.
  const double s0 = luminance(vertexStdError(0)), s1 = luminance(vertexStdError(1)),
               s2 = luminance(vertexStdError(2));
  const double expected = std::sqrt(w0 * w0 * s0 * s0 + w1 * w1 * s1 * s1 + w2 * w2 * s2 * s2);
  ASSERT_TRUE(r->stdErrorLuminanceLux);
  EXPECT_NEAR(*r->stdErrorLuminanceLux, expected, 1e-5);
  // The panel's line: whole lux from 100 lux up, the standard error to 2 digits, relative too.
  char start[128];
  std::snprintf(start, sizeof start, "201 lux ± %.2g (%.2g %%), front, node 7 at (0.50, 0.00, -1.00) m",
                expected, 100.0 * expected / double(r->illuminanceLuminanceLux));
  EXPECT_EQ(luxReadingText(*r), start);
}

TEST(LuxProbe, FromBelowReadsTheBackOfATwoSidedMesh) {
  const Scene s = floorScene();
  const PickRay up{vec3(0.0f, -2.0f, -3.0f), vec3(0, 1, 0)};  // at vertex 2, from under the floor
  const std::optional<SurfaceHit> hit = pickSurface(s.rdb, up);
  ASSERT_TRUE(hit);
  EXPECT_TRUE(hit->back);
  const std::optional<LuxReading> r = probeIlluminance(s.rdb, &s.store, *hit);
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->back);
  EXPECT_NEAR(r->illuminanceLuminanceLux, 7.0f, 1e-4f);  // backLux of vertex 2: 5 + 2 on every channel
  ASSERT_TRUE(r->stdErrorLuminanceLux);
  EXPECT_NEAR(*r->stdErrorLuminanceLux, 0.5f, 1e-5f);
}

TEST(LuxProbe, MissesAndSurfacesWithoutLightMapsReadNothing) {
  const Scene s = floorScene();
  EXPECT_FALSE(pickSurface(s.rdb, down(1.5f, -2.0f)));  // beside the hypotenuse: outside
  EXPECT_FALSE(pickSurface(s.rdb, PickRay{vec3(0.5f, 4.0f, -1.0f), vec3(0, 1, 0)}));  // pointing away
  const std::optional<SurfaceHit> shelf = pickSurface(s.rdb, down(5.5f, -1.0f));
  ASSERT_TRUE(shelf);
  EXPECT_EQ(shelf->mesh, 1u);
  EXPECT_FALSE(probeIlluminance(s.rdb, &s.store, *shelf));
  // Without the store's standard errors the value still reads, without an error.
  const std::optional<SurfaceHit> floor = pickSurface(s.rdb, down(0.5f, -1.0f));
  ASSERT_TRUE(floor);
  const std::optional<LuxReading> r = probeIlluminance(s.rdb, nullptr, *floor);
  ASSERT_TRUE(r);
  EXPECT_FALSE(r->stdErrorLuminanceLux);
}

// A light-textured floor: the reading is the light texture filtered bilinearly at the interpolated light-map
// UV (as GL_LINEAR with GL_CLAMP_TO_EDGE), with the error √(Σ wᵢ² σᵢ²) of the independent texels (a texel
// that the clamp takes twice counts once with both weights).
TEST(LuxProbe, OnALightTextureReadsTheTexelUnderTheHit) {
  Scene s = floorScene();
  // Light-map UV u = x/2, v = −z/3 on the floor triangle: (0,0), (1,0), (0,1); a 4 × 2 texture.
  s.rdb.lightMapUv = {{0, 0}, {1, 0}, {0, 1}, {0, 0}, {0, 0}, {0, 0}};
  rdb::RasterLightTexture tex;
  tex.width = 4;
  tex.height = 2;
  rdb::MeshLightTexture stored;
  stored.width = 4;
  stored.height = 2;
  for (uint32_t t = 0; t < 8; ++t) {
    tex.frontLux.push_back(Rgb(100.0f * float(t + 1)));
    stored.frontLux.push_back(tex.frontLux.back());
    stored.frontStdErrorLux.push_back(Rgb(float(t + 1)));
  }
  s.rdb.lightTextures = {tex};
  s.rdb.meshes[0].twoSided = false;
  s.rdb.meshes[0].lightTexture = 0;
  s.store.meshes[0].lightTexture = stored;
  // (x, z) = (1.1, −0.6): u = 0.55, v = 0.2, texel-centre coordinates (1.7, −0.1): columns 1 and 2 with
  // weights 0.3 and 0.7, row 0 (the row above is clamped onto it): 0.3 · 200 + 0.7 · 300 = 270 lux,
  // error √(0.3² · 2² + 0.7² · 3²) = √4.77.
  const std::optional<SurfaceHit> hit = pickSurface(s.rdb, down(1.1f, -0.6f));
  ASSERT_TRUE(hit);
  const std::optional<LuxReading> r = probeIlluminance(s.rdb, &s.store, *hit);
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->fromLightTexture);
  EXPECT_NEAR(r->illuminanceLuminanceLux, 270.0f, 1e-2f);
  ASSERT_TRUE(r->stdErrorLuminanceLux);
  EXPECT_NEAR(*r->stdErrorLuminanceLux, std::sqrt(4.77f), 1e-4f);
  // (0.3, −1.8): u = 0.15, v = 0.6, coordinates (0.1, 0.7): texels 0, 1, 4, 5 (100, 200, 500, 600 lux ± 1,
  // 2, 5, 6) with weights 0.27, 0.03, 0.63, 0.07: 390 lux, error √(0.27² + 0.03²·4 + 0.63²·25 + 0.07²·36).
  const std::optional<LuxReading> r2 =
      probeIlluminance(s.rdb, &s.store, *pickSurface(s.rdb, down(0.3f, -1.8f)));
  ASSERT_TRUE(r2);
  EXPECT_NEAR(r2->illuminanceLuminanceLux, 390.0f, 1e-2f);
  EXPECT_NEAR(*r2->stdErrorLuminanceLux, std::sqrt(0.0729f + 0.0036f + 9.9225f + 0.1764f), 1e-4f);
  // A triangle outside the atlas (light-map UVs rdb::noLightTextureUv()) reads its vertex light map.
  for (uint32_t v = 0; v < 3; ++v) s.rdb.lightMapUv[v] = rdb::noLightTextureUv();
  const std::optional<LuxReading> r3 = probeIlluminance(s.rdb, &s.store, *hit);
  ASSERT_TRUE(r3);
  EXPECT_FALSE(r3->fromLightTexture);
  EXPECT_NEAR(r3->illuminanceLuminanceLux, luminance(affineLux(hit->pointWorld)), 1e-2f);
}

TEST(LuxProbe, TheNearestOfTwoSurfacesIsHit) {
  Scene s = floorScene();
  // Move the shelf over the floor, 1 m up: from above it hides the floor.
  for (uint32_t v = 3; v < 6; ++v) s.rdb.positionsM[v].x -= 5.0f;
  const std::optional<SurfaceHit> hit = pickSurface(s.rdb, down(0.5f, -1.0f));
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->mesh, 1u);
  EXPECT_NEAR(hit->distanceM, 3.0f, 1e-5f);
}

// pickSurfaceNear: of the hits within the limit, the one nearest the target distance, before or beyond it.
TEST(LuxProbe, NearATargetDistanceTheClosestHitWithinTheLimitIsPicked) {
  Scene s = floorScene();
  for (uint32_t v = 3; v < 6; ++v) s.rdb.positionsM[v].x -= 5.0f;  // the shelf 1 m over the floor
  const PickRay ray = down(0.5f, -1.0f);                           // the shelf at 3 m, the floor at 4 m
  const auto mesh = [&](float target, float max) {
    const std::optional<SurfaceHit> hit = pickSurfaceNear(s.rdb, ray, target, max);
    return hit ? int(hit->mesh) : -1;
  };
  EXPECT_EQ(mesh(3.4f, 10.0f), 1);
  EXPECT_EQ(mesh(3.6f, 10.0f), 0);
  EXPECT_EQ(mesh(5.0f, 10.0f), 0);
  EXPECT_EQ(mesh(3.9f, 3.5f), 1);   // the floor lies beyond the limit
  EXPECT_EQ(mesh(3.9f, 2.5f), -1);  // both do
  const std::optional<SurfaceHit> hit = pickSurfaceNear(s.rdb, ray, 3.6f, 10.0f);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distanceM, 4.0f, 1e-5f);
}

// Coincident surfaces (a floor and the underside of a block lying on it): the one whose front faces the ray
// is read, whichever comes first in the arrays.
TEST(LuxProbe, OfCoincidentSurfacesTheOneFacingTheRayIsPicked) {
  for (bool downFirst : {true, false}) {
    Scene s = floorScene();
    // The shelf lowered onto the floor and turned to face down (its back up), over the floor's triangle.
    s.rdb.positionsM[3] = {0, 0, 0};
    s.rdb.positionsM[4] = {0, 0, -3};
    s.rdb.positionsM[5] = {2, 0, 0};
    for (uint32_t v = 3; v < 6; ++v) s.rdb.normals[v] = vec3(0, -1, 0);
    if (downFirst) std::swap(s.rdb.meshes[0], s.rdb.meshes[1]);
    const std::optional<SurfaceHit> hit = pickSurfaceNear(s.rdb, down(0.5f, -1.0f), 4.0f, 10.0f);
    ASSERT_TRUE(hit);
    EXPECT_FALSE(hit->back);
    EXPECT_EQ(s.rdb.meshes[hit->mesh].sdbNodeId, 7u) << (downFirst ? "down first" : "up first");
  }
}

// A pick ray through the pixel where the renderer's projection puts a point passes through that point, and
// projectToImage finds that pixel; a point behind the eye has none.
TEST(LuxProbe, PickRayInvertsTheRenderersProjection) {
  const uint32_t w = 640, h = 360;
  View v;
  v.worldFromCamera = sdb::lookAtTransform(vec3(3, 2, 4), vec3(0, 0, -1), vec3(0, 1, 0));
  v.yfovRad = 0.9f;
  for (const bool ortho : {false, true}) {
    v.orthographic = ortho;
    v.ymagM = 2.0f;
    const float aspect = float(w) / float(h);
    const mat4 clipFromCamera =
        ortho ? glm::ortho(-v.ymagM * aspect, v.ymagM * aspect, -v.ymagM, v.ymagM, v.znearM, 100.0f)
              : glm::perspective(v.yfovRad, aspect, v.znearM, 100.0f);
    for (const vec3 p : {vec3(0.5f, 0.0f, -1.0f), vec3(-1.0f, 0.7f, 0.3f)}) {
      const vec4 clip = clipFromCamera * glm::inverse(v.worldFromCamera) * vec4(p, 1.0f);
      const double x = (clip.x / clip.w * 0.5 + 0.5) * w, y = (0.5 - clip.y / clip.w * 0.5) * h;
      const PickRay ray = pickRay(v, x, y, w, h);
      EXPECT_NEAR(glm::length(ray.dirWorld), 1.0f, 1e-6f);
      // Distance from p to the ray's line.
      const vec3 d = p - ray.originWorld;
      EXPECT_NEAR(glm::length(d - glm::dot(d, ray.dirWorld) * ray.dirWorld), 0.0f, 1e-4f)
          << (ortho ? "orthographic " : "perspective ") << p.x << "," << p.y << "," << p.z;
      EXPECT_GT(glm::dot(d, ray.dirWorld), 0.0f);
      // projectToImage is the projection itself.
      const std::optional<vec2> px = projectToImage(v, p, w, h);
      ASSERT_TRUE(px);
      EXPECT_NEAR(px->x, x, 1e-3);
      EXPECT_NEAR(px->y, y, 1e-3);
    }
  }
  v.orthographic = false;
  EXPECT_FALSE(projectToImage(v, vec3(6, 4, 9), w, h));  // behind the eye at (3, 2, 4)
}

}  // namespace
}  // namespace fly::raster
