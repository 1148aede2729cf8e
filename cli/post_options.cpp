#include "cli/post_options.h"

#include <cmath>
#include <cstdlib>

#include "base/error.h"

namespace fly::cli {

void addPostOptions(CLI::App& sub, PostOptions& options) {
  sub.add_flag(
      "--ssao", options.ssao,
      "screen-space ambient occlusion of the ambient term in simple mode (where no light map holds the "
      "scene's own shadowing); off by default");
  options.ssaoRadiusOption =
      sub.add_option("--ssao-radius", options.ssaoRadiusM,
                     "the ambient occlusion's reach in metres, (0, 10000] (default 0.5); implies --ssao");
  options.bloomOption =
      sub.add_option("--bloom", options.bloom,
                     "glare around the sun and bright highlights: the fraction STRENGTH in [0, 1] "
                     "of the light above the threshold spread around it, energy kept (default "
                     "0.05 when given without a value); off by default")
          ->expected(0, 1);
  sub.add_option(
      "--bloom-threshold", options.bloomThreshold,
      "the exposed value above which light glows, > 0 (default 1: the luminance 1.2 · 2^EV100 cd/m² "
      "the linear operator shows as white)");
}

raster::AmbientOcclusionSettings parseAmbientOcclusion(const PostOptions& options) {
  raster::AmbientOcclusionSettings s;
  s.enabled = options.ssao || (options.ssaoRadiusOption && options.ssaoRadiusOption->count() > 0);
  if (!(options.ssaoRadiusM > 0.0f && options.ssaoRadiusM <= 1e4f)) {
    throw UsageError("--ssao-radius " + std::to_string(options.ssaoRadiusM) +
                     ": give a radius in (0, 10000] metres");
  }
  s.radiusM = options.ssaoRadiusM;
  return s;
}

raster::BloomSettings parseBloom(const PostOptions& options) {
  raster::BloomSettings s;
  if (!(options.bloomThreshold > 0.0f && std::isfinite(options.bloomThreshold))) {
    throw UsageError("--bloom-threshold " + std::to_string(options.bloomThreshold) +
                     ": give a finite exposed value > 0");
  }
  s.thresholdExposed = options.bloomThreshold;
  if (!options.bloomOption || options.bloomOption->count() == 0) return s;
  s.strength = kDefaultBloomStrength;
  if (!options.bloom.empty() && !options.bloom.front().empty()) {  // CLI11 gives "" for --bloom alone
    const std::string& text = options.bloom.front();
    char* end = nullptr;
    const float k = std::strtof(text.c_str(), &end);
    if (*end != '\0' || !(k >= 0.0f && k <= 1.0f)) {
      throw UsageError("--bloom " + text +
                       ": give a strength in [0, 1] (the fraction of the light above the "
                       "threshold that spreads), or --bloom alone for 0.05");
    }
    s.strength = k;
  }
  return s;
}

}  // namespace fly::cli
