// The GL engine's optional image passes on the command line of `fly render` and `fly view`: --ssao,
// --ssao-radius M (raster/ambient_occlusion.h) and --bloom [STRENGTH], --bloom-threshold X (raster/bloom.h).
// Both are off unless asked for.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "raster/ambient_occlusion.h"
#include "raster/bloom.h"

namespace fly::cli {

struct PostOptions {
  bool ssao = false;
  float ssaoRadiusM = raster::AmbientOcclusionSettings{}.radiusM;
  std::vector<std::string> bloom;  // --bloom's optional STRENGTH
  float bloomThreshold = raster::BloomSettings{}.thresholdExposed;
  CLI::Option* bloomOption = nullptr;
  CLI::Option* ssaoRadiusOption = nullptr;
};

// The strength --bloom gives without a value: 5 % of the light above the threshold spreads.
inline constexpr float kDefaultBloomStrength = 0.05f;

void addPostOptions(CLI::App& sub, PostOptions& options);
// Checks and converts the values (UsageError naming the option otherwise). --ssao-radius alone turns the
// occlusion on.
raster::AmbientOcclusionSettings parseAmbientOcclusion(const PostOptions& options);
raster::BloomSettings parseBloom(const PostOptions& options);

}  // namespace fly::cli
