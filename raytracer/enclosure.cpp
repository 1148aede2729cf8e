#include "raytracer/enclosure.h"

#include <cmath>
#include <limits>

#include "raytracer/warp.h"

namespace fly::raytracer {

float enclosureReachM(const rdb::TraceRdb& rdb) {
  Bounds3 bounds;
  for (const vec3& q : rdb.positionsM) bounds.extend(q);
  const float diagonal = rdb.positionsM.empty() ? 0.0f : glm::length(bounds.max - bounds.min);
  return std::isfinite(diagonal) ? kEnclosureReachShare * diagonal : 0.0f;
}

bool isEnclosed(const EmbreeScene& scene, const vec3& p, const vec3& n, float magnitudeM, float reachM,
                uint64_t& rays) {
  if (!(reachM > 0.0f)) return false;
  const Onb frame = onb(n);
  const vec3 origin = offsetRayOrigin(p, n, std::max(maxAbs(p), magnitudeM));
  constexpr float kGoldenAngle = 2.39996323f;
  int backs = 0;
  for (int k = 0; k < kEnclosureRays; ++k) {
    // Equal solid angles: cos θ uniform in (0, 1), φ by the golden angle.
    const float cosTheta = 1.0f - (float(k) + 0.5f) / float(kEnclosureRays);
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const float phi = kGoldenAngle * float(k);
    const vec3 dir = frame.toWorld(vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
    ++rays;
    const std::optional<Hit> hit = scene.intersect(origin, dir, reachM);
    if (!hit) return false;  // open: nothing within reach
    backs += glm::dot(dir, hit->geometricNormal) > 0.0f ? 1 : 0;
    if (kEnclosureRays - (k + 1) + backs < kEnclosureBackRays) return false;  // too many fronts already
  }
  return backs >= kEnclosureBackRays;
}

}  // namespace fly::raytracer
