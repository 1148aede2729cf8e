#include "raytracer/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "base/log.h"
#include "raytracer/surface_point.h"

namespace fly::raytracer {
namespace {

void logEmbreeError(void* /*userPtr*/, RTCError code, const char* message) {
  log::error("Embree error " + std::to_string(static_cast<int>(code)) + ": " +
             (message ? message : "(no message)"));
}

thread_local std::vector<LoggedRay>* tRayLog = nullptr;

// Every query's context: Embree's, and for transmittance() what the filter needs to pass surfaces and what
// it has passed (Embree hands the filter the context it was given; the extension follows its first member).
struct QueryContext {
  RTCIntersectContext embree;
  const EmbreeScene::PassThrough* pass = nullptr;
  Rgb transmittance{1.0f};
  uint32_t passedCount = 0;
  // The surfaces passed, as triangle and distance, so that a repeated report, or the second triangle of a
  // crossing through the edge that two share, counts once. Only the first passedCount entries are read, so
  // the arrays are left uninitialised: every ray's query builds this context.
  std::array<uint32_t, 64> passed;
  std::array<float, 64> passedAtM;
};

// Fills the ray in place: built in a temporary and copied, its scalar stores would be read back by the copy's
// vector loads, which stalls on store forwarding.
void setRay(RTCRay& ray, const vec3& origin, const vec3& dir, float tMaxM) {
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.tnear = 0.0f;
  ray.dir_x = dir.x;
  ray.dir_y = dir.y;
  ray.dir_z = dir.z;
  ray.time = 0.0f;
  ray.tfar = tMaxM;
  ray.mask = 0xffffffffu;
  ray.id = 0;
  ray.flags = 0;
}

}  // namespace

EmbreeScene::EmbreeScene(const rdb::TraceRdb& rdb) : rdb_(rdb) {
  for (const rdb::TraceMaterial& m : rdb.materials)
    hasCutOuts_ = hasCutOuts_ || m.alpha == rdb::TraceAlpha::kMask;
  if (hasCutOuts_ && rdb.triangleMaterial.size() != rdb.triangleCount()) {
    throw std::invalid_argument("EmbreeScene: " + std::to_string(rdb.triangleMaterial.size()) +
                                " triangle materials for " + std::to_string(rdb.triangleCount()) +
                                " triangles");
  }
  const size_t triangleCount = rdb.triangleCount();
  triangles_.assign(triangleCount, TriangleData{});
  triangleOfPrimitive_.reserve(triangleCount);
  for (size_t t = 0; t < triangleCount; ++t) {
    const uint32_t i0 = rdb.indices[3 * t], i1 = rdb.indices[3 * t + 1], i2 = rdb.indices[3 * t + 2];
    if (i0 >= rdb.positionsM.size() || i1 >= rdb.positionsM.size() || i2 >= rdb.positionsM.size()) {
      throw std::invalid_argument("EmbreeScene: triangle " + std::to_string(t) +
                                  " has a vertex index beyond " + std::to_string(rdb.positionsM.size()) +
                                  " positions");
    }
    const vec3& p0 = rdb.positionsM[i0];
    const vec3& p1 = rdb.positionsM[i1];
    const vec3& p2 = rdb.positionsM[i2];
    if (!isFinite(p0) || !isFinite(p1) || !isFinite(p2)) continue;
    // In double, so that the normal of a sliver is not lost to cancellation.
    const dvec3 cross = glm::cross(dvec3(p1) - dvec3(p0), dvec3(p2) - dvec3(p0));
    const double twiceArea = glm::length(cross);
    if (!(twiceArea > 0.0) || !std::isfinite(twiceArea)) continue;
    const vec3 n(cross / twiceArea);
    if (!isFinite(n) || glm::dot(n, n) < 0.5f) continue;
    triangles_[t] = {n, static_cast<float>(0.5 * twiceArea), std::max({maxAbs(p0), maxAbs(p1), maxAbs(p2)})};
    triangleOfPrimitive_.push_back(static_cast<uint32_t>(t));
  }

  primitivesAreTriangles_ = triangleOfPrimitive_.size() == triangleCount;

  device_ = rtcNewDevice(nullptr);
  if (device_ == nullptr) {
    throw std::runtime_error("cannot create the Embree device (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(device_, logEmbreeError, nullptr);
  scene_ = rtcNewScene(device_);
  // Watertight ray–triangle tests: a ray through a shared edge or vertex hits one of the triangles.
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  if (!triangleOfPrimitive_.empty()) {
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Copies: Embree pads the vertex buffer so that it can read the last vertex as 16 bytes.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(vec3), rdb.positionsM.size()));
    for (size_t v = 0; v < rdb.positionsM.size(); ++v) {
      const vec3& p = rdb.positionsM[v];
      // Vertices of left-out triangles may be non-finite; Embree must not see them.
      const vec3 finite = isFinite(p) ? p : vec3(0.0f);
      vertices[3 * v] = finite.x;
      vertices[3 * v + 1] = finite.y;
      vertices[3 * v + 2] = finite.z;
    }
    auto* indices =
        static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                       3 * sizeof(uint32_t), triangleOfPrimitive_.size()));
    for (size_t k = 0; k < triangleOfPrimitive_.size(); ++k) {
      std::copy_n(&rdb.indices[3 * size_t(triangleOfPrimitive_[k])], 3, indices + 3 * k);
    }
    rtcSetGeometryUserData(geometry, this);
    rtcSetGeometryIntersectFilterFunction(geometry, filterHits);
    rtcSetGeometryOccludedFilterFunction(geometry, filterPassing);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(scene_);
}

