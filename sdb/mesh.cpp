#include "sdb/mesh.h"

namespace fly::sdb {

std::string validate(const Mesh& m) {
  const size_t n = m.positions.size();
  auto sized = [n](size_t s) { return s == 0 || s == n; };
  if (!sized(m.normals.size())) return "normals count differs from positions count";
  if (!sized(m.tangents.size())) return "tangents count differs from positions count";
  if (!sized(m.uv0.size())) return "uv0 count differs from positions count";
  if (!sized(m.uv1.size())) return "uv1 count differs from positions count";
  if (!sized(m.colors.size())) return "colors count differs from positions count";
  if (m.indices.size() % 3 != 0) return "index count is not a multiple of 3";
  for (uint32_t i : m.indices) {
    if (i >= n) return "index " + std::to_string(i) + " is past the vertex count " + std::to_string(n);
  }
  if (m.lightTexture.enabled && !(m.lightTexture.texelsPerMetre >= 0.0f && m.lightTexture.texelsPerMetre <= 1000.0f)) {
    return "light-texture density must be in [0, 1000] texels/m";
  }
  return "";
}

}  // namespace fly::sdb
