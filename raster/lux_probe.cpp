#include "raster/lux_probe.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fly::raster {

PickRay pickRay(const View& view, double xPx, double yPx, uint32_t widthPx, uint32_t heightPx) {
  const double w = std::max<uint32_t>(widthPx, 1), h = std::max<uint32_t>(heightPx, 1);
  const float aspect = float(w / h);
  // Normalised device coordinates: x right, y up, both in [−1, 1] over the image.
  const float ndcX = float(2.0 * xPx / w - 1.0), ndcY = float(1.0 - 2.0 * yPx / h);
  PickRay ray;
  vec3 originCamera{0.0f}, dirCamera{0.0f, 0.0f, -1.0f};
  if (view.orthographic) {  // the renderer's glm::ortho: half extents ymag · aspect by ymag
    originCamera = vec3(ndcX * view.ymagM * aspect, ndcY * view.ymagM, -view.znearM);
  } else {  // glm::perspective: tan(yfov/2) at unit distance
    const float t = std::tan(0.5f * view.yfovRad);
    dirCamera = glm::normalize(vec3(ndcX * t * aspect, ndcY * t, -1.0f));
  }
  ray.originWorld = vec3(view.worldFromCamera * vec4(originCamera, 1.0f));
  ray.dirWorld = glm::normalize(vec3(view.worldFromCamera * vec4(dirCamera, 0.0f)));
  return ray;
}

std::optional<vec2> projectToImage(const View& view, const vec3& pointWorld, uint32_t widthPx,
                                   uint32_t heightPx) {
  const double w = std::max<uint32_t>(widthPx, 1), h = std::max<uint32_t>(heightPx, 1);
  const float aspect = float(w / h);
  const vec3 p = vec3(glm::inverse(view.worldFromCamera) * vec4(pointWorld, 1.0f));
  float ndcX = 0.0f, ndcY = 0.0f;
  if (view.orthographic) {
    ndcX = p.x / (view.ymagM * aspect);
    ndcY = p.y / view.ymagM;
  } else {
    if (!(p.z < 0.0f)) return std::nullopt;
    const float t = std::tan(0.5f * view.yfovRad);
    ndcX = p.x / (-p.z * t * aspect);
    ndcY = p.y / (-p.z * t);
  }
  return vec2(float((ndcX + 1.0) * 0.5 * w), float((1.0 - ndcY) * 0.5 * h));
}

std::optional<SurfaceHit> pickSurface(const rdb::RasterRdb& rdb, const PickRay& ray) {
  return pickSurfaceNear(rdb, ray, 0.0f, std::numeric_limits<float>::infinity());
}

std::optional<SurfaceHit> pickSurfaceNear(const rdb::RasterRdb& rdb, const PickRay& ray,
                                          float targetDistanceM, float maxDistanceM) {
  std::optional<SurfaceHit> best;
  float nearest = std::numeric_limits<float>::infinity();  // |t − targetDistanceM| of the best hit
  for (uint32_t m = 0; m < rdb.meshes.size(); ++m) {
    const rdb::RasterMesh& mesh = rdb.meshes[m];
    for (uint32_t i = mesh.firstIndex; i + 3 <= mesh.firstIndex + mesh.indexCount; i += 3) {
      const vec3& p0 = rdb.positionsM[rdb.indices[i]];
      const vec3& p1 = rdb.positionsM[rdb.indices[i + 1]];
      const vec3& p2 = rdb.positionsM[rdb.indices[i + 2]];
      // Möller–Trumbore: solve origin + t·dir = (1 − u − v)·p0 + u·p1 + v·p2 by Cramer's rule.
      const vec3 e1 = p1 - p0, e2 = p2 - p0;
      const vec3 pv = glm::cross(ray.dirWorld, e2);
      const float det = glm::dot(e1, pv);
      if (!(std::abs(det) > 1e-12f * glm::length(e1) * glm::length(e2))) continue;  // parallel or degenerate
      const float inv = 1.0f / det;
      const vec3 tv = ray.originWorld - p0;
      const float u = glm::dot(tv, pv) * inv;
      if (u < 0.0f || u > 1.0f) continue;
      const vec3 qv = glm::cross(tv, e1);
      const float v = glm::dot(ray.dirWorld, qv) * inv;
      if (v < 0.0f || u + v > 1.0f) continue;
      const float t = glm::dot(e2, qv) * inv;
      if (!(t > 0.0f) || t > maxDistanceM) continue;
      const vec3 n = (1.0f - u - v) * rdb.normals[rdb.indices[i]] + u * rdb.normals[rdb.indices[i + 1]] +
                     v * rdb.normals[rdb.indices[i + 2]];
      const bool back = glm::dot(n, ray.dirWorld) > 0.0f;
      // Coincident surfaces (a floor and the underside of a block on it, duplicated faces): the one whose
      // front faces the ray wins, as back-face culling shows it.
      const float offset = std::abs(t - targetDistanceM);
      const float tie = 1e-5f * std::max(t, 1e-3f);
      const bool same = best && std::abs(offset - nearest) <= tie;
      if (same ? !(best->back && !back) : offset >= nearest) continue;
      nearest = offset;
      SurfaceHit hit;
      hit.triangle = i / 3;
      hit.mesh = m;
      hit.distanceM = t;
      hit.barycentric = vec3(1.0f - u - v, u, v);
      hit.pointWorld = ray.originWorld + t * ray.dirWorld;
      hit.back = back;
      best = hit;
    }
  }
  return best;
}

