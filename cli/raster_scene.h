// What `fly render` and `fly view` share: a scene file, glTF model or baked scene directory loaded for the
// OpenGL engine (with a baked directory's light maps), and the options both take (mode, operator, size,
// camera, the sun's shadows).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "base/tone_map.h"
#include "cli/site_options.h"
#include "raster/renderer.h"
#include "rdb/light_map_store.h"
#include "rdb/raster_rdb.h"
#include "sdb/scene.h"

namespace fly::cli {

struct RasterScene {
  std::filesystem::path scenePath;  // the scene file; for a baked directory, the scene it was baked from
  sdb::Scene scene;
  std::optional<rdb::LightMapStore> lightMaps;  // a baked directory's
  std::string light;                            // what lights it (cli/scene_daylight.h, describeLight)
  // A baked directory's: when its light was baked (cli/baked_manifest.h, bakedSunTime; "" when the bake kept
  // no sun-direct part) and the line on what sunlight mode shows of it (bakedSunlightText).
  std::string bakedSunTime;
  std::string bakedSunlight;
};

// Loads `sceneOrBakedDir` with its daylight (cli/scene_daylight.h, loadLitScene: a baked directory's recorded
// daylight, then `daylight`'s options). A baked directory names its scene in manifest.json: that path as
// given to fly bake, resolved against the current directory, else against the baked directory's parent.
// UsageError for bad options, InputError for unreadable input.
RasterScene loadRasterScene(const std::filesystem::path& sceneOrBakedDir, const DaylightOptions& daylight);

// --size WIDTHxHEIGHT, each 1..16384 pixels; UsageError otherwise.
void parseSize(const std::string& text, uint32_t& widthPx, uint32_t& heightPx);
// --mode simple|lightmap|sunlight; UsageError otherwise.
raster::RenderMode parseRenderMode(const std::string& name);
// --operator linear|reinhard|filmic; UsageError otherwise.
ToneOperator parseToneOperator(const std::string& name);
// --shadows vismap|classic|off, --shadow-map N and --glass-map N (raster/sun_shadows.h, raster/sun_glass.h):
// adds them to `sub`, and checks and converts their values (UsageError naming the option otherwise).
struct ShadowOptions {
  std::string mode = "classic";
  uint32_t visibilityMapTexels = 1024;
  uint32_t transmittanceMapTexels = 1024;
};
void addShadowOptions(CLI::App& sub, ShadowOptions& options);
raster::SunShadowSettings parseShadowOptions(const ShadowOptions& options);
// --ball N (raster/ball_texture.h): the measured materials' ball textures, N × N texels (8 to 4096), the
// environment term at N/4; adds it to `sub`, and checks and converts its value (UsageError otherwise).
void addBallOption(CLI::App& sub, uint32_t& ballTexels);
raster::BallSettings parseBallOption(uint32_t ballTexels);
// What the scene's measured materials are and how they are shown: "" without any, else a line for the
// command's summary ("brdf      2 measured materials (car paint 1, table 1), 256² ball textures …").
std::string measuredBrdfLine(const rdb::RasterRdb& rdb, const raster::BallSettings& balls);

// `requested` when the scene supports it (UsageError saying why not otherwise), else the best mode it
// supports (raster::supportedModes).
raster::RenderMode chooseRenderMode(const rdb::RasterRdb& rdb,
                                    const std::optional<raster::RenderMode>& requested,
                                    const std::filesystem::path& scenePath);

// The index in rdb.cameras of the camera called `name`; UsageError listing the scene's cameras otherwise.
size_t findCamera(const rdb::RasterRdb& rdb, const std::string& name);

}  // namespace fly::cli