EmbreeScene::~EmbreeScene() {
  rtcReleaseScene(scene_);
  rtcReleaseDevice(device_);
}

void EmbreeScene::filterHits(const RTCFilterFunctionNArguments* args) {
  const auto* self = static_cast<const EmbreeScene*>(args->geometryUserPtr);
  for (unsigned int i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const vec3 origin(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                      RTCRayN_org_z(args->ray, args->N, i));
    // The filter sees the candidate hit's distance in tfar. Nearly every hit lies beyond the origin's
    // offset: its triangle is looked up only where the hit may be rejected.
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    const bool atOrigin = t <= rayOffsetM(maxAbs(origin));
    if (!atOrigin && !self->hasCutOuts_) continue;
    const uint32_t triangle = self->triangleOf(RTCHitN_primID(args->hit, args->N, i));
    if (atOrigin) {
      const vec3 dir(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                     RTCRayN_dir_z(args->ray, args->N, i));
      if (glm::dot(self->triangles_[triangle].normal, dir) > 0.0f) {
        args->valid[i] = 0;
        continue;
      }
    }
    if (self->hasCutOuts_) {
      const rdb::TraceMaterial& m = self->rdb_.materials[self->rdb_.triangleMaterial[triangle]];
      if (m.alpha == rdb::TraceAlpha::kMask) {
        const TrianglePoint at{triangle,
                               vec2(RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i))};
        if (coverageAt(self->rdb_, m, at) < m.alphaCutoff) args->valid[i] = 0;
      }
    }
  }
}

void EmbreeScene::filterPassing(const RTCFilterFunctionNArguments* args) {
  filterHits(args);
  auto* context = reinterpret_cast<QueryContext*>(args->context);
  if (context->pass == nullptr) return;
  const auto* self = static_cast<const EmbreeScene*>(args->geometryUserPtr);
  const EmbreeScene::PassThrough& pass = *context->pass;
  for (unsigned int i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const uint32_t triangle = self->triangleOf(RTCHitN_primID(args->hit, args->N, i));
    if (!pass.passes[triangle]) continue;  // blocks: the query ends
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    const vec3 origin(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                      RTCRayN_org_z(args->ray, args->N, i));
    const float sameM = rayOffsetM(std::max(maxAbs(origin), t));
    bool repeated = false;
    for (uint32_t k = 0; k < context->passedCount && !repeated; ++k) {
      repeated = context->passed[k] == triangle || std::abs(context->passedAtM[k] - t) <= sameM;
    }
    if (repeated) {
      args->valid[i] = 0;  // this crossing was passed already
      continue;
    }
    if (context->passedCount == std::min(pass.maxPassed, static_cast<uint32_t>(context->passed.size()))) continue;
    const vec3 dir(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                   RTCRayN_dir_z(args->ray, args->N, i));
    const Hit hit{triangle, vec2(RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)),
                  self->triangles_[triangle].normal, t};
    const Rgb passing = pass.transmittance(pass.user, hit, dir);
    if (!(maxComponent(passing) > 0.0f)) continue;  // blocks here
    context->transmittance *= passing;
    context->passed[context->passedCount] = triangle;
    context->passedAtM[context->passedCount++] = t;
    args->valid[i] = 0;
  }
}

void EmbreeScene::logRaysOfThisThread(std::vector<LoggedRay>* log) {
  tRayLog = log;
}

bool EmbreeScene::occluded(const vec3& origin, const vec3& dir, float tMaxM) const {
  if (tRayLog != nullptr) [[unlikely]]
    tRayLog->push_back({origin, dir, tMaxM, true});
  QueryContext context;
  rtcInitIntersectContext(&context.embree);
  RTCRay ray;
  setRay(ray, origin, dir, tMaxM);
  rtcOccluded1(scene_, &context.embree, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();
}

Rgb EmbreeScene::transmittance(const vec3& origin, const vec3& dir, float tMaxM, const PassThrough& pass) const {
  if (tRayLog != nullptr) [[unlikely]]
    tRayLog->push_back({origin, dir, tMaxM, true});
  QueryContext context;
  rtcInitIntersectContext(&context.embree);
  context.pass = &pass;
  RTCRay ray;
  setRay(ray, origin, dir, tMaxM);
  rtcOccluded1(scene_, &context.embree, &ray);
  if (ray.tfar == -std::numeric_limits<float>::infinity()) return Rgb(0.0f);
  return context.transmittance;
}

std::optional<Hit> EmbreeScene::intersect(const vec3& origin, const vec3& dir, float tMaxM) const {
  if (tRayLog != nullptr) [[unlikely]]
    tRayLog->push_back({origin, dir, tMaxM, false});
  QueryContext context;
  rtcInitIntersectContext(&context.embree);
  RTCRayHit rayHit;
  setRay(rayHit.ray, origin, dir, tMaxM);
  rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context.embree, &rayHit);
  if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const uint32_t triangle = triangleOf(rayHit.hit.primID);
  return Hit{triangle, vec2(rayHit.hit.u, rayHit.hit.v), triangles_[triangle].normal, rayHit.ray.tfar};
}

}  // namespace fly::raytracer
