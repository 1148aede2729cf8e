// `fly render`: one view of a scene or a baked scene through the OpenGL engine, headless (EGL), into a PNG
// (tone-mapped sRGB) or an EXR (luminance in cd/m²).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include "base/error.h"
#include "base/image_io.h"
#include "base/tone_map.h"
#include "cli/baked_light_maps.h"
#include "cli/baked_scene.h"
#include "cli/command.h"
#include "cli/raster_scene.h"
#include "raster/gl_context.h"
#include "raster/renderer.h"
#include "rdb/raster_rdb.h"
#include "sdb/scene_load.h"

namespace fly::cli {

namespace {

struct RenderOptions {
  std::string scene;
  std::string camera;
  std::string mode;
  std::string size = "1280x720";
  std::string out;
  std::optional<double> exposureEv100;
  bool autoExposure = false;
  std::string op = "filmic";
  float whitePoint = 4.0f;
  std::string shadows = "vismap";
  uint32_t shadowMapTexels = 2048;
  DaylightOptions daylight;
};


std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

int runRender(const RenderOptions& o) {
  const std::string ext = lowerExtension(o.out);
  if (ext != ".png" && ext != ".exr") {
    throw UsageError("--out " + o.out + ": give a .png (tone-mapped sRGB) or .exr (luminance in cd/m²) file");
  }
  if (o.exposureEv100 && o.autoExposure)
    throw UsageError("give either --exposure or --auto-exposure, not both");
  if (o.exposureEv100 && !std::isfinite(*o.exposureEv100))
    throw UsageError("--exposure must be a finite EV100");
  if (!(o.whitePoint > 0.0f) || !std::isfinite(o.whitePoint)) throw UsageError("--white-point must be > 0");
  uint32_t width = 0, height = 0;
  parseSize(o.size, width, height);
  const ToneOperator op = parseToneOperator(o.op);
  const raster::SunShadowSettings shadows = parseShadowOptions(o.shadows, o.shadowMapTexels);
  std::optional<raster::RenderMode> requestedMode;
  if (!o.mode.empty()) requestedMode = parseRenderMode(o.mode);

  // The scene, and the light maps of a baked directory.
  const RasterScene loaded = loadRasterScene(o.scene, o.daylight);
  const std::filesystem::path& scenePath = loaded.scenePath;
  const std::optional<rdb::LightMapStore>& lightMaps = loaded.lightMaps;
  const rdb::RasterRdb rdb = buildRasterRdb(loaded.scene, lightMaps ? &*lightMaps : nullptr);
  if (rdb.indices.empty()) throw InputError({scenePath.string()}, "has no triangles to render");
  const std::optional<raster::RenderMode> mode = chooseRenderMode(rdb, requestedMode, scenePath);

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
  renderer.render(view, *mode, width, height);
  const std::vector<float> rgb = renderer.luminanceRgb();
  for (float v : rgb) {
    if (!std::isfinite(v)) throw std::runtime_error("internal error: the render has a non-finite luminance");
  }
  double ev100 = 0.0;
  if (ext == ".exr") {
    ImageRgbF image{int(width), int(height), rgb};
    writeExr(o.out, image,
             {{"units", "cd/m^2 (linear Rec.709 RGB, luminance Y = 0.2126 R + 0.7152 G + 0.0722 B)"},
              {"fly:mode", raster::renderModeName(*mode)},
              {"fly:view", viewName},
              {"fly:scene", scenePath.string()}});
  } else {
    if (o.exposureEv100) {
      ev100 = *o.exposureEv100;
    } else {
      std::vector<float> lum(rgb.size() / 3);
      for (size_t i = 0; i < lum.size(); ++i)
        lum[i] = luminance(Rgb(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]));
      ev100 = autoExposureEv100Histogram(lum);
    }
    renderer.toneMap(ToneMapSettings{op, ev100, o.whitePoint});
    const std::vector<uint8_t> px = renderer.srgb8();
    writePng(o.out, int(width), int(height), 3, px.data());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::ostringstream t;
  t << "scene     " << scenePath.string() << " (" << rdb.triangleCount() << " triangles"
    << (lightMaps ? ", baked light maps" : "") << ")\n";
  t << "view      " << viewName << "\n";
  t << "mode      " << raster::renderModeName(*mode) << "\n";
  t << "light     " << loaded.light << "\n";
  if (renderer.stats().shadowPasses > 0) {
    const raster::SunShadowCounts c = renderer.sunShadowCounts();
    t << "shadows   sun shadow volumes of " << c.keptTriangles << " of " << c.casterTriangles << " triangles, "
      << c.silhouetteEdges << " silhouette edges ("
      << (shadows.mode == raster::SunShadowMode::kVisibilityMap
              ? std::to_string(shadows.visibilityMapTexels) + "² visibility map"
              : std::string("every sun-facing triangle"))
      << ")\n";
  }
  t << "OpenGL    " << context->info().major << "." << context->info().minor << " core, "
    << context->info().renderer << " (" << context->info().platform << ")\n";
  t << "image     " << o.out << " (" << width << "×" << height;
  char buf[64];
  if (ext == ".png") {
    std::snprintf(buf, sizeof buf, "%.2f", ev100);
    t << "; exposure EV100 " << buf << (o.exposureEv100 ? "" : " (auto)") << ", " << o.op;
  } else {
    t << "; luminance in cd/m²";
  }
  std::snprintf(buf, sizeof buf, "%.2f", seconds);
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
  sub->add_flag("--auto-exposure", o->autoExposure,
                "exposure from the log-luminance histogram (the default when --exposure is not given)");
  sub->add_option("--operator", o->op, "tone-mapping operator: linear, reinhard or filmic (default filmic)");
  sub->add_option("--white-point", o->whitePoint, "Reinhard: the exposed value shown as white (default 4)");
  addShadowOptions(*sub, o->shadows, o->shadowMapTexels);
  o->daylight.add(*sub);
  return {sub, [o]() { return runRender(*o); }};
}

}  // namespace fly::cli
