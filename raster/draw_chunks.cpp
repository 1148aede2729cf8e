#include "raster/draw_chunks.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace fly::raster {

namespace {

// x's low 10 bits spread to every third bit (the Morton code's interleave).
uint32_t spreadBits(uint32_t x) {
  x &= 0x3ffu;
  x = (x | (x << 16)) & 0x030000ffu;
  x = (x | (x << 8)) & 0x0300f00fu;
  x = (x | (x << 4)) & 0x030c30c3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

// The triangles of indices[first, first + count) in the Morton order of their centroids on a 1024³ lattice
// over the range's box.
void sortSpatially(std::vector<uint32_t>& indices, uint32_t first, uint32_t count, const std::vector<vec3>& positionsM) {
  const uint32_t triangles = count / 3;
  std::vector<vec3> centroid(triangles);
  vec3 lo(INFINITY), hi(-INFINITY);
  for (uint32_t t = 0; t < triangles; ++t) {
    const uint32_t* v = &indices[first + 3 * t];
    centroid[t] = (positionsM[v[0]] + positionsM[v[1]] + positionsM[v[2]]) / 3.0f;
    lo = glm::min(lo, centroid[t]);
    hi = glm::max(hi, centroid[t]);
  }
  const vec3 scale = 1023.0f / glm::max(hi - lo, vec3(1e-30f));
  std::vector<std::pair<uint32_t, uint32_t>> keyed(triangles);  // (Morton code, triangle)
  for (uint32_t t = 0; t < triangles; ++t) {
    const glm::uvec3 q(glm::clamp((centroid[t] - lo) * scale, vec3(0.0f), vec3(1023.0f)));
    keyed[t] = {spreadBits(q.x) | (spreadBits(q.y) << 1) | (spreadBits(q.z) << 2), t};
  }
  std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const std::vector<uint32_t> old(indices.begin() + first, indices.begin() + first + 3 * triangles);
  for (uint32_t k = 0; k < triangles; ++k) {
    for (uint32_t c = 0; c < 3; ++c) indices[first + 3 * k + c] = old[3 * keyed[k].second + c];
  }
}

}  // namespace

void appendDrawChunks(std::vector<uint32_t>& indices, uint32_t first, uint32_t count,
                      const std::vector<vec3>& positionsM, std::vector<DrawChunk>& chunks) {
  constexpr uint32_t kIndicesPerChunk = 3 * kTrianglesPerChunk;
  if (count > kIndicesPerChunk) sortSpatially(indices, first, count, positionsM);
  for (uint32_t start = first; start < first + count; start += kIndicesPerChunk) {
    DrawChunk c;
    c.firstIndex = start;
    c.indexCount = std::min(kIndicesPerChunk, first + count - start);
    c.loM = vec3(INFINITY);
    c.hiM = vec3(-INFINITY);
    for (uint32_t i = start; i < start + c.indexCount; ++i) {
      const vec3& p = positionsM[indices[i]];
      c.loM = glm::min(c.loM, p);
      c.hiM = glm::max(c.hiM, p);
    }
    chunks.push_back(c);
  }
}

void visibleRanges(const std::vector<DrawChunk>& chunks, const mat4& clipFromWorld, const NdcRect& rect,
                   std::vector<IndexRange>& ranges) {
  ranges.clear();
  // The rows of clipFromWorld (glm is column-major: m[column][row]); a point p is inside where
  // x0 w ≤ x ≤ x1 w, y0 w ≤ y ≤ y1 w and −w ≤ z ≤ w, each a plane dot(plane, (p, 1)) ≥ 0 (Gribb & Hartmann,
  // "Fast extraction of viewing frustum planes from the world-view-projection matrix", 2001).
  vec4 row[4];
  for (int r = 0; r < 4; ++r) row[r] = vec4(clipFromWorld[0][r], clipFromWorld[1][r], clipFromWorld[2][r], clipFromWorld[3][r]);
  const vec4 planes[6] = {row[0] - rect.x0 * row[3], rect.x1 * row[3] - row[0], row[1] - rect.y0 * row[3],
                          rect.y1 * row[3] - row[1], row[2] + row[3],           row[3] - row[2]};
  for (const DrawChunk& c : chunks) {
    const vec3 centre = 0.5f * (c.loM + c.hiM), half = 0.5f * (c.hiM - c.loM);
    bool outside = false;
    for (const vec4& pl : planes) {
      const vec3 n(pl);
      // The box's largest signed distance (times |n|) from the plane; outside where even that is below 0 by
      // more than float rounding of the terms.
      const float centreSide = glm::dot(n, centre) + pl.w;
      const float reach = glm::dot(glm::abs(n), half);
      const float rounding = 1e-5f * (glm::dot(glm::abs(n), glm::abs(centre)) + reach + std::abs(pl.w));
      if (centreSide + reach < -rounding) {
        outside = true;
        break;
      }
    }
    if (outside) continue;
    if (!ranges.empty() && ranges.back().firstIndex + ranges.back().indexCount == c.firstIndex) {
      ranges.back().indexCount += c.indexCount;
    } else {
      ranges.push_back({c.firstIndex, c.indexCount});
    }
  }
}

}  // namespace fly::raster
