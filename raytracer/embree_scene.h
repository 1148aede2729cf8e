// The TraceRdb's triangles in an Embree 3 scene, and the two ray queries the integrator needs. Embree's types
// stay in the .cpp: callers see triangle indices of the TraceRdb and glm vectors only.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "rdb/trace_rdb.h"

struct RTCDeviceTy;
struct RTCSceneTy;
struct RTCFilterFunctionNArguments;

namespace fly::raytracer {

// The nearest intersection of a ray.
struct Hit {
  uint32_t triangle = 0;       // index into the TraceRdb's triangles
  vec2 barycentric{0.0f};      // (u, v): the point is (1 − u − v)·p0 + u·p1 + v·p2
  vec3 geometricNormal{0.0f};  // unit, (p1 − p0) × (p2 − p0): the front face is counter-clockwise (glTF)
  float distanceM = 0.0f;      // along the (unit) ray direction
};

// The distance to move a ray's origin off a surface along its normal so that the ray cannot hit that surface
// again. `magnitudeM` is the largest absolute coordinate of the point and of the triangle it lies on: Embree
// evaluates the ray–triangle test in float relative to the ray origin, so its error in the signed distance to
// the plane is a few ulps of that magnitude (Wächter & Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems, ch. 6, 2019, who likewise offset by a fixed number of ulps of the
// coordinates). 2^-19 relative is 16–32 ulps: 9.5 mm at 5 km, 1.9 nm for a 1 mm detail at the origin. A floor
// of 2^-19 × 2^-10 m keeps the offset representable near the origin.
inline float rayOffsetM(float magnitudeM) {
  return std::max(magnitudeM, 0x1p-10f) * 0x1p-19f;
}

// Largest absolute coordinate.
inline float maxAbs(const vec3& p) {
  return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

// p moved off its surface to the side of unit normal n (the side the new ray leaves on).
inline vec3 offsetRayOrigin(const vec3& p, const vec3& n, float magnitudeM) {
  return p + rayOffsetM(magnitudeM) * n;
}

// A query as it was made, for benchmarks that time Embree alone on the integrator's own rays
// (bench/bench_baker.cpp).
struct LoggedRay {
  vec3 origin;
  vec3 dir;
  float tMaxM = 0.0f;
  bool occlusion = false;  // occluded() rather than intersect()
};

class EmbreeScene {
 public:
  // Builds and commits one triangle geometry from rdb's positions and indices; keeps a reference to rdb,
  // which must outlive it. Degenerate triangles (zero area or non-finite vertices) are left out: no ray ever
  // hits them. Embree errors reach fly::log::error; a
  // device that cannot be created throws std::runtime_error.
  explicit EmbreeScene(const rdb::TraceRdb& rdb);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Queries see hits on [0, tMaxM], except one that leaves the back of a face within
  // rayOffsetM(maxAbs(origin)) of the origin: a point moved off its own face may still lie on another that
  // meets it at an inner edge or corner (the wall beside a floor point on their shared edge), which a ray
  // leaving that wall would otherwise hit at t ≈ 0. A face ahead of the origin, however near, is hit: no
  // light leaks through the corner. Nor do they see alpha cut-outs: points of a TraceAlpha::kMask material
  // whose coverage (raytracer/surface_point.h) is below its alphaCutoff, for every ray alike.

  // Is anything hit before tMaxM? dir is unit; tMaxM may be infinite. Safe to call from many threads.
  bool occluded(const vec3& origin, const vec3& dir, float tMaxM) const;
  // The nearest hit before tMaxM, if any. dir is unit. Safe to call from many threads.
  std::optional<Hit> intersect(const vec3& origin, const vec3& dir, float tMaxM) const;

  // Surfaces that let light through along a ray (clear glass, partial coverage): passes(t) says whether
  // triangle t may (else it blocks), and transmittance(user, hit, dir) what share of each channel passes at
  // the hit (0: blocks there).
  struct PassThrough {
    const uint8_t* passes;  // per TraceRdb triangle
    Rgb (*transmittance)(const void* user, const Hit& hit, const vec3& dir);
    const void* user;
    uint32_t maxPassed;  // surfaces passed beyond which the ray counts as blocked
  };
  // The share of light that travels from origin along unit dir over [0, tMaxM] (tMaxM may be infinite): 0
  // when a surface that does not pass light is hit, else the product of the transmittances of the distinct
  // surfaces that pass it. One occlusion query: Embree reports the candidate hits in any order, stops at
  // the first blocking one, and passes the others; each triangle counts once. Safe to call from many
  // threads.
  Rgb transmittance(const vec3& origin, const vec3& dir, float tMaxM, const PassThrough& pass) const;

  // While `log` is set (not null), every query made on the calling thread is appended to it; null stops.
  // For benchmarks: one pointer test per query otherwise.
  static void logRaysOfThisThread(std::vector<LoggedRay>* log);

  // Per TraceRdb triangle: its unit geometric normal (zero for a degenerate one), its area in m², and the
  // largest absolute coordinate of its vertices (for rayOffsetM()).
  const vec3& triangleNormal(uint32_t t) const { return triangles_[t].normal; }
  float triangleAreaM2(uint32_t t) const { return triangles_[t].areaM2; }
  float triangleMagnitudeM(uint32_t t) const { return triangles_[t].magnitudeM; }
  // Triangles given to Embree (the others are degenerate).
  uint32_t validTriangleCount() const { return static_cast<uint32_t>(triangleOfPrimitive_.size()); }

 private:
  // Embree's intersection and occlusion filter: rejects the hits at the origin and in cut-outs described
  // above.
  static void filterHits(const RTCFilterFunctionNArguments* args);
  // The occlusion filter: filterHits, then for transmittance() the surfaces that pass light.
  static void filterPassing(const RTCFilterFunctionNArguments* args);

  const rdb::TraceRdb& rdb_;
  bool hasCutOuts_ = false;  // some material is an alpha mask
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  // The TraceRdb triangle of an Embree primitive id: the id itself when no triangle is left out.
  uint32_t triangleOf(uint32_t primitive) const {
    return primitivesAreTriangles_ ? primitive : triangleOfPrimitive_[primitive];
  }

  std::vector<uint32_t> triangleOfPrimitive_;  // Embree primitive id → TraceRdb triangle
  bool primitivesAreTriangles_ = false;        // triangleOfPrimitive_ is the identity
  // What a hit reads of its triangle, together: one cache line's load where the scene is large.
  struct TriangleData {
    vec3 normal{0.0f};
    float areaM2 = 0.0f;
    float magnitudeM = 0.0f;
  };
  std::vector<TriangleData> triangles_;
};

}  // namespace fly::raytracer