std::optional<LuxReading> probeIlluminance(const rdb::RasterRdb& rdb, const rdb::LightMapStore* store,
                                           const SurfaceHit& hit) {
  if (hit.mesh >= rdb.meshes.size()) return std::nullopt;
  const rdb::RasterMesh& mesh = rdb.meshes[hit.mesh];
  if (!mesh.hasLightMap) return std::nullopt;
  const uint32_t v[3] = {rdb.indices[3 * hit.triangle], rdb.indices[3 * hit.triangle + 1],
                         rdb.indices[3 * hit.triangle + 2]};
  const float w[3] = {hit.barycentric.x, hit.barycentric.y, hit.barycentric.z};
  // A one-sided mesh shows its front values on both faces (rdb/raster_rdb.h).
  const bool back = hit.back && mesh.twoSided && !rdb.backLux.empty();
  const rdb::MeshLightMap* map = store ? store->find(mesh.sdbNodeId, mesh.sdbMeshId) : nullptr;
  LuxReading r;
  r.pointWorld = hit.pointWorld;
  r.sdbNodeId = mesh.sdbNodeId;
  r.back = back;
  if (mesh.lightTexture != rdb::RasterMesh::kNoLightTexture && mesh.lightTexture < rdb.lightTextures.size() &&
      rdb::inLightTexture(rdb.lightMapUv[v[0]])) {
    // Bilinear between the four texel centres around the point, as the GL engine filters the light texture;
    // the texels' estimates are independent, so the error is √(Σ wᵢ² σᵢ²).
    const rdb::RasterLightTexture& tex = rdb.lightTextures[mesh.lightTexture];
    const vec2 uv = w[0] * rdb.lightMapUv[v[0]] + w[1] * rdb.lightMapUv[v[1]] + w[2] * rdb.lightMapUv[v[2]];
    const vec2 x = glm::clamp(uv, 0.0f, 1.0f) * vec2(float(tex.width), float(tex.height)) - 0.5f;
    const vec2 lo = glm::floor(x);
    const vec2 f = x - lo;
    const bool backTexels = back && !tex.backLux.empty();
    const std::vector<Rgb>& texels = backTexels ? tex.backLux : tex.frontLux;
    const rdb::MeshLightTexture* stored = map && map->lightTexture ? &*map->lightTexture : nullptr;
    const std::vector<Rgb>* errors =
        stored ? (backTexels ? &stored->backStdErrorLux : &stored->frontStdErrorLux) : nullptr;
    const bool withErrors = errors && stored->width == tex.width && stored->height == tex.height &&
                            errors->size() == texels.size();
    // The four texels (clamped at the border, as GL_CLAMP_TO_EDGE: one texel may come twice, its weights
    // then add before the error's square).
    size_t texel[4];
    float weight[4];
    for (int k = 0; k < 4; ++k) {
      const int di = k & 1, dj = k >> 1;
      weight[k] = (di ? f.x : 1.0f - f.x) * (dj ? f.y : 1.0f - f.y);
      const uint32_t i = uint32_t(std::clamp(int(lo.x) + di, 0, int(tex.width) - 1));
      const uint32_t j = uint32_t(std::clamp(int(lo.y) + dj, 0, int(tex.height) - 1));
      texel[k] = size_t(j) * tex.width + i;
      for (int q = 0; q < k; ++q) {
        if (texel[q] == texel[k]) {
          weight[q] += weight[k];
          weight[k] = 0.0f;
          break;
        }
      }
    }
    double variance = 0.0;
    r.illuminanceLux = Rgb(0.0f);
    for (int k = 0; k < 4; ++k) {
      r.illuminanceLux += weight[k] * texels[texel[k]];
      if (withErrors) {
        const double s = luminance((*errors)[texel[k]]);
        variance += double(weight[k]) * double(weight[k]) * s * s;
      }
    }
    r.fromLightTexture = true;
    if (withErrors) r.stdErrorLuminanceLux = float(std::sqrt(variance));
  } else {
    const std::vector<Rgb>& lux = back ? rdb.backLux : rdb.frontLux;
    r.illuminanceLux = w[0] * lux[v[0]] + w[1] * lux[v[1]] + w[2] * lux[v[2]];
    const std::vector<Rgb>* errors = map ? (back ? &map->backStdErrorLux : &map->frontStdErrorLux) : nullptr;
    if (errors && !errors->empty()) {
      double variance = 0.0;
      bool known = true;
      for (int k = 0; k < 3; ++k) {
        const uint32_t local = v[k] - mesh.firstVertex;  // the SDB mesh's vertex order
        if (local >= errors->size()) {
          known = false;
          break;
        }
        const double sigma = luminance((*errors)[local]);
        variance += double(w[k]) * w[k] * sigma * sigma;
      }
      if (known) r.stdErrorLuminanceLux = float(std::sqrt(variance));
    }
  }
  r.illuminanceLuminanceLux = luminance(r.illuminanceLux);
  return r;
}

}  // namespace fly::raster
