// `fly illuminance SCENE --points IN.csv --out OUT.csv`: illuminance at sensor points with its standard
// error, from the baker's integrator — the point-in-time illuminance grid of daylighting studies (as
// Radiance's rtrace -I). `--grid HEIGHT,SPACING` instead places the sensors on a work plane over every floor
// (raytracer/sensor_grid.h).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "base/error.h"
#include "base/file_io.h"
#include "cli/bake_options.h"
#include "cli/bounce_cap_warning.h"
#include "cli/command.h"
#include "cli/scene_daylight.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "raytracer/sensor_grid.h"
#include "rdb/trace_rdb_build.h"

namespace fly::cli {

namespace {

struct IlluminanceOptions {
  std::string scene;
  std::string points;
  std::string grid;
  std::string out;
  SamplingOptions sampling;
  DaylightOptions daylight;
};

// The sensors of a CSV file and its lines, so that the output repeats them.
struct SensorTable {
  std::string header;
  std::vector<std::string> lines;
  std::vector<vec3> positionsM;
  std::vector<vec3> normals;
};

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream s(line);
  while (std::getline(s, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  const size_t b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

SensorTable readSensors(const std::string& path) {
  const std::string text = readInputFile(path, "sensor file");
  SensorTable t;
  std::istringstream in(text);
  std::string line;
  int lineNo = 0;
  int col[6] = {-1, -1, -1, -1, -1, -1};
  static const char* kNames[6] = {"x", "y", "z", "nx", "ny", "nz"};
  size_t columns = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty()) continue;
    if (line.find('"') != std::string::npos) {
      throw InputError({path, lineNo}, "quoted fields are not supported",
                       "write plain comma-separated numbers");
    }
    const std::vector<std::string> fields = splitCsv(line);
    if (t.header.empty()) {
      t.header = line;
      columns = fields.size();
      for (size_t i = 0; i < fields.size(); ++i) {
        for (int k = 0; k < 6; ++k) {
          if (trim(fields[i]) == kNames[k]) col[k] = int(i);
        }
      }
      for (int k = 0; k < 6; ++k) {
        if (col[k] < 0) {
          throw InputError(
              {path, lineNo}, std::string("the header has no column \"") + kNames[k] + "\"",
              "the first line must name the columns, e.g. x,y,z,nx,ny,nz (metres, world space; the "
              "sensor's normal)");
        }
      }
      continue;
    }
    if (fields.size() != columns) {
      throw InputError(
          {path, lineNo},
          "has " + std::to_string(fields.size()) + " fields, the header " + std::to_string(columns),
          "give every row the header's columns");
    }
    float v[6];
    for (int k = 0; k < 6; ++k) {
      const std::string f = trim(fields[size_t(col[k])]);
      const char* end = f.data() + f.size();
      const auto [ptr, ec] = std::from_chars(f.data(), end, v[k]);
      if (ec != std::errc() || ptr != end || !std::isfinite(v[k])) {
        throw InputError(
            {path, lineNo},
            std::string("column \"") + kNames[k] + "\": '" + printableExcerpt(f) + "' is not a finite number",
            "write decimal numbers such as 1.25 or -3e2");
      }
    }
    const vec3 n(v[3], v[4], v[5]);
    if (!(glm::length(n) > 0.0f)) {
      throw InputError({path, lineNo}, "the sensor's normal (nx, ny, nz) is zero",
                       "give the direction the sensor faces, e.g. 0,1,0 for a horizontal sensor facing up");
    }
    t.lines.push_back(line);
    t.positionsM.emplace_back(v[0], v[1], v[2]);
    t.normals.push_back(glm::normalize(n));
  }
  if (t.header.empty())
    throw InputError({path}, "the sensor file has no header line", "start with x,y,z,nx,ny,nz");
  if (t.lines.empty()) throw InputError({path}, "the sensor file has no sensors", "add one row per sensor");
  return t;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// The most sensors --grid may place: beyond this a spacing is surely a slip (10^6 sensors take minutes).
constexpr double kMaxGridSensors = 1e6;

struct GridSpec {
  float heightM = 0.0f;
  float spacingM = 0.0f;
};

// --grid HEIGHT,SPACING in metres, e.g. 0.85,0.5.
GridSpec parseGrid(const std::string& s) {
  const std::vector<std::string> fields = splitCsv(s);
  GridSpec g;
  float* values[2] = {&g.heightM, &g.spacingM};
  bool ok = fields.size() == 2;
  for (size_t i = 0; ok && i < 2; ++i) {
    const std::string f = trim(fields[i]);
    const char* end = f.data() + f.size();
    const auto [ptr, ec] = std::from_chars(f.data(), end, *values[i]);
    ok = ec == std::errc() && ptr == end && std::isfinite(*values[i]);
  }
  if (!ok) {
    throw UsageError("--grid " + s +
                     ": expected HEIGHT,SPACING in metres, e.g. 0.85,0.5 (sensors 0.85 m above "
                     "the floors, 0.5 m apart)");
  }
  if (!(g.heightM > 0.0f)) throw UsageError("--grid " + s + ": the height above the floors must be > 0 m");
  if (!(g.spacingM >= 0.01f)) throw UsageError("--grid " + s + ": the spacing must be at least 0.01 m");
  return g;
}

// --grid's sensors over the scene's floors, as a table with the columns x,y,z,nx,ny,nz.
SensorTable gridSensors(const std::string& spec, const GridSpec& g, const std::string& scenePath,
                        const rdb::TraceRdb& rdb, const raytracer::EmbreeScene& embree) {
  const double columns = raytracer::floorGridColumnCount(rdb, g.spacingM);
  if (columns > kMaxGridSensors) {
    throw UsageError("--grid " + spec + ": a spacing of " + number(g.spacingM) + " m gives " +
                     number(columns) + " grid columns over the scene's " + number(rdb.boundsM.size().x) +
                     " m × " + number(rdb.boundsM.size().z) +
                     " m, more than the limit of 10^6 sensors; give a larger spacing");
  }
  const std::vector<raytracer::GridSensor> grid =
      raytracer::floorSensorGrid(rdb, embree, g.heightM, g.spacingM);
  if (double(grid.size()) > kMaxGridSensors) {
    throw UsageError("--grid " + spec + ": " + std::to_string(grid.size()) +
                     " sensors over all floors, more than the limit of 10^6; give a larger spacing");
  }
  if (grid.empty()) {
    throw InputError(
        {scenePath},
        "--grid " + spec + ": the scene has no floor with " + number(g.heightM) + " m of free space above it",
        "a floor is a surface facing up (within 25.8° of +Y); give a smaller height or use --points");
  }
  SensorTable t;
  t.header = "x,y,z,nx,ny,nz";
  for (const raytracer::GridSensor& s : grid) {
    t.lines.push_back(number(s.positionM.x) + "," + number(s.positionM.y) + "," + number(s.positionM.z) +
                      "," + number(s.normal.x) + "," + number(s.normal.y) + "," + number(s.normal.z));
    t.positionsM.push_back(s.positionM);
    t.normals.push_back(s.normal);
  }
  return t;
}

int runIlluminance(const IlluminanceOptions& o) {
  if (o.points.empty() == o.grid.empty()) {
    throw UsageError(
        "give exactly one of --points FILE.csv (your sensors) and --grid HEIGHT,SPACING (a grid "
        "over the floors)");
  }
  const GridSpec grid = o.grid.empty() ? GridSpec{} : parseGrid(o.grid);  // bad values fail before the load
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
  const SensorTable sensors =
      o.grid.empty() ? readSensors(o.points) : gridSensors(o.grid, grid, o.scene, rdb, embree);
  const raytracer::IntegratorSettings integratorOptions = integratorSettings(o.sampling, scene.bakeSettings());
  const raytracer::Integrator integrator(rdb, embree, integratorOptions);
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
        sensors.lines[i] + "," + number(luminance(e.meanLux)) + "," + number(luminance(e.stdErrorLux)) + "\n";
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
         "--out", o->out,
         "output .csv: the sensor rows (--grid: x,y,z,nx,ny,nz) with illuminance_lux and std_error_lux "
         "added")
      ->required();
  addSamplingOptions(*sub, o->sampling, "sensor");
  o->daylight.add(*sub, &o->sampling.time);
  return {sub, [o] { return runIlluminance(*o); }};
}

}  // namespace fly::cli
