#include "raytracer/embree_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "raytracer/sampler.h"
#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

void addTriangle(rdb::TraceRdb& rdb, const vec3& a, const vec3& b, const vec3& c) {
  const auto first = static_cast<uint32_t>(rdb.positionsM.size());
  rdb.positionsM.insert(rdb.positionsM.end(), {a, b, c});
  rdb.indices.insert(rdb.indices.end(), {first, first + 1, first + 2});
  rdb.triangleMaterial.push_back(0);
}

// A quad a b c d, counter-clockwise seen from its front.
void addQuad(rdb::TraceRdb& rdb, const vec3& a, const vec3& b, const vec3& c, const vec3& d) {
  addTriangle(rdb, a, b, c);
  addTriangle(rdb, a, c, d);
}

// A square ground at y = 0 from −halfM to halfM, facing +Y.
void addGround(rdb::TraceRdb& rdb, float halfM) {
  addQuad(rdb, vec3(-halfM, 0, -halfM), vec3(-halfM, 0, halfM), vec3(halfM, 0, halfM),
          vec3(halfM, 0, -halfM));
}

// An axis-aligned box from lo to hi with its faces towards its inside (inward = true) or outside.
void addBox(rdb::TraceRdb& rdb, const vec3& lo, const vec3& hi, bool inward) {
  const vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                     {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  // Outward counter-clockwise faces: −z, +z, −x, +x, −y, +y.
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 4, 7, 3},
                           {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}};
  for (const auto& f : faces) {
    if (inward) {
      addQuad(rdb, c[f[0]], c[f[3]], c[f[2]], c[f[1]]);
    } else {
      addQuad(rdb, c[f[0]], c[f[1]], c[f[2]], c[f[3]]);
    }
  }
}

TEST(EmbreeScene, IntersectReportsTriangleBarycentricsNormalDistance) {
  rdb::TraceRdb rdb;
  addTriangle(rdb, vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0));  // in z = 0, front towards +z
  const EmbreeScene scene(rdb);
  const std::optional<Hit> hit = scene.intersect(vec3(0.25f, 0.5f, 2.0f), vec3(0, 0, -1), kInf);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->triangle, 0u);
  EXPECT_NEAR(hit->barycentric.x, 0.25f, 1e-6f);
  EXPECT_NEAR(hit->barycentric.y, 0.5f, 1e-6f);
  EXPECT_NEAR(hit->distanceM, 2.0f, 1e-6f);
  EXPECT_EQ(hit->geometricNormal, vec3(0, 0, 1));
  EXPECT_NEAR(scene.triangleAreaM2(0), 0.5f, 1e-7f);

  EXPECT_FALSE(scene.intersect(vec3(0.25f, 0.5f, 2.0f), vec3(0, 0, -1), 1.5f).has_value());
  EXPECT_FALSE(scene.intersect(vec3(0.25f, 0.5f, 2.0f), vec3(0, 0, 1), kInf).has_value());
  EXPECT_FALSE(scene.intersect(vec3(2.0f, 2.0f, 2.0f), vec3(0, 0, -1), kInf).has_value());
  EXPECT_TRUE(scene.occluded(vec3(0.25f, 0.5f, 2.0f), vec3(0, 0, -1), kInf));
  EXPECT_TRUE(scene.occluded(vec3(0.25f, 0.5f, 2.0f), vec3(0, 0, -1), 2.5f));
  EXPECT_FALSE(scene.occluded(vec3(0.25f, 0.5f, 2.0f), vec3(0, 0, -1), 1.5f));
  // Back faces block too.
  EXPECT_TRUE(scene.occluded(vec3(0.25f, 0.5f, -2.0f), vec3(0, 0, 1), kInf));
}

TEST(EmbreeScene, DegenerateTrianglesAreNeverHit) {
  rdb::TraceRdb rdb;
  addTriangle(rdb, vec3(0, 0, 0), vec3(0, 0, 0), vec3(0, 0, 0));      // a point
  addTriangle(rdb, vec3(-1, 0, 0), vec3(0, 0, 0), vec3(1, 0, 0));     // collinear
  addTriangle(rdb, vec3(-1, -1, 0), vec3(1, -1, 0), vec3(1, -1, 0));  // repeated vertex
  const float nan = std::numeric_limits<float>::quiet_NaN();
  addTriangle(rdb, vec3(nan, 0, 0), vec3(1, 1, 0), vec3(0, 1, 0));  // non-finite
  addTriangle(rdb, vec3(-1, 2, 0), vec3(1, 2, 0), vec3(0, 3, 0));   // a valid one
  const EmbreeScene scene(rdb);
  EXPECT_EQ(scene.validTriangleCount(), 1u);
  for (uint32_t t = 0; t < 4; ++t) {
    EXPECT_EQ(scene.triangleNormal(t), vec3(0.0f));
    EXPECT_EQ(scene.triangleAreaM2(t), 0.0f);
  }
  RandomSampler sampler(7);
  for (uint32_t i = 0; i < 4096; ++i) {
    sampler.startSample(i);
    const vec3 d = sampleUniformSphere(sampler.next2D());
    const std::optional<Hit> hit = scene.intersect(vec3(0.0f, 0.0f, 0.5f) - 0.5f * d, d, kInf);
    if (hit) {
      EXPECT_EQ(hit->triangle, 4u);
      EXPECT_TRUE(isFinite(hit->geometricNormal) && std::isfinite(hit->distanceM));
    }
  }
  const std::optional<Hit> valid = scene.intersect(vec3(0, 2.5f, 1), vec3(0, 0, -1), kInf);
  ASSERT_TRUE(valid.has_value());
  EXPECT_EQ(valid->triangle, 4u);
}

