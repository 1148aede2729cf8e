// `fly render`: one view of a scene or a baked scene through the OpenGL engine, headless (EGL), into a PNG
// (tone-mapped sRGB) or an EXR (luminance in cd/m²).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/image_io.h"
#include "base/log.h"
#include "base/tone_map.h"
#include "cli/bake_options.h"
#include "cli/baked_light_maps.h"
#include "cli/baked_scene.h"
#include "cli/command.h"
#include "cli/illuminance_view.h"
#include "cli/image_metadata.h"
#include "cli/environment_option.h"
#include "cli/post_options.h"
#include "cli/raster_scene.h"
#include "cli/scene_daylight.h"
#include "raster/gl_context.h"
#include "raster/renderer.h"
#include "rdb/raster_rdb.h"
#include "sdb/scene_load.h"
#include "sunsky/civil_time.h"

namespace fly::cli {

namespace {

struct RenderOptions {
  std::string scene;
  std::string camera;
  std::string mode;
  std::string size = "1280x720";
  std::string out;
  std::optional<double> exposureEv100;
  double evCompensation = 0.0;  // stops added to the automatic exposure's brightness (--ev-comp)
  double dotsPerInch = 0.0;
  std::string falseColour;  // "lux": the bake's illuminance in false colour (cli/illuminance_view.h)
  bool autoExposure = false;
  std::string op = "filmic";
  float whitePoint = 4.0f;
  ShadowOptions shadows;
  PostOptions post;
  uint32_t ballTexels = 256;
  EnvironmentOptions environment;
  DaylightOptions daylight;
  std::string timeLapse;  // FROM,TO,STEP
};


std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The frames of --time-lapse FROM,TO,STEP: the scene's times FROM, FROM + STEP, … up to TO (inclusive),
// as hours after FROM. FROM and TO take --time's forms (local in the site's zone, UTC "…Z" or with an
// offset), STEP a duration (30m, 1h, 900s). UsageError for a malformed value, TO before FROM, or more than
// kMaxTimeLapseFrames frames.
constexpr size_t kMaxTimeLapseFrames = 10000;
struct TimeLapse {
  std::string from;
  std::vector<double> hoursAfterFrom;
};
std::vector<std::string> timeLapseParts(const std::string& text) {
  std::vector<std::string> parts;
  size_t begin = 0;
  for (size_t comma = text.find(',');; comma = text.find(',', begin)) {
    parts.push_back(text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  if (parts.size() != 3 || parts[0].empty() || parts[1].empty() || parts[2].empty()) {
    throw UsageError("--time-lapse " + text +
                     ": expected FROM,TO,STEP, e.g. 2026-06-21T06:00,2026-06-21T21:00,30m");
  }
  return parts;
}
TimeLapse parseTimeLapse(const std::string& text, const std::string& timeZone) {
  const std::vector<std::string> parts = timeLapseParts(text);
  const double stepH = parseDuration(parts[2], "--time-lapse STEP") / 3600.0;
  sunsky::UtcTime from, to;
  try {
    from = sunsky::parseTime(parts[0], timeZone, "--time-lapse FROM");
    to = sunsky::parseTime(parts[1], timeZone, "--time-lapse TO");
  } catch (const InputError& e) {
    throw UsageError(e.what());
  }
  const double spanH = (sunsky::julianDay(to) - sunsky::julianDay(from)) * 24.0;
  if (spanH < -1e-9) {
    throw UsageError("--time-lapse " + text + ": TO (" + to.iso() + ") is before FROM (" + from.iso() +
                     "); give the earlier time first");
  }
  const double frames = std::floor(std::max(spanH, 0.0) / stepH + 1e-6) + 1.0;
  if (!(frames <= double(kMaxTimeLapseFrames))) {
    throw UsageError("--time-lapse " + text + ": " + std::to_string(int64_t(std::min(frames, 1e15))) +
                     " frames, more than " + std::to_string(kMaxTimeLapseFrames) + "; give a longer STEP");
  }
  TimeLapse t{parts[0], {}};
  for (size_t k = 0; k < size_t(frames); ++k) t.hoursAfterFrom.push_back(double(k) * stepH);
  return t;
}

// OUT with its frame number before the extension: shadows.png → shadows-0003.png.
std::string framePath(const std::string& out, size_t frame) {
  const std::filesystem::path p(out);
  char number[32];
  std::snprintf(number, sizeof number, "-%04zu", frame);
  return (p.parent_path() / (p.stem().string() + number + p.extension().string())).string();
}

int runRender(const RenderOptions& options) {
  RenderOptions o = options;
  const std::string ext = lowerExtension(o.out);
  if (ext != ".png" && ext != ".exr") {
    throw UsageError("--out " + o.out + ": give a .png (tone-mapped sRGB) or .exr (luminance in cd/m²) file");
  }
  if (o.exposureEv100 && o.autoExposure)
    throw UsageError("give either --exposure or --auto-exposure, not both");
  if (o.exposureEv100 && !std::isfinite(*o.exposureEv100))
    throw UsageError("--exposure must be a finite EV100");
  if (!std::isfinite(o.evCompensation) || std::abs(o.evCompensation) > 10.0)
    throw UsageError("--ev-comp must be a number of stops in [-10, 10]");
  if (o.exposureEv100 && o.evCompensation != 0.0)
    throw UsageError("--ev-comp compensates the automatic exposure; with --exposure, give the EV100 you want");
  if (!(o.whitePoint > 0.0f) || !std::isfinite(o.whitePoint)) throw UsageError("--white-point must be > 0");
  if (!o.falseColour.empty()) {
    if (o.falseColour != "lux") {
      throw UsageError("--false-colour " + o.falseColour + ": expected lux (the bake's illuminance)");
    }
    if (ext != ".png") throw UsageError("--false-colour draws a PNG with a legend; give --out FILE.png");
    if (!o.mode.empty() || !o.timeLapse.empty()) {
      throw UsageError("--false-colour shows the bake's light maps; leave out --mode and --time-lapse");
    }
  }
  uint32_t width = 0, height = 0;
  parseSize(o.size, width, height);
  const ToneOperator op = parseToneOperator(o.op);
  const raster::SunShadowSettings shadows = parseShadowOptions(o.shadows);
  const raster::AmbientOcclusionSettings ambientOcclusion = parseAmbientOcclusion(o.post);
  const raster::BloomSettings bloom = parseBloom(o.post);
  const raster::BallSettings balls = parseBallOption(o.ballTexels);
  if (!o.environment.source.empty() && !o.timeLapse.empty())
    throw UsageError("--time-lapse moves the sun of the sky; --environment replaces both: give one of them");
  const std::optional<rdb::RasterSky> environment = loadEnvironment(o.environment);
  std::optional<raster::RenderMode> requestedMode;
  if (!o.mode.empty()) requestedMode = parseRenderMode(o.mode);
  const bool timeLapse = !o.timeLapse.empty();
  if (timeLapse) {
    if (!o.daylight.time.empty()) throw UsageError("give either --time or --time-lapse, not both");
    if (!o.daylight.sunDirection.empty()) {
      throw UsageError("--time-lapse moves the sun by the site's clock; it cannot be given with --sun-dir");
    }
    if (requestedMode == raster::RenderMode::kLightMap) {
      throw UsageError(
          "--time-lapse with --mode lightmap would draw the same image at every time (light maps show the "
          "bake's light); use --mode sunlight (the baked indirect light under the moving sun) or simple");
    }
    // The scene is loaded at the first time, which also checks that there is a site to give it.
    o.daylight.time = timeLapseParts(o.timeLapse).front();
  }

  // The scene, and the light maps of a baked directory.
  RasterScene loaded = loadRasterScene(o.scene, o.daylight);
  const std::filesystem::path& scenePath = loaded.scenePath;
  ImageSettings falseColourSettings;
  if (!o.falseColour.empty()) {
    if (!loaded.lightMaps) {
      throw UsageError(
          "--false-colour lux shows a bake's illuminance: give a baked directory (fly bake SCENE "
          "--out DIR), not " +
          o.scene);
    }
    falseColourSettings = daylightSettings(loaded.scene);  // the bake's daylight, before it is turned off
    showIlluminance(loaded.scene);
    requestedMode = raster::RenderMode::kLightMap;
  }
  const std::optional<rdb::LightMapStore>& lightMaps = loaded.lightMaps;
  const rdb::LightMapStore* maps = lightMaps ? &*lightMaps : nullptr;
  rdb::RasterRdb rdb = buildRasterRdb(loaded.scene, maps);
  if (rdb.indices.empty()) throw InputError({scenePath.string()}, "has no triangles to render");
  if (environment) applyEnvironment(rdb, *environment);
  std::optional<TimeLapse> lapse;
  if (timeLapse) {
    if (!loaded.scene.hasSite() || loaded.scene.time().localDateTime.empty()) {
      throw UsageError("--time-lapse needs a site: give --lat and --lon (and --tz), or a scene with a site");
    }
    lapse = parseTimeLapse(o.timeLapse, loaded.scene.site().timeZone);
    // Sunlight mode (the sky and the moving sun) unless another is asked for.
    if (!requestedMode && rdb.variants.sky) requestedMode = raster::RenderMode::kSunlight;
  }
  const std::optional<raster::RenderMode> mode = chooseRenderMode(rdb, requestedMode, scenePath);
  if (ambientOcclusion.enabled && mode && *mode != raster::RenderMode::kSimple) {
    log::warn(std::string("--ssao occludes simple mode's ambient term only; this is ") +
              raster::renderModeName(*mode) + " mode, which it leaves as it is (give --mode simple)");
  }

  // The view: the named camera, else the scene's first camera, else one framing the whole scene.
  const float aspect = float(width) / float(height);
  raster::View view;
  std::string viewName;
  if (!o.camera.empty()) {
    const rdb::RasterCamera& camera = rdb.cameras[findCamera(rdb, o.camera)];
    view = raster::viewOfCamera(camera);
    viewName = "camera \"" + camera.name + "\"";
  } else if (!rdb.cameras.empty()) {
    view = raster::viewOfCamera(rdb.cameras.front());
    viewName = "camera \"" + rdb.cameras.front().name + "\"";
  } else {
    view = raster::framingView(rdb.boundsM, aspect);
    viewName = "a view framing the whole scene";
  }

  const auto start = std::chrono::steady_clock::now();
  const std::unique_ptr<raster::GlContext> context = raster::createHeadlessContext();
  raster::Renderer renderer;
  renderer.upload(rdb);
  renderer.setSunShadows(shadows);
  renderer.setBallSettings(balls);
  renderer.setAmbientOcclusion(ambientOcclusion);
  renderer.setBloom(bloom);
  // Renders the current RasterRdb into `path`; the exposure is `ev100` when given, else automatic (returned).
  auto meter = [&](const std::vector<float>& rgb) {
    std::vector<float> lum(rgb.size() / 3);
    for (size_t i = 0; i < lum.size(); ++i) lum[i] = luminance(Rgb(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]));
    // Compensation as a camera's: +1 stop is twice the exposure, one EV100 less.
    return autoExposureEv100Histogram(lum) - o.evCompensation;
  };
  auto renderImage = [&](const std::string& path, std::optional<double> ev100) {
    // Emission given as a display colour shows at the exposure's white: with automatic exposure, the frame
    // is metered without it, then drawn again with it.
    renderer.setDisplayWhite(ev100 ? 1.0f / exposureScale(*ev100) : 0.0f);
    renderer.render(view, *mode, width, height);
    std::vector<float> rgb = renderer.luminanceRgb();
    if (!ev100 && renderer.hasDisplayEmission() && o.falseColour.empty()) {
      ev100 = meter(rgb);
      renderer.setDisplayWhite(1.0f / exposureScale(*ev100));
      renderer.render(view, *mode, width, height);
      rgb = renderer.luminanceRgb();
    }
    for (float v : rgb) {
      if (!std::isfinite(v))
        throw std::runtime_error("internal error: the render has a non-finite luminance");
    }
    ImageSettings settings = daylightSettings(loaded.scene);
    if (!o.falseColour.empty()) {
      IlluminanceView illuminance{int(width), int(height), illuminanceFromRender(rgb), {}, {}};
      illuminance.scale = falseColourScale(illuminance.lux, true);
      falseColourSettings.insert(
          falseColourSettings.end(),
          {{"fly:scene", scenePath.string()},
           {"fly:view", viewName},
           {"fly:quantity", "illuminance from the bake's light maps, lux (log scale)"}});
      illuminance.metadata = imageMetadata("Illuminance, lux", falseColourSettings, o.dotsPerInch);
      drawIlluminanceView(illuminance, path);
      return 0.0;
    }
    settings.insert(settings.end(), {{"fly:scene", scenePath.string()},
                                     {"fly:mode", raster::renderModeName(*mode)},
                                     {"fly:view", viewName}});
    if (ext == ".exr") {
      ImageRgbF image{int(width), int(height), rgb};
      ExrAttributes attributes = exrAttributes(imageMetadata("Render", settings, o.dotsPerInch));
      attributes.emplace_back("units",
                              "cd/m^2 (linear Rec.709 RGB, luminance Y = 0.2126 R + 0.7152 G + 0.0722 B)");
      writeExr(path, image, attributes);
      return 0.0;
    }
    if (!ev100) ev100 = meter(rgb);
    renderer.toneMap(ToneMapSettings{op, *ev100, o.whitePoint});
    const std::vector<uint8_t> px = renderer.srgb8();
    settings.emplace_back("fly:exposure", "EV100 " + std::to_string(*ev100) + ", white point " +
                                              std::to_string(o.whitePoint) + ", tone operator " + o.op);
    writePng(path, int(width), int(height), 3, px.data(), imageMetadata("Render", settings, o.dotsPerInch));
    return *ev100;
  };

  std::ostringstream t;
  t << "scene     " << scenePath.string() << " (" << rdb.triangleCount() << " triangles"
    << (lightMaps ? ", baked light maps" : "") << ")\n";
  t << "view      " << viewName << "\n";
  t << "mode      " << raster::renderModeName(*mode) << "\n";
  t << "light     " << loaded.light << "\n";
  t << measuredBrdfLine(rdb, balls) << environmentLine(o.environment, environment);
  if (lightMaps && *mode == raster::RenderMode::kSunlight) t << "baked     " << loaded.bakedSunlight << "\n";
  t << "OpenGL    " << context->info().major << "." << context->info().minor << " core, "
    << context->info().renderer << " (" << context->info().platform << ")\n";
  // What the last render's sun shadows took, when it drew them.
  // The scene's glTF lights where the Phong shades with them (simple mode, and sunlight mode without light
  // maps): the GL engine draws no shadows of theirs; a bake holds them.
  auto lampShadowLine = [&]() -> std::string {
    const bool phong = mode == raster::RenderMode::kSimple || (mode == raster::RenderMode::kSunlight && !rdb.variants.lightMap);
    if (rdb.lights.empty() || !phong) return "";
    return "lights    " + std::to_string(rdb.lights.size()) + (rdb.lights.size() == 1 ? " light shades" : " lights shade") +
           " without shadows: the GL engine draws the sun's shadows only (a bake holds the lights')\n";
  };
  auto shadowLine = [&]() -> std::string {
    if (renderer.stats().shadowPasses == 0) return lampShadowLine();
    const raster::SunShadowCounts c = renderer.sunShadowCounts();
    return "shadows   sun shadow volumes of " + std::to_string(c.keptTriangles) + " of " +
           std::to_string(c.casterTriangles) + " triangles, " + std::to_string(c.silhouetteEdges) +
           " silhouette edges (" +
           (shadows.mode == raster::SunShadowMode::kVisibilityMap
                ? std::to_string(shadows.visibilityMapTexels) + "² visibility map: " +
                      std::to_string(c.visibleTriangles) + " seen, " + std::to_string(c.keptByDepthTest) +
                      " kept by the depth test"
                : std::string("every triangle the sun can see")) +
           ")\n" + lampShadowLine();
  };
  // The sun through clear glass, when the last render drew it.
  auto glassLine = [&]() -> std::string {
    const raster::SunGlassCounts g = renderer.sunGlassCounts();
    if (g.glassTriangles == 0) return "";
    char size[32];
    std::snprintf(size, sizeof size, "%.1f", double(g.texelSizeM) * 100.0);
    return "glass     the sun through " + std::to_string(g.glassTriangles) +
           " clear-glass triangles times T(θ) (" + std::to_string(g.texels) + "² transmittance map, texels " +
           size + " cm)\n";
  };
  char buf[64];
  if (!lapse) {
    const double ev100 = renderImage(o.out, o.exposureEv100);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    t << shadowLine() << glassLine();
    t << "image     " << o.out << " (" << width << "×" << height;
    if (!o.falseColour.empty()) {
      t << "; illuminance in lux, false colour with a legend";
    } else if (ext == ".png") {
      std::snprintf(buf, sizeof buf, "%.2f", ev100);
      t << "; exposure EV100 " << buf;
      if (!o.exposureEv100) {
        char comp[32];
        std::snprintf(comp, sizeof comp, "%+.1f", o.evCompensation);
        t << (o.evCompensation != 0.0 ? std::string(" (auto, compensation ") + comp + " EV)" : std::string(" (auto)"));
      }
      t << ", " << o.op;
    } else {
      t << "; luminance in cd/m²";
    }
    std::snprintf(buf, sizeof buf, "%.2f", seconds);
    t << ") in " << buf << " s\n";
    std::cout << t.str();
    return 0;
  }

  // A time-lapse: one image per time, each written whole (atomically), with one exposure for all (the
  // first frame's automatic one unless --exposure is given) so that the frames compare.
  std::cout << t.str() << std::flush;
  std::optional<double> ev100 = o.exposureEv100;
  sdb::Scene& scene = loaded.scene;
  std::vector<std::string> times;  // local, with the UTC offset of each (daylight saving may change between)
  for (double hours : lapse->hoursAfterFrom) times.push_back(sceneLocalTime(scene, hours));
  for (size_t k = 0; k < times.size(); ++k) {
    if (k > 0) {
      // Only the sky, the sun and the daylight ambient change (rdb::RasterRdbChanges::sky); the light maps
      // stay on the GPU.
      renderer.update(rdb, rdb::updateRasterRdb(rdb, scene, scene.setTime(sdb::SiteTime{times[k]}), maps));
    }
    const std::string path = framePath(o.out, k);
    ev100 = renderImage(path, ev100);
    const std::string& local = times[k];  // 2026-06-21T09:00:00+03:00
    std::string sun = "sun below the horizon";
    if (rdb.sky && rdb.sky->hasSun) {
      std::snprintf(buf, sizeof buf, "sun at %.1f° elevation",
                    radToDeg(std::asin(std::clamp(double(rdb.sky->sunDirWorld.y), -1.0, 1.0))));
      sun = buf;
    }
    std::cout << "frame     " << path << "  " << local.substr(0, 10) << " " << local.substr(11, 5) << " "
              << local.substr(19) << ", " << sun << "\n"
              << std::flush;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::snprintf(buf, sizeof buf, "%.2f", seconds);
  t.str("");
  t << "images    " << lapse->hoursAfterFrom.size() << " (" << width << "×" << height;
  if (ext == ".png") {
    char e[32];
    std::snprintf(e, sizeof e, "%.2f", *ev100);
    t << "; exposure EV100 " << e << (o.exposureEv100 ? "" : " (auto, from the first frame)") << ", " << o.op;
  } else {
    t << "; luminance in cd/m²";
  }
  t << ") in " << buf << " s\n";
  std::cout << t.str();
  return 0;
}

}  // namespace

Command addRenderCommand(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* sub = app.add_subcommand(
      "render",
      "Render a view of a scene or a baked scene with the OpenGL engine, headless (no display needed): "
      "a tone-mapped PNG or an EXR in cd/m²");
  sub->add_option("SCENE", o->scene, "scene file (.json), glTF model (.gltf, .glb) or baked scene directory")
      ->required();
  sub->add_option("--camera", o->camera,
                  "the scene camera to look through, by name (default: the first camera, "
                  "else a view framing the whole scene)");
  sub->add_option(
      "--mode", o->mode,
      "simple (Phong and directional ambient), lightmap (baked light maps) or sunlight (sky dome and "
      "sun); default: the best the scene supports (lightmap for a baked directory)");
  sub->add_option("--size", o->size, "image size WIDTHxHEIGHT in pixels (default 1280x720)");
  sub->add_option("--out", o->out, "output image: .png (tone-mapped sRGB) or .exr (luminance, cd/m²)")
      ->required();
  sub->add_option("--exposure", o->exposureEv100, "exposure as EV100 (default: automatic)");
  sub->add_option("--ev-comp", o->evCompensation,
                  "exposure compensation of the automatic exposure, in stops (+1: twice as bright; default 0)");
  addDpiOption(*sub, &o->dotsPerInch);
  sub->add_option("--false-colour", o->falseColour,
                  "lux: the illuminance of a baked directory's light maps on the visible surfaces, in false "
                  "colour with a legend (PNG), instead of their luminance");
  sub->add_flag("--auto-exposure", o->autoExposure,
                "exposure from the log-luminance histogram (the default when --exposure is not given)");
  sub->add_option("--operator", o->op, "tone-mapping operator: linear, reinhard or filmic (default filmic)");
  sub->add_option("--white-point", o->whitePoint, "Reinhard: the exposed value shown as white (default 4)");
  addShadowOptions(*sub, o->shadows);
  addPostOptions(*sub, o->post);
  addBallOption(*sub, o->ballTexels);
  addEnvironmentOptions(*sub, o->environment);
  o->daylight.add(*sub);
  sub->add_option("--time-lapse", o->timeLapse,
                  "FROM,TO,STEP: one image per time from FROM to TO (times as --time takes them) every STEP "
                  "(30m, 1h), written to OUT with a frame number (shadows.png → shadows-0000.png …), for "
                  "shadow studies; sunlight mode unless --mode says otherwise, one exposure for all");
  return {sub, [o]() { return runRender(*o); }};
}

}  // namespace fly::cli
