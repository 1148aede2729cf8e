#include "cli/raster_scene.h"

#include <algorithm>
#include <cstdio>

#include "base/error.h"
#include "cli/baked_light_maps.h"
#include "cli/baked_manifest.h"
#include "cli/baked_scene.h"
#include "cli/scene_daylight.h"
#include "sdb/scene_load.h"

namespace fly::cli {

namespace {

std::filesystem::path bakedScenePath(const std::filesystem::path& dir, const nlohmann::json& manifest) {
  if (const std::optional<std::filesystem::path> scene = findBakedSourceScene(dir, manifest)) return *scene;
  throw InputError({(dir / "manifest.json").string(), 0, 0, "/scene"},
                   "names the scene " + manifest.value("scene", std::string()) + ", which does not exist",
                   "put the scene file back at that path, or bake it again with fly bake");
}

}  // namespace

RasterScene loadRasterScene(const std::filesystem::path& sceneOrBakedDir, const DaylightOptions& daylight) {
  RasterScene r;
  r.scenePath = sceneOrBakedDir;
  nlohmann::json bakedDaylight;
  std::string manifestPath;
  if (isBakedScene(r.scenePath)) {
    const nlohmann::json manifest = readBakedManifest(r.scenePath);
    r.lightMaps = readBakedLightMaps(r.scenePath);
    manifestPath = (r.scenePath / "manifest.json").string();
    bakedDaylight = manifest.value("daylight", nlohmann::json());
    r.bakedSunTime = bakedSunTime(manifest);
    r.bakedSunlight = bakedSunlightText(manifest);
    r.scenePath = bakedScenePath(r.scenePath, manifest);
  }
  LitScene lit = loadLitScene(r.scenePath, daylight, bakedDaylight, manifestPath);
  r.scene = std::move(lit.scene);
  r.light = std::move(lit.light);
  return r;
}

void parseSize(const std::string& text, uint32_t& widthPx, uint32_t& heightPx) {
  unsigned a = 0, b = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%u%c%u%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X') || a < 1 ||
      b < 1 || a > 16384 || b > 16384) {
    throw UsageError("--size " + text + ": expected WIDTHxHEIGHT in pixels, each 1 to 16384 (e.g. 1280x720)");
  }
  widthPx = a;
  heightPx = b;
}

raster::RenderMode parseRenderMode(const std::string& name) {
  if (name == "simple") return raster::RenderMode::kSimple;
  if (name == "lightmap") return raster::RenderMode::kLightMap;
  if (name == "sunlight") return raster::RenderMode::kSunlight;
  throw UsageError("--mode " + name + ": expected simple, lightmap or sunlight");
}

ToneOperator parseToneOperator(const std::string& name) {
  if (name == "linear") return ToneOperator::kLinear;
  if (name == "reinhard") return ToneOperator::kReinhard;
  if (name == "filmic") return ToneOperator::kFilmic;
  throw UsageError("--operator " + name + ": expected linear, reinhard or filmic");
}

void addShadowOptions(CLI::App& sub, ShadowOptions& options) {
  sub.add_option("--shadows", options.mode,
                 "the sun's shadows where its direct term is drawn: classic (shadow volumes of every sun-facing "
                 "triangle; exact, the default), vismap (of the triangles a visibility map from the sun finds, "
                 "and those a depth test cannot prove hidden: fewer, so faster frames in interiors and cars, "
                 "but slower rebuilds when the sun moves) or off");
  sub.add_option("--shadow-map", options.visibilityMapTexels,
                 "texels per side of the sun's visibility map (--shadows vismap), 16 to 16384 (default 1024)");
  sub.add_option("--glass-map", options.transmittanceMapTexels,
                 "texels per side of the sun's transmittance map through clear glass, 16 to 16384 (default "
                 "1024): finer follows a pane's edge more closely");
}

