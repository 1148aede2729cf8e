// Bake settings a scene file may carry; CLI flags override them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace fly::sdb {

struct BakeSettings {
  uint32_t samples = 0;            // samples per vertex/texel, a power of two; 0 = until another limit stops it
  double targetErrorRel = 0.01;    // target relative standard error (95th percentile), (0, 1); default 1 %
  double timeLimitS = 0.0;         // seconds; 0 = no limit
  // A cap on the reflections of indirect light, [0, 10000]; none (the default) = paths end by Russian roulette
  // alone, the unbiased answer. A cap removes the light of longer paths, which fly estimates and reports.
  std::optional<uint32_t> maxBounces;
  double texelsPerMetre = 20.0;    // light-texture density, texels/m, (0, 1000]
  // Meshes or nodes (by name) that get light textures in addition to vertex light maps.
  std::vector<std::string> lightTextureNames;
};

}  // namespace fly::sdb
