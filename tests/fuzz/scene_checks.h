// Postconditions of an imported or parsed scene that the fuzz targets check: what the importer promises
// (sdb/gltf_import.h: NaN/Inf positions and bad normals are fixed; indices are in range), and that the
// summaries `fly info` prints can be computed.
#pragma once

#include <cmath>

#include "sdb/features.h"
#include "sdb/scene.h"
#include "sdb/scene_stats.h"
#include "tests/fuzz/fuzz_support.h"

namespace fly::fuzz {

inline void checkScene(const sdb::Scene& scene) {
  for (const auto& [id, mesh] : scene.meshes()) {
    require(sdb::validate(mesh).empty(), "mesh attributes and indices are consistent");
    for (const vec3& p : mesh.positions) {
      require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), "positions are finite");
    }
    for (const vec3& n : mesh.normals) {
      require(std::abs(glm::length(n) - 1.0f) < 1e-3f, "normals have unit length");
    }
  }
  sdb::computeStats(scene);
  sdb::computeFeatures(scene);
}

}  // namespace fly::fuzz