void addBallOption(CLI::App& sub, uint32_t& ballTexels) {
  sub.add_option("--ball", ballTexels,
                 "texels per side of the ball textures that show measured-BRDF materials (FLY §4), 8 to 4096 "
                 "(default 256; a sharp clear coat needs more, docs/ball-textures.md)");
}

raster::BallSettings parseBallOption(uint32_t ballTexels) {
  if (ballTexels < 8 || ballTexels > 4096)
    throw UsageError("--ball " + std::to_string(ballTexels) + ": give 8 to 4096 texels per side");
  raster::BallSettings b;
  b.sizePx = ballTexels;
  b.envSizePx = std::max(4u, ballTexels / 4);
  return b;
}

std::string measuredBrdfLine(const rdb::RasterRdb& rdb, const raster::BallSettings& balls) {
  if (rdb.measuredBrdfs.empty()) return "";
  size_t tables = 0;
  for (const rdb::RasterMeasuredBrdf& b : rdb.measuredBrdfs) tables += b.kind == rdb::RasterBrdfKind::kTable;
  const size_t paints = rdb.measuredBrdfs.size() - tables;
  std::string kinds;
  if (paints) kinds += "car paint " + std::to_string(paints);
  if (tables) kinds += std::string(kinds.empty() ? "" : ", ") + "MERL table " + std::to_string(tables);
  const std::string n = std::to_string(balls.sizePx);
  return "brdf      " + std::to_string(rdb.measuredBrdfs.size()) + " measured material" +
         (rdb.measuredBrdfs.size() == 1 ? "" : "s") + " (" + kinds + "), shown by " + n + "×" + n +
         " ball textures under the current lights (near lamps per pixel)\n";
}

raster::SunShadowSettings parseShadowOptions(const ShadowOptions& options) {
  raster::SunShadowSettings s;
  if (options.mode == "vismap") {
    s.mode = raster::SunShadowMode::kVisibilityMap;
  } else if (options.mode == "classic") {
    s.mode = raster::SunShadowMode::kSunFacing;
  } else if (options.mode == "off") {
    s.mode = raster::SunShadowMode::kOff;
  } else {
    throw UsageError("--shadows " + options.mode + ": give vismap, classic or off");
  }
  auto texels = [](const char* option, uint32_t n) {
    if (n < 16 || n > 16384) {
      throw UsageError(std::string(option) + " " + std::to_string(n) + ": give 16 to 16384 texels per side");
    }
    return n;
  };
  s.visibilityMapTexels = texels("--shadow-map", options.visibilityMapTexels);
  s.transmittanceMapTexels = texels("--glass-map", options.transmittanceMapTexels);
  return s;
}

raster::RenderMode chooseRenderMode(const rdb::RasterRdb& rdb,
                                    const std::optional<raster::RenderMode>& requested,
                                    const std::filesystem::path& scenePath) {
  const std::vector<raster::RenderMode> modes = raster::supportedModes(rdb);
  if (!requested) return modes.front();
  if (std::find(modes.begin(), modes.end(), *requested) == modes.end()) {
    throw UsageError(std::string("--mode ") + raster::renderModeName(*requested) + ": " + scenePath.string() +
                     (*requested == raster::RenderMode::kLightMap
                          ? " has no light maps (render a baked directory)"
                          : " has neither sky nor sun (give --lat --lon --time, or --sun-dir AZ,EL, "
                            "to add daylight)"));
  }
  return *requested;
}

size_t findCamera(const rdb::RasterRdb& rdb, const std::string& name) {
  const auto it = std::find_if(rdb.cameras.begin(), rdb.cameras.end(),
                               [&](const rdb::RasterCamera& c) { return c.name == name; });
  if (it != rdb.cameras.end()) return size_t(it - rdb.cameras.begin());
  std::string names;
  for (const rdb::RasterCamera& c : rdb.cameras)
    names += (names.empty() ? "" : ", ") + ("\"" + c.name + "\"");
  throw UsageError("--camera " + name + ": the scene has no such camera (" +
                   (names.empty() ? std::string("it has none") : "it has " + names) + ")");
}

}  // namespace fly::cli
