// Baked light, handed from the raytracer's results to the GL engine (DESIGN.md: the engines share baked
// results only through the LightMapStore). Plain data: the CLI fills it from a bake in memory or from a baked
// scene directory (cli/baked_light_maps.h); the raster engine reads it.
#pragma once

#include <cstdint>
#include <vector>

#include "base/color.h"

namespace fly::rdb {

// The baked irradiance of one placed mesh: SDB node `sdbNodeId` holding SDB mesh `sdbMeshId`.
struct MeshLightMap {
  uint32_t sdbNodeId = 0, sdbMeshId = 0;
  // Irradiance, lux per channel, on the front (the side the shading normal points to) and the back of the
  // surface, per vertex of the SDB mesh, in the SDB mesh's vertex order. backLux is empty for a one-sided
  // mesh.
  std::vector<Rgb> frontLux, backLux;
};

struct LightMapStore {
  std::vector<MeshLightMap> meshes;

  // The light map of SDB mesh `sdbMeshId` as placed by node `sdbNodeId`, or nullptr when none was baked.
  const MeshLightMap* find(uint32_t sdbNodeId, uint32_t sdbMeshId) const;
};

}  // namespace fly::rdb
