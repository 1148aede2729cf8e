// `--environment FILE.exr|FILE.hdr|studio` and `--environment-scale S` of `fly render` and `fly view`: an
// environment that sunlight mode shows behind the scene and lights it with (raster/renderer.h, image-based
// light) in place of the scene's sky and sun. A file is an equirectangular panorama in world directions
// (+Y up; u = φ/2π with φ = atan2(z, x), rows from the zenith: rdb::RasterSky's layout) of radiance in cd/m²,
// times S for a file in other units (e.g. S = 179 lm/W for radiance in W/(m² sr) of the visible band, the
// photometric equivalent of equal-energy white; or a measured scale). `studio` is cli/studio_environment.h.
// The file is decoded by OpenImageIO's module (cli/image_decoder_module.h): the GL engine gets float pixels.
#pragma once

#include <optional>
#include <string>

#include "rdb/raster_rdb.h"
#include "rdb/raster_sky.h"

namespace CLI {
class App;
}

namespace fly::cli {

struct EnvironmentOptions {
  std::string source;  // "" = none
  double scale = 1.0;  // cd/m² per file unit
};
void addEnvironmentOptions(CLI::App& sub, EnvironmentOptions& options);

// The environment the options name, or nullopt without --environment. UsageError for a scale that is not
// finite and > 0 or a scale without an environment; InputError naming the file for one that cannot be read
// or decoded, or with a negative or non-finite value (naming the pixel).
std::optional<rdb::RasterSky> loadEnvironment(const EnvironmentOptions& options);

// Puts `environment` in place of rdb's sky and sun: sunlight mode then shows and is lit by it alone (the
// scene's sun, a directional light of the sky's model, is left out with its sky), and its daylight ambient
// levels (rdb::DirectionalAmbient, for renderers without image-based light) are the environment's upper and
// lower hemispheres' horizontal illuminance.
void applyEnvironment(rdb::RasterRdb& rdb, const rdb::RasterSky& environment);

// "environment FILE (W×H, scale S)" or "environment studio …" for the commands' summaries; "" without one.
std::string environmentLine(const EnvironmentOptions& options, const std::optional<rdb::RasterSky>& environment);

}  // namespace fly::cli
