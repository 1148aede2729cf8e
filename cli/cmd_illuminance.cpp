// `fly illuminance SCENE --points IN.csv --out OUT.csv`: illuminance at sensor points with its standard
// error, from the baker's integrator — the point-in-time illuminance grid of daylighting studies (as
// Radiance's rtrace -I). `--grid HEIGHT,SPACING` instead places the sensors on a work plane over every floor
// (raytracer/sensor_grid.h), and `--image plan.png` draws them as a false-colour plan (cli/plan_image.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "base/error.h"
#include "base/file_io.h"
#include "cli/bake_options.h"
#include "cli/bounce_cap_warning.h"
#include "cli/command.h"
#include "cli/grid_sensors.h"
#include "cli/image_metadata.h"
#include "cli/plan_image.h"
#include "cli/scene_daylight.h"
#include "cli/sensor_csv.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb_build.h"

namespace fly::cli {

namespace {

struct IlluminanceOptions {
  std::string scene;
  std::string points;
  std::string grid;
  std::string area;
  std::string out;
  PlanImageOptions image;
  SamplingOptions sampling;
  DaylightOptions daylight;
};

int runIlluminance(const IlluminanceOptions& o) {
  const auto commandStart = std::chrono::steady_clock::now();
  const GridSpec grid = parseSensorOptions(o.points, o.grid, o.area);  // bad values fail before the load
  o.image.check(!o.grid.empty());
  const LitScene lit = loadLitScene(o.scene, o.daylight);
  const sdb::Scene& scene = lit.scene;
  std::fprintf(stderr, "light: %s\n", lit.light.c_str());
  raytracer::EstimateSettings settings = estimateSettings(o.sampling, scene.bakeSettings());
  // Eight replicates per sensor, whatever their number: sensors are few and unlike (full sun beside
  // penumbra), so the replicates' gain pooled over them (progressive.h) would misstate single sensors'
  // errors — by up to 2× against an independent path tracer (docs/validation.md).
  settings.replicates = std::min(8u, settings.firstPassSamples);
  const rdb::TraceRdb rdb = rdb::buildTraceRdb(scene);
  const raytracer::EmbreeScene embree(rdb);
  const GridSensors gridded = loadSensors(o.points, o.grid, grid, o.scene, rdb, embree);
  const SensorTable& sensors = gridded.table;
  const PlanStoreys storeys = o.image.path.empty() ? PlanStoreys{} : planStoreys(o.image, gridded);
  const raytracer::IntegratorSettings integratorOptions = integratorSettings(o.sampling, scene.bakeSettings());
  const raytracer::Integrator integrator(rdb, embree, integratorOptions);
  // --time is the command's wall-clock limit: loading, the sensors' placement and the integrator's training
  // come out of it, and a second is kept for writing the table and the plan.
  if (std::isfinite(settings.timeLimitS)) {
    const double elapsedS =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - commandStart).count();
    settings.timeLimitS = std::max(0.0, settings.timeLimitS - elapsedS - 1.0);
  }
  const raytracer::EstimateResult result =
      raytracer::estimateIrradiance(integrator, sensors.positionsM, sensors.normals, settings);
  if (integratorOptions.maxBounces < raytracer::kPathLengthGuard) {
    warnBounceCapBias(raytracer::estimateBounceCapBias(rdb, embree, integratorOptions, sensors.positionsM,
                                                       sensors.normals, {}, settings.threads, settings.seed));
  }

  std::string csv = sensors.header + ",illuminance_lux,std_error_lux\n";
  for (size_t i = 0; i < sensors.lines.size(); ++i) {
    const raytracer::IrradianceEstimate& e = result.points[i];
    // The luminance of the per-channel standard errors: exact when the channels' errors are fully correlated
    // (as they are for white light), otherwise a slight overestimate.
    csv +=
        sensors.lines[i] + "," + csvNumber(luminance(e.meanLux)) + "," + csvNumber(luminance(e.stdErrorLux)) + "\n";
  }
  if (!o.image.path.empty()) {
    PlanContent plan;
    plan.title = "Illuminance, lux, on a work plane " + csvNumber(grid.heightM) + " m above the floor";
    plan.unit = "lx";
    for (const raytracer::IrradianceEstimate& e : result.points) plan.values.push_back(luminance(e.meanLux));
    plan.settings = daylightSettings(scene);
    plan.subtitle = o.scene;
    for (const auto& [key, value] : plan.settings) {
      if (key == "fly:time" || key == "fly:sky") plan.subtitle += "  ·  " + value;
    }
    if (const size_t n = scene.lights().size(); n > 0) {
      plan.subtitle += "  ·  " + std::to_string(n) + (n == 1 ? " lamp" : " lamps");
    }
    plan.settings.emplace_back("fly:quantity", "illuminance on a horizontal work plane, lux");
    for (const std::string& line : writePlanImage(o.image, gridded, plan, storeys, rdb, scene))
      std::fprintf(stderr, "image: %s\n", line.c_str());
  }
  writeFileAtomic(o.out, csv);
  std::fprintf(
      stderr,
      "illuminance: %zu sensors, %u samples each, 95th percentile of relative standard error %.3g %%, "
      "%.1f s, %.3g Mrays/s -> %s\n",
      sensors.lines.size(), result.samplesPerPoint, 100.0 * result.relativeErrorP95, result.seconds,
      result.seconds > 0.0 ? double(result.rays) / result.seconds * 1e-6 : 0.0, o.out.c_str());
  return 0;
}

}  // namespace

Command addIlluminanceCommand(CLI::App& app) {
  auto o = std::make_shared<IlluminanceOptions>();
  CLI::App* sub = app.add_subcommand("illuminance",
                                     "Illuminance (lux) at sensor points with its standard error, from sun, "
                                     "sky, lights and interreflections");
  sub->add_option("SCENE", o->scene, "scene file (.json) or glTF model (.gltf, .glb)")->required();
  sub->add_option("--points", o->points,
                  "sensor file (.csv): a header naming the columns x,y,z,nx,ny,nz (metres, world space; the "
                  "sensor's unit normal), one row per sensor; other columns are kept");
  sub->add_option(
         "--grid", o->grid,
         "instead of --points: sensors facing up HEIGHT m above every floor (a surface facing within 25.8° "
         "of up, the ground included) that has HEIGHT m of free space, on a lattice SPACING m apart in x "
         "and z centred on the scene; rows ordered by floor height, z, x. HEIGHT,SPACING in metres, e.g. "
         "0.85,0.5")
      ->type_name("HEIGHT,SPACING");
  sub->add_option(
         "--area", o->area,
         "with --grid: only the sensors with x in [XMIN, XMAX] and z in [ZMIN, ZMAX] (world, metres), e.g. a "
         "building's rooms without the ground around it")
      ->type_name("XMIN,ZMIN,XMAX,ZMAX");
  sub->add_option(
         "--out", o->out,
         "output .csv: the sensor rows (--grid: x,y,z,nx,ny,nz) with illuminance_lux and std_error_lux "
         "added")
      ->required();
  o->image.add(*sub, "illuminance");
  addSamplingOptions(*sub, o->sampling, "sensor");
  o->daylight.add(*sub, &o->sampling.time);
  return {sub, [o] { return runIlluminance(*o); }};
}

}  // namespace fly::cli
