#include "rdb/light_map_store.h"

#include <algorithm>

namespace fly::rdb {

const MeshLightMap* LightMapStore::find(uint32_t sdbNodeId, uint32_t sdbMeshId) const {
  const auto it = std::find_if(meshes.begin(), meshes.end(), [&](const MeshLightMap& m) {
    return m.sdbNodeId == sdbNodeId && m.sdbMeshId == sdbMeshId;
  });
  return it == meshes.end() ? nullptr : &*it;
}

}  // namespace fly::rdb
