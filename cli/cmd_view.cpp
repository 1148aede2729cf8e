// `fly view`: walk through a scene or a baked scene in a window (raster/viewer.h) with its panel and lux
// probe, with a scripted mode (--frames, --keys, --probe, --screenshot, --window-screenshot) that tests run
// under xvfb-run.
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
#include "cli/command.h"
#include "cli/environment_option.h"
#include "cli/image_metadata.h"
#include "cli/post_options.h"
#include "cli/raster_scene.h"
#include "cli/view_host.h"
#include "raster/gl_context.h"
#include "raster/viewer.h"
#include "rdb/raster_rdb.h"

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
  double evCompensation = 0.0;
  std::string op = "filmic";
  ShadowOptions shadows;
  PostOptions post;
  uint32_t ballTexels = 256;
  EnvironmentOptions environment;
  DaylightOptions daylight;
  uint64_t frames = 0;
  std::string keys;
  std::string screenshot;
  std::string windowScreenshot;
  bool noPanel = false;
  std::string probe;
  double dotsPerInch = 0.0;  // --dpi: the screenshots' print resolution; 0 = none
};

// --probe X,Y: a window point in pixels from the top left, inside the window.
vec2 parseProbePoint(const std::string& text, uint32_t widthPx, uint32_t heightPx) {
  double x = 0.0, y = 0.0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf%c", &x, &y, &tail) != 2 || !std::isfinite(x) || !std::isfinite(y) ||
      x < 0.0 || y < 0.0 || x >= widthPx || y >= heightPx) {
    throw UsageError("--probe " + text + ": give X,Y in pixels from the window's top left, inside the " +
                     std::to_string(widthPx) + "×" + std::to_string(heightPx) + " window");
  }
  return vec2(float(x), float(y));
}

void checkPngName(const std::string& option, const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".png") throw UsageError(option + " " + file + ": give a .png file");
}

std::vector<raster::ViewerAction> parseKeys(const std::string& text) {
  std::vector<raster::ViewerAction> actions;
  if (text.empty()) return actions;
  std::stringstream in(text);
  std::string key;
  while (std::getline(in, key, ',')) {
    const std::optional<raster::ViewerAction> a = raster::parseViewerAction(key);
    if (!a) {
      throw UsageError("--keys: unknown key '" + key +
                       "' (expected keys separated by commas: 1 2 3 + - E O T shift+T C R P F1 Esc)");
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
  const raster::AmbientOcclusionSettings ambientOcclusion = parseAmbientOcclusion(o.post);
  const raster::BloomSettings bloom = parseBloom(o.post);
  const raster::BallSettings balls = parseBallOption(o.ballTexels);
  std::optional<raster::RenderMode> mode;
  if (!o.mode.empty()) mode = parseRenderMode(o.mode);
  if (o.exposureEv100 && !std::isfinite(*o.exposureEv100))
    throw UsageError("--exposure must be a finite EV100");
  if (!std::isfinite(o.evCompensation) || std::abs(o.evCompensation) > 10.0)
    throw UsageError("--ev-comp must be a number of stops in [-10, 10]");
  const std::vector<raster::ViewerAction> script = parseKeys(o.keys);
  if (!o.screenshot.empty()) checkPngName("--screenshot", o.screenshot);
  if (!o.windowScreenshot.empty()) checkPngName("--window-screenshot", o.windowScreenshot);
  std::optional<vec2> probeAt;
  if (!o.probe.empty()) probeAt = parseProbePoint(o.probe, width, height);
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
  v.evCompensation = o.evCompensation;
  v.frames = o.frames;
  v.script = script;
  v.shadows = shadows;
  v.balls = balls;
  v.ambientOcclusion = ambientOcclusion;
  v.bloom = bloom;
  v.panel = !o.noPanel;
  v.lightMaps = scene.lightMaps ? &*scene.lightMaps : nullptr;
  v.probeAtPx = probeAt;
  v.captureWindow = !o.windowScreenshot.empty();

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
  SceneViewHost host(scene, rdb, environment.has_value(), o.dotsPerInch);
  const raster::ViewerResult r = raster::runViewer(*window, rdb, host, v);

  if (!o.screenshot.empty()) {
    if (r.frames == 0) throw std::runtime_error("the window closed before a frame was drawn; no screenshot");
    writePng(o.screenshot, int(r.widthPx), int(r.heightPx), 3, r.srgb8.data(),
             host.screenshotMetadata("fly view", r.mode, r.tone));
  }
  if (!o.windowScreenshot.empty()) {
    if (r.windowSrgb8.empty())
      throw std::runtime_error("the window closed before a frame was drawn; no screenshot");
    writePng(o.windowScreenshot, int(r.windowWidthPx), int(r.windowHeightPx), 3, r.windowSrgb8.data(),
             host.screenshotMetadata("fly view, the window", r.mode, r.tone));
  }
  char line[160];
  std::snprintf(line, sizeof line, "frames    %llu in %.2f s; last: mode %s, exposure EV100 %.2f\n",
                static_cast<unsigned long long>(r.frames), r.seconds, raster::renderModeName(r.mode),
                r.tone.ev100);
  std::cout << line;
  if (const std::string t = host.timeLabel(); !t.empty()) std::cout << "time      " << t << "\n";
  if (!o.screenshot.empty())
    std::cout << "image     " << o.screenshot << " (" << r.widthPx << "×" << r.heightPx << ")\n";
  if (!o.windowScreenshot.empty())
    std::cout << "window    " << o.windowScreenshot << " (" << r.windowWidthPx << "×" << r.windowHeightPx
              << ")\n";
  if (!r.probeText.empty()) std::cout << "probe     " << r.probeText << "\n";
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
  sub->add_option("--ev-comp", o->evCompensation,
                  "exposure compensation of the automatic exposure, in stops (+1: twice as bright; default 0)");
  sub->add_option("--operator", o->op, "tone-mapping operator: linear, reinhard or filmic (default filmic)");
  addShadowOptions(*sub, o->shadows);
  addPostOptions(*sub, o->post);
  addBallOption(*sub, o->ballTexels);
  addEnvironmentOptions(*sub, o->environment);
  o->daylight.add(*sub);
  sub->add_option("--frames", o->frames, "close after this many frames (and after the --keys script)");
  sub->add_option(
      "--keys", o->keys,
      "key presses to replay, one per frame from the first, separated by commas, e.g. 3,+,T,shift+T");
  sub->add_option("--screenshot", o->screenshot,
                  "save the last frame (without the overlay) to this PNG on closing");
  sub->add_option("--window-screenshot", o->windowScreenshot,
                  "save the last frame as the window shows it (overlay and panel included) to this PNG");
  addDpiOption(*sub, &o->dotsPerInch);
  sub->add_flag("--no-panel", o->noPanel, "start with the panel hidden (F1 shows it)");
  sub->add_option("--probe", o->probe,
                  "read the baked illuminance under the window point X,Y (pixels from the top left) at the "
                  "first frame, as a click there does");
  return {sub, [o]() { return runView(*o); }};
}

}  // namespace fly::cli
