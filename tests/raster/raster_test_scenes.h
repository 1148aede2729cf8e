// Shared by the raster tests (header-only: the test glob compiles *_test.cpp): one headless context per test
// process, and small scenes built in code.
#pragma once

#include <cmath>
#include <memory>

#include "raster/gl_context.h"
#include "raster/renderer.h"
#include "sdb/camera.h"
#include "sdb/scene.h"

namespace fly::raster::test {

// The process's headless context, made current. Throws (the test fails, it does not skip) when EGL or Mesa
// is missing: CI has Mesa, and a silently skipped GL test would hide a broken engine.
inline GlContext& context() {
  static const std::unique_ptr<GlContext> c = createHeadlessContext();
  c->makeCurrent();
  return *c;
}

// A perspective view (0.9 rad vertical field, near plane 5 cm) from `eye` towards `target`, +Y up.
inline View lookAtView(const vec3& eye, const vec3& target, float zfarM) {
  View v;
  v.worldFromCamera = sdb::lookAtTransform(eye, target, vec3(0, 1, 0));
  v.yfovRad = 0.9f;
  v.znearM = 0.05f;
  v.zfarM = zfarM;
  return v;
}

// A quad in the local XY plane from (−1, −0.5) to (1, 0.5) at z = 0, normals +Z, counter-clockwise seen from
// +Z (its front), vertices in the order (−1,−0.5), (1,−0.5), (1,0.5), (−1,0.5), triangles (0,1,2), (0,2,3).
inline sdb::Mesh quadXY(sdb::MaterialId material) {
  sdb::Mesh m;
  m.name = "quad";
  m.positions = {{-1.0f, -0.5f, 0.0f}, {1.0f, -0.5f, 0.0f}, {1.0f, 0.5f, 0.0f}, {-1.0f, 0.5f, 0.0f}};
  m.normals.assign(4, vec3(0, 0, 1));
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  return m;
}

// An axis-aligned box from `lo` to `hi`, its six faces as separate quads (24 vertices), facing out (or in,
// for a room seen from inside).
inline sdb::Mesh box(const vec3& lo, const vec3& hi, sdb::MaterialId material, bool inward = false) {
  sdb::Mesh m;
  m.name = inward ? "room" : "box";
  // Face along axis n on side `side`; in-plane axes u, v with u × v = the outward normal (cyclic order on the
  // high side, swapped on the low side), so (0,1,2), (0,2,3) over the corners below wind counter-clockwise
  // seen from outside.
  for (int n = 0; n < 3; ++n) {
    for (int side = 0; side < 2; ++side) {
      const int u = side ? (n + 1) % 3 : (n + 2) % 3;
      const int v = side ? (n + 2) % 3 : (n + 1) % 3;
      vec3 normal(0.0f);
      normal[n] = side ? 1.0f : -1.0f;
      const uint32_t first = uint32_t(m.positions.size());
      for (int k = 0; k < 4; ++k) {
        vec3 p;
        p[n] = side ? hi[n] : lo[n];
        p[u] = (k == 1 || k == 2) ? hi[u] : lo[u];
        p[v] = (k >= 2) ? hi[v] : lo[v];
        m.positions.push_back(p);
        m.normals.push_back(inward ? -normal : normal);
      }
      if (inward) {
        m.indices.insert(m.indices.end(), {first, first + 2, first + 1, first, first + 3, first + 2});
      } else {
        m.indices.insert(m.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
      }
    }
  }
  m.material = material;
  return m;
}

// A UV sphere of radius `radiusM` about `centreM`: `rings` × `segments` quads (the poles' as triangles),
// unit normals from the centre, counter-clockwise seen from outside.
inline sdb::Mesh uvSphere(const vec3& centreM, float radiusM, int rings, int segments, sdb::MaterialId material) {
  sdb::Mesh m;
  m.name = "sphere";
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPiF * float(i) / float(rings);
    for (int j = 0; j <= segments; ++j) {
      const float phi = 2.0f * kPiF * float(j) / float(segments);
      const vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      m.positions.push_back(centreM + radiusM * n);
      m.normals.push_back(n);
    }
  }
  const uint32_t row = uint32_t(segments + 1);
  for (uint32_t i = 0; i < uint32_t(rings); ++i) {
    for (uint32_t j = 0; j < uint32_t(segments); ++j) {
      const uint32_t a = i * row + j, b = a + row;
      if (i > 0) m.indices.insert(m.indices.end(), {a, b, a + 1});
      if (i + 1 < uint32_t(rings)) m.indices.insert(m.indices.end(), {a + 1, b, b + 1});
    }
  }
  m.material = material;
  return m;
}

}  // namespace fly::raster::test
