// The daylight of the scene a command lights: the daylight options (cli/site_options.h) applied to the SDB
// scene, the default daylight of a plain glTF model without lights, the record of both in a bake, and the
// line that tells the user what lights the scene. The result is an ordinary SDB site, time and sky, which
// rdb lowers like a scene file's (rdb/site_lowering.h): both engines see the same light.
//
// The default daylight. A glTF model given without a scene file that has no lights and no materials that
// emit light in physical units (KHR_materials_emissive_strength; emission without it is a display colour),
// and no daylight options, would be black; it is put in a clear sky instead (sky "clear",
// turbidity 3, with the sun), with the sun placed directly at elevation 45°, azimuth 135° (south-east;
// north along the model's −Z). Why: a clear sky is the daylight in which products and buildings are most
// often shown and has both a sun (shape, shading, shadows in a bake) and a sky (soft fill from every side);
// a 45° sun is a temperate mid-morning or mid-afternoon sun, high enough to light the model's sides and its
// top; from the south-east it lights the model's front (+Z, glTF's forward) and its right (+X) from behind a
// viewer standing in front of it, so that the two sides differ. No ground is added: the model stands over the
// baker's black lower hemisphere (a non-reflecting ground), and the GL engine's ambient term keeps its
// kRasterGroundAlbedo ground (rdb/raster_sky.h).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli/site_options.h"
#include "sdb/scene.h"

namespace fly::cli {

// The default daylight's sun (see above), degrees, and its sky's turbidity.
inline constexpr double kDefaultSunAzimuthDeg = 135.0;
inline constexpr double kDefaultSunElevationDeg = 45.0;
inline constexpr double kDefaultTurbidity = 3.0;

// A scene with its daylight as a command lights it.
struct LitScene {
  sdb::Scene scene;
  bool defaultDaylight = false;  // the default daylight of a plain model (above)
  std::string light;             // one line: what lights the scene, with the daylight's figures
};

// True for a glTF model given on its own (.gltf, .glb), which the default daylight may light.
bool isPlainModel(const std::filesystem::path& scenePath);

// Applies the options to `scene` (a scene file's values are overridden option by option; a scene without
// daylight gets a clear sky with the sun when any daylight option is given) and, for a plain model without
// lights, emissive materials and options, the default daylight. Returns whether the default was applied.
// UsageError (exit 2) naming the option for a value out of range, a malformed value and contradictory
// options (a sun direction with a site or time, --time without a site, a Perez sky without a weather file
// …); InputError for an unreadable weather file.
bool applyDaylightOptions(sdb::Scene& scene, const DaylightOptions& options, bool plainModel);

// The line that says what lights the scene (lights, emissive meshes, the daylight's sky, sun position and
// horizontal illuminances in lux), e.g. "default daylight (no lights in truck.gltf): clear sky …".
std::string describeLight(const sdb::Scene& scene, bool defaultDaylight);

// sdb::loadScene, the daylight recorded by a bake (`baked`: the "daylight" of the file `bakedFile`, or null)
// and then the options, described by describeLight.
LitScene loadLitScene(const std::filesystem::path& scenePath, const DaylightOptions& options,
                      const nlohmann::json& baked = nullptr, const std::string& bakedFile = "");

// The scene's site, time and sky as a bake records them ("daylight" in manifest.json and the checkpoint),
// so that the bake's light maps are shown, resumed and described under the light they were baked with.
nlohmann::json daylightJson(const sdb::Scene& scene, bool defaultDaylight);

// The scene's time shifted by addHours, as the site's local civil time with its UTC offset then:
// "2026-09-15T17:30:00+03:00" (steps in UTC, so that a daylight-saving change neither repeats nor skips one).
// The scene must have a site and a local time.
std::string sceneLocalTime(const sdb::Scene& scene, double addHours = 0.0);

// Sets the recorded site, time and sky on `scene` (the site's map grid stays the scene's). Returns the
// record's "default". InputError naming `file` for a malformed record.
bool applyDaylightJson(sdb::Scene& scene, const nlohmann::json& record, const std::string& file);

}  // namespace fly::cli
