#include "rdb/vertex_weld.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace fly::rdb {

float weldToleranceM(float boundsDiagonalM) {
  return std::isfinite(boundsDiagonalM) ? std::max(1e-6f * boundsDiagonalM, 1e-9f) : 1e-9f;
}

namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

}  // namespace

std::vector<uint32_t> weldCoincidentVertices(std::span<const vec3> positionsM, std::span<const vec3> normals,
                                             float toleranceM) {
  const size_t n = positionsM.size();
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  if (n == 0 || !(toleranceM > 0.0f)) return parent;
  const bool withNormals = normals.size() == n;
  // Cells of twice the tolerance: two vertices within the tolerance lie in the same or adjacent cells.
  const double cell = 2.0 * double(toleranceM);
  auto key = [](int64_t x, int64_t y, int64_t z) {
    return uint64_t(x) * 0x9E3779B97F4A7C15ull ^ uint64_t(y) * 0xC2B2AE3D27D4EB4Full ^
           uint64_t(z) * 0x165667B19E3779F9ull;
  };
  std::unordered_multimap<uint64_t, uint32_t> grid;
  grid.reserve(n);
  struct Cell { int64_t x, y, z; };
  std::vector<Cell> cellOf(n);
  std::vector<bool> valid(n, false);
  for (uint32_t v = 0; v < n; ++v) {
    const vec3& p = positionsM[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    if (withNormals && !(std::isfinite(normals[v].x) && std::isfinite(normals[v].y) &&
                         std::isfinite(normals[v].z) && glm::dot(normals[v], normals[v]) > 0.0f))
      continue;
    const dvec3 c = glm::floor(dvec3(p) / cell);
    if (glm::any(glm::greaterThan(glm::abs(c), dvec3(4e18)))) continue;
    valid[v] = true;
    cellOf[v] = {int64_t(c.x), int64_t(c.y), int64_t(c.z)};
    grid.emplace(key(cellOf[v].x, cellOf[v].y, cellOf[v].z), v);
  }
  for (uint32_t v = 0; v < n; ++v) {
    if (!valid[v]) continue;
    const Cell c = cellOf[v];
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const auto [begin, end] = grid.equal_range(key(c.x + dx, c.y + dy, c.z + dz));
          for (auto it = begin; it != end; ++it) {
            const uint32_t w = it->second;
            if (w <= v) continue;
            const vec3 d = glm::abs(positionsM[w] - positionsM[v]);
            if (d.x > toleranceM || d.y > toleranceM || d.z > toleranceM) continue;
            if (withNormals && glm::dot(glm::normalize(normals[v]), glm::normalize(normals[w])) < kWeldNormalCos)
              continue;
            const uint32_t a = findRoot(parent, v);
            const uint32_t b = findRoot(parent, w);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
          }
        }
  }
  for (uint32_t v = 0; v < n; ++v) parent[v] = findRoot(parent, v);
  return parent;
}

}  // namespace fly::rdb
