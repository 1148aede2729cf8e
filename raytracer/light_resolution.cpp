#include "raytracer/light_resolution.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "base/color.h"
#include "rdb/trace_rdb_build.h"

namespace fly::raytracer {

namespace {

// One triangle's examination.
struct TriangleResult {
  float maxRelativeError = 0.0f;  // of the direct light, relative to max(E, E_interpolated)
  float maxAbsoluteErrorLux = 0.0f;  // the absolute error where that relative one was found
  float maxDirectLux = 0.0f;      // the largest direct illuminance met at its points
  bool large = false;
  bool examined = false;
};

// A point at barycentric coordinates b of triangle t, with its interpolated shading normal on the given side.
struct TrianglePointAt {
  vec3 p;
  vec3 n;
};

TrianglePointAt pointOf(const rdb::TraceRdb& rdb, const EmbreeScene& scene, uint32_t t, const vec3& b,
                        bool back) {
  vec3 p(0.0f), n(0.0f);
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = rdb.indices[3 * size_t(t) + size_t(k)];
    p += b[k] * rdb.positionsM[v];
    if (!rdb.normals.empty()) n += b[k] * rdb.normals[v];
  }
  const vec3& ng = scene.triangleNormal(t);
  // The front is the side of the vertex normals (the baker's convention); a degenerate or flipped
  // interpolated normal falls back to the geometric one on that side.
  const float side = glm::dot(n, ng) >= 0.0f ? 1.0f : -1.0f;
  const vec3 ngFront = side * ng;
  n = glm::dot(n, n) > 0.0f ? glm::normalize(n) : ngFront;
  if (!(glm::dot(n, ngFront) > 0.0f)) n = ngFront;
  return {p, back ? -n : n};
}

// Emitters as point sources for the analysis: each emissive triangle (the brightest kMaxEmitterTriangles by
// luminance × area) split into 4 parts, each a Lambertian point at its centroid with the part's L·A (cd/m² ×
// m² = cd at normal emission). Deterministic; near an emitter it overstates the variation, which only gives
// such a surface texels.
constexpr size_t kMaxEmitterTriangles = 64;
struct EmitterPoint {
  vec3 pM;
  vec3 normal;        // unit, the emitting front
  bool bothSides;     // a double-sided emitter emits from both faces
  Rgb intensityCd;    // L · A of the part
  float minDistM2;    // its area: distances below its size are clamped to it
};

std::vector<EmitterPoint> emitterPoints(const rdb::TraceRdb& rdb, const EmbreeScene& scene) {
  std::vector<std::pair<float, uint32_t>> byPower;
  for (uint32_t t : rdb.emissiveTriangles) {
    const rdb::TraceMaterial& m = rdb.materials[rdb.triangleMaterial[t]];
    const float power = luminance(m.emissionCdM2) * scene.triangleAreaM2(t);
    if (power > 0.0f && std::isfinite(power)) byPower.emplace_back(power, t);
  }
  std::stable_sort(byPower.begin(), byPower.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  if (byPower.size() > kMaxEmitterTriangles) byPower.resize(kMaxEmitterTriangles);
  std::vector<EmitterPoint> out;
  const vec3 parts[4] = {{2.0f / 3, 1.0f / 6, 1.0f / 6}, {1.0f / 6, 2.0f / 3, 1.0f / 6}, {1.0f / 6, 1.0f / 6, 2.0f / 3},
                         {1.0f / 3, 1.0f / 3, 1.0f / 3}};
  for (const auto& [power, t] : byPower) {
    const rdb::TraceMaterial& m = rdb.materials[rdb.triangleMaterial[t]];
    const float areaM2 = scene.triangleAreaM2(t) / 4.0f;
    for (const vec3& b : parts) {
      vec3 p(0.0f);
      for (int k = 0; k < 3; ++k) p += b[k] * rdb.positionsM[rdb.indices[3 * size_t(t) + size_t(k)]];
      out.push_back({p, scene.triangleNormal(t), m.doubleSided, m.emissionCdM2 * areaM2, areaM2});
    }
  }
  return out;
}

// The emitters' direct irradiance at p (normal n), lux, with one shadow ray each.
Rgb emitterIrradiance(const EmbreeScene& scene, const std::vector<EmitterPoint>& emitters, const vec3& p,
                      const vec3& n, float magnitudeM, uint64_t& rays) {
  Rgb sum(0.0f);
  const vec3 origin = offsetRayOrigin(p, n, std::max(maxAbs(p), magnitudeM));
  for (const EmitterPoint& e : emitters) {
    const vec3 toEmitter = e.pM - p;
    const float d2 = glm::dot(toEmitter, toEmitter);
    if (!(d2 > 0.0f)) continue;
    const float d = std::sqrt(d2);
    const vec3 dir = toEmitter / d;
    const float cosReceiver = glm::dot(n, dir);
    float cosEmitter = -glm::dot(e.normal, dir);
    if (e.bothSides) cosEmitter = std::abs(cosEmitter);
    if (!(cosReceiver > 0.0f) || !(cosEmitter > 0.0f)) continue;
    ++rays;
    // Stop short of the emitter's own surface.
    if (scene.occluded(origin, dir, d * (1.0f - 1e-3f))) continue;
    sum += e.intensityCd * (cosEmitter * cosReceiver / std::max(d2, e.minDistM2));
  }
  return sum;
}

TriangleResult examine(const rdb::TraceRdb& rdb, const EmbreeScene& scene, const Integrator& integrator,
                       const std::vector<EmitterPoint>& emitters,
                       const LightResolutionSettings& s, bool directLights, uint32_t t, bool twoSided,
                       uint64_t& rays) {
  TriangleResult r;
  if (!(scene.triangleAreaM2(t) > 0.0f)) return r;
  const vec3& a = rdb.positionsM[rdb.indices[3 * size_t(t)]];
  const vec3& b = rdb.positionsM[rdb.indices[3 * size_t(t) + 1]];
  const vec3& c = rdb.positionsM[rdb.indices[3 * size_t(t) + 2]];
  const float edgeM = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
  if (!std::isfinite(edgeM) || edgeM * s.texelsPerMetre < 2.0f) return r;
  r.examined = true;
  r.large = edgeM >= s.largeTriangleEdgeM;
  if (!directLights) return r;
  const uint32_t k = std::clamp(uint32_t(std::ceil(edgeM * s.texelsPerMetre / 8.0f)), 2u, s.maxLatticeK);
  const float magnitudeM = scene.triangleMagnitudeM(t);
  // The corners, moved 10⁻³ of the way to the centroid so that their shadow rays leave from inside the
  // triangle (a corner on the edge where a wall meets the floor would see into the wall's offset).
  const vec3 centre(1.0f / 3.0f);
  vec3 corners[3];
  for (int i = 0; i < 3; ++i) {
    vec3 e(0.0f);
    e[i] = 1.0f;
    corners[i] = glm::mix(e, centre, 1e-3f);
  }
  for (int side = 0; side < (twoSided ? 2 : 1); ++side) {
    const bool back = side == 1;
    float cornerLux[3];
    for (int i = 0; i < 3; ++i) {
      const TrianglePointAt q = pointOf(rdb, scene, t, corners[i], back);
      cornerLux[i] = luminance(integrator.deltaDirectIrradiance(q.p, q.n, rays, magnitudeM) +
                               emitterIrradiance(scene, emitters, q.p, q.n, magnitudeM, rays));
      r.maxDirectLux = std::max(r.maxDirectLux, cornerLux[i]);
    }
    // Centroids of the k² sub-triangles of the lattice that splits each edge into k.
    for (uint32_t i = 0; i < k; ++i) {
      for (uint32_t j = 0; i + j < k; ++j) {
        for (int up = 0; up < (i + j + 1 < k ? 2 : 1); ++up) {
          const float u = (float(i) + (up ? 2.0f : 1.0f) / 3.0f) / float(k);
          const float v = (float(j) + (up ? 2.0f : 1.0f) / 3.0f) / float(k);
          const vec3 bary(1.0f - u - v, u, v);
          const TrianglePointAt q = pointOf(rdb, scene, t, bary, back);
          const float e = luminance(integrator.deltaDirectIrradiance(q.p, q.n, rays, magnitudeM) +
                                    emitterIrradiance(scene, emitters, q.p, q.n, magnitudeM, rays));
          const float interpolated = bary.x * cornerLux[0] + bary.y * cornerLux[1] + bary.z * cornerLux[2];
          const float scale = std::max(e, interpolated);
          r.maxDirectLux = std::max(r.maxDirectLux, e);
          if (!(scale > 0.0f)) continue;
          const float relative = std::abs(e - interpolated) / scale;
          if (relative > r.maxRelativeError) {
            r.maxRelativeError = relative;
            r.maxAbsoluteErrorLux = std::abs(e - interpolated);
          }
        }
      }
    }
  }
  return r;
}

std::string areaText(double m2) {
  char text[32];
  std::snprintf(text, sizeof text, m2 < 10.0 ? "%.2g m²" : "%.0f m²", m2);
  return text;
}

}  // namespace

std::vector<MeshLightResolution> analyseLightResolution(const rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                                        const Integrator& integrator,
                                                        const LightResolutionSettings& settings,
                                                        uint64_t& rays) {
  if (!(settings.texelsPerMetre > 0.0f) || !std::isfinite(settings.texelsPerMetre) ||
      !(settings.relativeTolerance > 0.0f) || !(settings.largeTriangleEdgeM > 0.0f) ||
      settings.maxLatticeK < 2) {
    throw std::invalid_argument("analyseLightResolution: a setting is out of range");
  }
  std::vector<uint32_t> meshes;
  for (uint32_t m = 0; m < rdb.meshes.size(); ++m) {
    const rdb::TraceMesh& tm = rdb.meshes[m];
    if (tm.automaticLightTextureAllowed && tm.lightTexture == rdb::TraceMesh::kNoLightTexture &&
        tm.triangleCount > 0)
      meshes.push_back(m);
  }
  const std::vector<EmitterPoint> emitters = emitterPoints(rdb, scene);
  const bool directLights = integrator.hasSun() || !rdb.punctualLights.empty() || !emitters.empty();
  // Every examined triangle, in mesh order, so that the work is split into equal blocks.
  std::vector<uint32_t> triangles;
  std::vector<uint8_t> twoSided;
  for (uint32_t m : meshes) {
    const rdb::TraceMesh& tm = rdb.meshes[m];
    for (uint32_t t = tm.firstTriangle; t < tm.firstTriangle + tm.triangleCount; ++t) {
      triangles.push_back(t);
      twoSided.push_back(tm.twoSided ? 1 : 0);
    }
  }
  std::vector<TriangleResult> results(triangles.size());
  const uint32_t threads =
      settings.threads > 0 ? settings.threads : std::max(1u, std::thread::hardware_concurrency());
  constexpr size_t kBlock = 64;
  std::atomic<size_t> next{0};
  std::vector<uint64_t> threadRays(threads, 0);
  auto work = [&](uint32_t w) {
    for (size_t begin; (begin = next.fetch_add(kBlock)) < triangles.size();) {
      const size_t end = std::min(triangles.size(), begin + kBlock);
      for (size_t i = begin; i < end; ++i)
        results[i] = examine(rdb, scene, integrator, emitters, settings, directLights, triangles[i], twoSided[i] != 0,
                             threadRays[w]);
    }
  };
  std::vector<std::thread> pool;
  for (uint32_t w = 1; w < threads; ++w) pool.emplace_back(work, w);
  work(0);
  for (std::thread& th : pool) th.join();
  for (uint64_t r : threadRays) rays += r;

  float sceneMaxLux = 0.0f;
  for (const TriangleResult& r : results) sceneMaxLux = std::max(sceneMaxLux, r.maxDirectLux);
  const float floorLux = settings.absoluteShare * sceneMaxLux;
  const double texelAreaM2 = 1.0 / (double(settings.texelsPerMetre) * double(settings.texelsPerMetre));

  std::vector<MeshLightResolution> out;
  size_t i = 0;
  for (uint32_t m : meshes) {
    const rdb::TraceMesh& tm = rdb.meshes[m];
    MeshLightResolution res;
    res.mesh = m;
    res.directInterpolationError.assign(tm.triangleCount, 0.0f);
    for (uint32_t k = 0; k < tm.triangleCount; ++k, ++i) {
      const TriangleResult& r = results[i];
      const double area = scene.triangleAreaM2(tm.firstTriangle + k);
      if (!(area > 0.0)) continue;
      res.areaM2 += area;
      if (r.maxAbsoluteErrorLux > floorLux) res.directInterpolationError[k] = r.maxRelativeError;
      if (r.examined && res.directInterpolationError[k] > settings.relativeTolerance) {
        res.directVariationAreaM2 += area;
      } else if (r.large) {
        res.largeTriangleAreaM2 += area;
      }
    }
    const double needM2 = res.directVariationAreaM2 + res.largeTriangleAreaM2;
    res.needsTexels = needM2 >= double(settings.minNeedTexels) * texelAreaM2;
    if (res.needsTexels) {
      std::string why;
      if (res.directVariationAreaM2 > 0.0) {
        why = (integrator.hasSun() ? (rdb.punctualLights.empty() && emitters.empty()
                                          ? "sun patches or shadow edges"
                                          : "sun patches, shadows or lamp pools")
                                   : "lamp pools or shadow edges") +
              std::string(" on ") + areaText(res.directVariationAreaM2);
      }
      if (res.largeTriangleAreaM2 > 0.0) {
        if (!why.empty()) why += ", ";
        char edge[48];
        std::snprintf(edge, sizeof edge, "triangles with %.3g m edges or longer on ", double(settings.largeTriangleEdgeM));
        why += edge + areaText(res.largeTriangleAreaM2);
      }
      res.reason = why + " of " + areaText(res.areaM2);
    }
    out.push_back(std::move(res));
  }
  return out;
}

std::vector<MeshLightResolution> addNeededLightTextures(rdb::TraceRdb& rdb, const EmbreeScene& scene,
                                                        const LightResolutionSettings& settings,
                                                        int maxAtlasSize, int paddingTexels) {
  IntegratorSettings is;
  is.litPatches = false;
  is.skyPortals = false;
  is.portalContinuation = false;
  std::vector<MeshLightResolution> analysis;
  {
    const Integrator integrator(rdb, scene, is);
    uint64_t rays = 0;
    analysis = analyseLightResolution(rdb, scene, integrator, settings, rays);
  }
  for (MeshLightResolution& r : analysis) {
    if (!r.needsTexels) continue;
    rdb::TraceLightTexture* lt =
        rdb::addAutomaticLightTexture(rdb, r.mesh, settings.texelsPerMetre, maxAtlasSize, paddingTexels);
    if (!lt) {
      // Every chart is finer in vertices than texels would be.
      r.needsTexels = false;
      r.reason.clear();
      continue;
    }
    const rdb::TraceMesh& tm = rdb.meshes[r.mesh];
    double texturedM2 = 0.0;
    for (uint32_t k = 0; k < tm.triangleCount; ++k) {
      if (rdb::inLightTexture(lt->cornerUv[3 * size_t(k)])) texturedM2 += scene.triangleAreaM2(tm.firstTriangle + k);
    }
    if (texturedM2 < r.areaM2 * (1.0 - 1e-6)) {
      r.reason += "; in texels " + areaText(texturedM2) + ", the rest finer in vertices";
    }
    lt->automaticReason = r.reason;
  }
  return analysis;
}

}  // namespace fly::raytracer
