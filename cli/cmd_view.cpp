// `fly view`: walk through a scene or a baked scene in a window (raster/viewer.h), with a scripted mode
// (--frames, --keys, --screenshot) that tests run under xvfb-run.
#include <cmath>
#include <cstdio>
#include <cstdlib>
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
#include "cli/command.h"
#include "cli/environment_option.h"
#include "cli/raster_scene.h"
#include "cli/scene_daylight.h"
#include "raster/gl_context.h"
#include "raster/viewer.h"
#include "rdb/raster_rdb.h"
#include "sunsky/civil_time.h"

namespace fly::cli {

namespace {

constexpr const char* kNoDisplay =
    "no display: fly view needs a window; use fly render SCENE --out shot.png for headless images";

struct ViewOptions {
  std::string scene;
  std::string camera;
  std::string mode;
  std::string size = "1280x720";
  std::optional<double> exposureEv100;
  std::string op = "filmic";
  ShadowOptions shadows;
  uint32_t ballTexels = 256;
  EnvironmentOptions environment;
  DaylightOptions daylight;
  uint64_t frames = 0;
  std::string keys;
  std::string screenshot;
};

class SceneHost : public raster::ViewerHost {
 public:
  SceneHost(RasterScene& scene, rdb::RasterRdb& rdb, bool environment)
      : s_(scene), rdb_(rdb), environment_(environment) {}

  std::optional<rdb::RasterRdbChanges> stepTime(int minutes, std::string& message) override {
    if (environment_) {
      message = "the --environment stands in for the sky and sun: the time of day does not change it";
      return std::nullopt;
    }
    if (!s_.scene.hasSite() || s_.scene.time().localDateTime.empty()) {
      message = s_.scene.time().sunDirection ? "no time of day: the sun is placed directly (--sun-dir)"
                                             : "no time of day: the scene has no site";
      return std::nullopt;
    }
    // Steps in UTC, so that a daylight-saving change neither repeats nor skips a step; the new time carries
    // its offset, which the local clock alone would leave ambiguous in the autumn overlap.
    const sdb::SiteTime before = s_.scene.time();
    const std::string after = sceneLocalTime(s_.scene, minutes / 60.0);
    const rdb::LightMapStore* maps = s_.lightMaps ? &*s_.lightMaps : nullptr;
    try {
      return rdb::updateRasterRdb(rdb_, s_.scene, s_.scene.setTime(sdb::SiteTime{after}), maps);
    } catch (const InputError& e) {  // e.g. a time the weather file does not cover: back to the time before
      message = e.what();
      return rdb::updateRasterRdb(rdb_, s_.scene, s_.scene.setTime(before), maps);
    }
  }

  std::string timeLabel() const override {
    if (!s_.scene.hasSite() || s_.scene.time().localDateTime.empty()) return "";
    std::string t = sceneLocalTime(s_.scene);  // 2026-09-15T17:30:00+03:00
    std::string label = t.substr(0, 10) + " " + t.substr(11, 5) + " " + t.substr(19);
    // Over a bake that keeps the sun's direct light apart, the indirect light stays as baked.
    if (!s_.bakedSunTime.empty()) label += ", indirect baked at " + s_.bakedSunTime;
    return label;
  }

  void saveScreenshot(const std::vector<uint8_t>& srgb8, uint32_t widthPx, uint32_t heightPx) override {
    std::filesystem::path name;
    do {
      char b[32];
      std::snprintf(b, sizeof b, "fly-view-%04d.png", ++counter_);
      name = b;
    } while (std::filesystem::exists(name));
    try {
      writePng(name, int(widthPx), int(heightPx), 3, srgb8.data());
      std::cout << "screenshot " << name.string() << " (" << widthPx << "×" << heightPx << ")" << std::endl;
    } catch (const std::exception& e) {  // a full disk or a read-only directory does not end the session
      log::error(std::string("screenshot not saved: ") + e.what());
    }
  }

 private:
  RasterScene& s_;
  rdb::RasterRdb& rdb_;
  bool environment_;
  int counter_ = 0;
};

std::vector<raster::ViewerAction> parseKeys(const std::string& text) {
  std::vector<raster::ViewerAction> actions;
  if (text.empty()) return actions;
  std::stringstream in(text);
  std::string key;
  while (std::getline(in, key, ',')) {
    const std::optional<raster::ViewerAction> a = raster::parseViewerAction(key);
    if (!a) {
      throw UsageError("--keys: unknown key '" + key +
                       "' (expected keys separated by commas: 1 2 3 + - E O T shift+T C R P Esc)");
    }
    actions.push_back(*a);
  }
  return actions;
}

int runView(const ViewOptions& o) {
  uint32_t width = 0, height = 0;
  parseSize(o.size, width, height);
  const ToneOperator op = parseToneOperator(o.op);
  const raster::SunShadowSettings shadows = parseShadowOptions(o.shadows);
  const raster::BallSettings balls = parseBallOption(o.ballTexels);
  std::optional<raster::RenderMode> mode;
  if (!o.mode.empty()) mode = parseRenderMode(o.mode);
  if (o.exposureEv100 && !std::isfinite(*o.exposureEv100))
    throw UsageError("--exposure must be a finite EV100");
  const std::vector<raster::ViewerAction> script = parseKeys(o.keys);
  if (!o.screenshot.empty()) {
    std::string ext = std::filesystem::path(o.screenshot).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".png") throw UsageError("--screenshot " + o.screenshot + ": give a .png file");
  }
  const std::optional<rdb::RasterSky> environment = loadEnvironment(o.environment);
  // GLFW 3.3 needs an X display (Wayland through XWayland).
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY")) throw std::runtime_error(kNoDisplay);