TEST(EmbreeScene, EmptySceneMisses) {
  rdb::TraceRdb rdb;
  addTriangle(rdb, vec3(0, 0, 0), vec3(1, 0, 0), vec3(2, 0, 0));
  const EmbreeScene scene(rdb);
  EXPECT_EQ(scene.validTriangleCount(), 0u);
  EXPECT_FALSE(scene.intersect(vec3(0, 1, 0), vec3(0, -1, 0), kInf).has_value());
  EXPECT_FALSE(scene.occluded(vec3(0, 1, 0), vec3(0, -1, 0), kInf));
}

// Rays leaving a surface point, moved off by rayOffsetM, never hit the surface they leave: on a 10 km ground
// near its far corner at grazing angles down to 0.01°, and inside and on a 1 mm box.
TEST(EmbreeScene, OffsetRaysDoNotSelfIntersect10KmGroundAnd1MmBox) {
  rdb::TraceRdb rdb;
  addGround(rdb, 5000.0f);
  addBox(rdb, vec3(-0.0005f, 0.0f, -0.0005f), vec3(0.0005f, 0.001f, 0.0005f), false);
  addBox(rdb, vec3(2.0f, 1.0f, 2.0f), vec3(2.001f, 1.001f, 2.001f), true);  // closed, faces inward
  const EmbreeScene scene(rdb);

  // Ground points from the origin to near the corner; directions at elevations from 0.01° to 90°.
  const vec3 up(0, 1, 0);
  int groundHits = 0;
  for (float x : {0.0f, 0.37f, 123.4f, 2500.3f, 4999.0f}) {
    for (float z : {0.0f, -0.61f, 777.7f, -4999.0f}) {
      const vec3 p(x, 0.0f, z);
      if (maxAbs(p) < 0.01f) continue;  // under the 1 mm box
      const vec3 origin = offsetRayOrigin(p, up, scene.triangleMagnitudeM(0));
      for (float elevationDeg : {0.01f, 0.1f, 0.5f, 5.0f, 45.0f, 90.0f}) {
        for (int k = 0; k < 16; ++k) {
          const float e = static_cast<float>(degToRad(elevationDeg));
          const float azimuth = 2.0f * kPiF * static_cast<float>(k) / 16.0f;
          const vec3 d(std::cos(e) * std::cos(azimuth), std::sin(e), std::cos(e) * std::sin(azimuth));
          // A ray from the far corner towards the origin passes over the 1 mm box; anything else hit is the
          // ground.
          const std::optional<Hit> hit = scene.intersect(origin, d, kInf);
          if (hit && hit->triangle < 2) ++groundHits;
        }
      }
    }
  }
  EXPECT_EQ(groundHits, 0);

  // Every face of the outside-facing 1 mm box (triangles 2 … 13): rays over its front hemisphere miss it.
  RandomSampler sampler(3);
  int selfHits = 0;
  int innerWrong = 0;
  for (uint32_t t = 2; t < 26; ++t) {
    const vec3& p0 = rdb.positionsM[rdb.indices[3 * t]];
    const vec3& p1 = rdb.positionsM[rdb.indices[3 * t + 1]];
    const vec3& p2 = rdb.positionsM[rdb.indices[3 * t + 2]];
    const vec3 n = scene.triangleNormal(t);
    const Onb frame = onb(n);
    for (uint32_t i = 0; i < 4096; ++i) {
      sampler.startSample(t * 4096 + i);
      const vec3 b = sampleUniformTriangle(sampler.next2D());
      const vec3 p = b.x * p0 + b.y * p1 + b.z * p2;
      const vec3 d = frame.toWorld(sampleCosineHemisphere(sampler.next2D()));
      const vec3 origin = offsetRayOrigin(p, n, scene.triangleMagnitudeM(t));
      const std::optional<Hit> hit = scene.intersect(origin, d, kInf);
      if (t < 14) {
        // Outside-facing box on the ground: a ray may hit only the ground.
        if (hit && hit->triangle >= 2) ++selfHits;
      } else {
        // Inside the closed box: a ray must hit another face of it within 2 mm (at distance 0 where it leaves
        // a point on an edge through the wall beyond that edge), never leak out.
        if (!hit || hit->triangle < 14 || hit->triangle == t || !(hit->distanceM >= 0.0f) ||
            hit->distanceM > 0.002f) {
          ++innerWrong;
        }
      }
    }
  }
  EXPECT_EQ(selfHits, 0);
  EXPECT_EQ(innerWrong, 0);

  // A point exactly on the inner edge between the closed box's top face and its −x wall, leaving the top face
  // away from the wall: it must not hit the wall at t = 0.
  const vec3 onEdge(2.0f, 1.001f, 2.0003f);
  const vec3 d = glm::normalize(vec3(0.49f, -0.8f, -0.34f));
  const std::optional<Hit> hit = scene.intersect(offsetRayOrigin(onEdge, vec3(0, -1, 0), 2.001f), d, kInf);
  ASSERT_TRUE(hit.has_value());
  EXPECT_GT(hit->distanceM, 1e-4f);
}

TEST(EmbreeScene, OffsetScalesWithMagnitude) {
  EXPECT_FLOAT_EQ(rayOffsetM(5000.0f), 5000.0f * 0x1p-19f);
  EXPECT_GT(rayOffsetM(0.0f), 0.0f);
  EXPECT_LT(rayOffsetM(0.001f), 1e-8f);
  // The offset moves a point at 5 km by at least 16 ulps.
  const vec3 p(4999.0f, 0.0f, 0.0f);
  const vec3 moved = offsetRayOrigin(p, vec3(1, 0, 0), 4999.0f);
  EXPECT_GE(moved.x - p.x, 16.0f * (std::nextafter(p.x, kInf) - p.x));
}

}  // namespace
}  // namespace fly::raytracer
