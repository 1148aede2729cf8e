// `fly daylight-factor SCENE --grid HEIGHT,SPACING --out DF.csv [--image plan.png]`: the daylight factor at
// sensor points under the CIE standard overcast sky (cli/daylight_factor.h) with its standard error, and the
// mean, minimum and uniformity of the points — the daylight-factor grid of daylighting studies (BS 8206-2,
// EN 17037). Sensors as fly illuminance places them (--grid, or --points FILE.csv).
#include <algorithm>
#include <cstdio>
#include <memory>

#include "base/error.h"
#include "base/file_io.h"
#include "cli/bake_options.h"
#include "cli/bounce_cap_warning.h"
#include "cli/command.h"
#include "cli/daylight_factor.h"
#include "cli/grid_sensors.h"
#include "cli/image_metadata.h"
#include "cli/plan_image.h"
#include "cli/sensor_csv.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/scene_load.h"

namespace fly::cli {

namespace {

struct DaylightFactorOptions {
  std::string scene;
  std::string points;
  std::string grid;
  std::string area;
  std::string out;
  PlanImageOptions image;
  SamplingOptions sampling;
};

int runDaylightFactor(const DaylightFactorOptions& o) {
  const GridSpec grid = parseSensorOptions(o.points, o.grid, o.area);  // bad values fail before the load
  o.image.check(!o.grid.empty());
  sdb::Scene scene = sdb::loadScene(o.scene);
  turnOffDaylight(scene);
  raytracer::EstimateSettings settings = estimateSettings(o.sampling, scene.bakeSettings());
  settings.replicates = std::min(8u, settings.firstPassSamples);  // as fly illuminance: per-sensor errors
  rdb::TraceRdb rdb = rdb::buildTraceRdb(scene);
  keepSkyOnly(rdb);
  rdb.sky = overcastSky(rdb::TraceBuildOptions{}.skyResolution,
                        overcastZenithLuminanceCdM2(kOvercastHorizontalLux));
  const double outsideLux = unobstructedHorizontalLux(rdb.sky);
  if (!(outsideLux > 0.0)) throw std::runtime_error("internal error: the overcast sky gives no illuminance");
  std::fprintf(
      stderr,
      "light: CIE overcast sky, L(θ) = Lz·(1 + 2 cos θ)/3, no sun, no lamps; unobstructed horizontal "
      "illuminance %.6g lux\n",
      outsideLux);
  const raytracer::EmbreeScene embree(rdb);
  const GridSensors gridded = loadSensors(o.points, o.grid, grid, o.scene, rdb, embree);
  const SensorTable& sensors = gridded.table;
  const PlanStoreys storeys = o.image.path.empty() ? PlanStoreys{} : planStoreys(o.image, gridded);
  const raytracer::IntegratorSettings integratorOptions =
      integratorSettings(o.sampling, scene.bakeSettings());
  const raytracer::Integrator integrator(rdb, embree, integratorOptions);
  const raytracer::EstimateResult result =
      raytracer::estimateIrradiance(integrator, sensors.positionsM, sensors.normals, settings);
  if (integratorOptions.maxBounces < raytracer::kPathLengthGuard) {
    warnBounceCapBias(raytracer::estimateBounceCapBias(rdb, embree, integratorOptions, sensors.positionsM,
                                                       sensors.normals, {}, settings.threads, settings.seed));
  }

  std::vector<double> percent, stdErrorPercent;
  std::string csv = sensors.header + ",daylight_factor_percent,std_error_percent\n";
  for (size_t i = 0; i < sensors.lines.size(); ++i) {
    const raytracer::IrradianceEstimate& e = result.points[i];
    percent.push_back(100.0 * luminance(e.meanLux) / outsideLux);
    stdErrorPercent.push_back(100.0 * luminance(e.stdErrorLux) / outsideLux);
    csv += sensors.lines[i] + "," + csvNumber(percent.back()) + "," + csvNumber(stdErrorPercent.back()) + "\n";
  }
  const DaylightFactorSummary s = summarizeDaylightFactors(percent, stdErrorPercent);
  char summary[160];
  std::snprintf(summary, sizeof summary, "mean %.3g %% ± %.2g %%, min %.3g %%, uniformity (min/mean) %.3g",
                s.meanPercent, s.meanStdErrorPercent, s.minPercent, s.uniformity);
  if (!o.image.path.empty()) {
    PlanContent plan;
    plan.title = "Daylight factor, %, on a work plane " + csvNumber(grid.heightM) + " m above the floor";
    plan.subtitle =
        o.scene + "  ·  CIE overcast sky, no sun, unobstructed horizontal " + csvNumber(outsideLux) + " lx";
    plan.unit = "%";
    plan.values = percent;
    plan.defaultMax = 100.0;  // an unobstructed point; above it only noise (and light reflected up)
    for (const auto& setting : daylightSettings(scene)) {
      if (setting.first == "fly:site") plan.settings.push_back(setting);  // the time and sky do not apply
    }
    plan.settings.emplace_back("fly:sky",
                               "CIE overcast sky, L = Lz (1 + 2 cos θ)/3, no sun; unobstructed "
                               "horizontal illuminance " +
                                   csvNumber(outsideLux) + " lux");
    plan.settings.emplace_back("fly:quantity", "daylight factor, %");
    for (const std::string& line : writePlanImage(o.image, gridded, plan, storeys, rdb, scene))
      std::fprintf(stderr, "image: %s\n", line.c_str());
  }
  writeFileAtomic(o.out, csv);
  std::fprintf(stderr, "daylight factor: %zu sensors, %u samples each, %s; %.1f s -> %s\n",
               sensors.lines.size(), result.samplesPerPoint, summary, result.seconds, o.out.c_str());
  return 0;
}

}  // namespace

Command addDaylightFactorCommand(CLI::App& app) {
  auto o = std::make_shared<DaylightFactorOptions>();
  CLI::App* sub = app.add_subcommand("daylight-factor",
                                     "Daylight factor (%) at sensor points under the CIE standard overcast "
                                     "sky, with its standard error, the "
                                     "mean, minimum and uniformity");
  sub->add_option("SCENE", o->scene, "scene file (.json) or glTF model (.gltf, .glb)")->required();
  sub->add_option("--points", o->points,
                  "sensor file (.csv): a header naming the columns x,y,z,nx,ny,nz (metres, world space; the "
                  "sensor's unit normal), one row per sensor; other columns are kept");
  sub->add_option(
         "--grid", o->grid,
         "instead of --points: sensors facing up HEIGHT m above every floor, SPACING m apart (as fly "
         "illuminance --grid), e.g. 0.85,0.5")
      ->type_name("HEIGHT,SPACING");
  sub->add_option(
         "--area", o->area,
         "with --grid: only the sensors with x in [XMIN, XMAX] and z in [ZMIN, ZMAX] (world, metres), e.g. a "
         "building's rooms without the ground around it")
      ->type_name("XMIN,ZMIN,XMAX,ZMAX");
  sub->add_option("--out", o->out,
                  "output .csv: the sensor rows with daylight_factor_percent and std_error_percent added")
      ->required();
  o->image.add(*sub, "daylight factor");
  addSamplingOptions(*sub, o->sampling, "sensor");
  return {sub, [o] { return runDaylightFactor(*o); }};
}

}  // namespace fly::cli
