// Counts and bounds of a scene, as `fly info` reports them.
#pragma once

#include <map>
#include <string>

#include "base/math.h"
#include "sdb/scene.h"

namespace fly::sdb {

struct SceneStats {
  size_t nodes = 0;
  size_t meshes = 0;          // mesh entities (one per glTF primitive)
  size_t meshInstances = 0;   // (node, mesh) pairs in the hierarchy
  size_t triangles = 0;       // over all instances
  size_t vertices = 0;        // over all instances
  size_t materials = 0;
  size_t textures = 0;
  size_t cameras = 0;
  size_t lights = 0;
  std::map<std::string, size_t> materialsByClass;  // materialClass() → count
  std::map<std::string, size_t> lightsByType;      // lightTypeName() → count
  size_t emissiveMeshes = 0;                       // placed meshes with an emissive material (area lights)
  Bounds3 boundsWorldM;                            // of all instanced positions, world frame, metres
};

SceneStats computeStats(const Scene& scene);

}  // namespace fly::sdb