  RasterScene scene = loadRasterScene(o.scene, o.daylight);
  rdb::RasterRdb rdb = buildRasterRdb(scene.scene, scene.lightMaps ? &*scene.lightMaps : nullptr);
  if (rdb.indices.empty()) throw InputError({scene.scenePath.string()}, "has no triangles to show");
  if (environment) applyEnvironment(rdb, *environment);

  raster::ViewerOptions v;
  v.mode = chooseRenderMode(rdb, mode, scene.scenePath);
  if (!o.camera.empty()) {
    v.camera = findCamera(rdb, o.camera);
  } else if (!rdb.cameras.empty()) {
    v.camera = 0;
  }
  v.toneMap = ToneMapSettings{op, o.exposureEv100.value_or(0.0), 4.0f};
  v.autoExposure = !o.exposureEv100;
  v.frames = o.frames;
  v.script = script;
  v.shadows = shadows;
  v.balls = balls;

  std::unique_ptr<raster::GlfwWindowContext> window;
  try {
    window = std::make_unique<raster::GlfwWindowContext>(int(width), int(height),
                                                         "fly view: " + scene.scenePath.filename().string());
  } catch (const raster::GlUnavailableError& e) {
    throw std::runtime_error(std::string(kNoDisplay) + " (" + e.what() + ")");
  }
  std::cout << "scene     " << scene.scenePath.string() << " (" << rdb.triangleCount() << " triangles"
            << (scene.lightMaps ? ", baked light maps" : "") << ")\n"
            << "view      "
            << (v.camera ? "camera \"" + rdb.cameras[*v.camera].name + "\""
                         : std::string("a view framing the whole scene"))
            << "\nlight     " << scene.light << "\n"
            << measuredBrdfLine(rdb, balls) << environmentLine(o.environment, environment)
            << (scene.bakedSunlight.empty() ? "" : "baked     " + scene.bakedSunlight + "\n") << "OpenGL    "
            << window->info().major << "." << window->info().minor << " core, " << window->info().renderer
            << " (" << window->info().platform << ")\n"
            << std::flush;
  SceneHost host(scene, rdb, environment.has_value());
  const raster::ViewerResult r = raster::runViewer(*window, rdb, host, v);

  if (!o.screenshot.empty()) {
    if (r.frames == 0) throw std::runtime_error("the window closed before a frame was drawn; no screenshot");
    writePng(o.screenshot, int(r.widthPx), int(r.heightPx), 3, r.srgb8.data());
  }
  char line[160];
  std::snprintf(line, sizeof line, "frames    %llu in %.2f s; last: mode %s, exposure EV100 %.2f\n",
                static_cast<unsigned long long>(r.frames), r.seconds, raster::renderModeName(r.mode),
                r.ev100);
  std::cout << line;
  if (const std::string t = host.timeLabel(); !t.empty()) std::cout << "time      " << t << "\n";
  if (!o.screenshot.empty())
    std::cout << "image     " << o.screenshot << " (" << r.widthPx << "×" << r.heightPx << ")\n";
  return 0;
}

}  // namespace

Command addViewCommand(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* sub = app.add_subcommand(
      "view",
      "Walk through a scene or a baked scene in a window with the OpenGL engine (needs a display; "
      "fly render makes images without one)");
  sub->footer(raster::kViewerKeysHelp);
  sub->add_option("SCENE", o->scene, "scene file (.json), glTF model (.gltf, .glb) or baked scene directory")
      ->required();
  sub->add_option("--camera", o->camera,
                  "the scene camera to start from, by name (default: the first camera, else a view of the "
                  "whole scene from eye height)");
  sub->add_option("--mode", o->mode,
                  "simple, lightmap or sunlight to start in; default: the best the scene supports");
  sub->add_option("--size", o->size, "window size WIDTHxHEIGHT in pixels (default 1280x720)");
  sub->add_option("--exposure", o->exposureEv100, "start with this exposure as EV100 (default: automatic)");
  sub->add_option("--operator", o->op, "tone-mapping operator: linear, reinhard or filmic (default filmic)");
  addShadowOptions(*sub, o->shadows);
  addBallOption(*sub, o->ballTexels);
  addEnvironmentOptions(*sub, o->environment);
  o->daylight.add(*sub);
  sub->add_option("--frames", o->frames, "close after this many frames (and after the --keys script)");
  sub->add_option(
      "--keys", o->keys,
      "key presses to replay, one per frame from the first, separated by commas, e.g. 3,+,T,shift+T");
  sub->add_option("--screenshot", o->screenshot,
                  "save the last frame (without the overlay) to this PNG on closing");
  return {sub, [o]() { return runView(*o); }};
}

}  // namespace fly::cli
