// `fly probe BAKED --points IN.csv --out OUT.csv`: the baked light maps' illuminance and standard error at
// sensor points — the viewer's lux probe (cli/baked_probe.h) — in fly illuminance's columns, so that the two
// outputs compare row by row.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "base/error.h"
#include "base/file_io.h"
#include "cli/baked_manifest.h"
#include "cli/baked_probe.h"
#include "cli/command.h"
#include "cli/raster_scene.h"
#include "cli/sensor_csv.h"

namespace fly::cli {

namespace {

struct ProbeOptions {
  std::string baked;
  std::string points;
  std::string out;
  double maxDistanceM = 0.05;
};

// Beyond it the ray's float origin, point + normal·d, no longer keeps the point to 0.1 mm.
constexpr double kMaxDistanceLimitM = 1000.0;

int runProbe(const ProbeOptions& o) {
  if (!(o.maxDistanceM > 0.0 && o.maxDistanceM <= kMaxDistanceLimitM)) {
    throw UsageError("--max-distance " + csvNumber(o.maxDistanceM) +
                     ": give a distance in metres, > 0 and at most " + csvNumber(kMaxDistanceLimitM) +
                     " (default 0.05)");
  }
  if (!std::filesystem::exists(o.baked)) {
    throw InputError({o.baked}, "does not exist", "give the directory that fly bake --out wrote");
  }
  if (!isBakedScene(o.baked)) {
    throw UsageError("fly probe reads a baked scene directory (fly bake SCENE --out DIR), not " + o.baked);
  }
  const SensorTable sensors = parseSensorCsv(readInputFile(o.points, "sensor file"), o.points);
  const RasterScene loaded = loadRasterScene(o.baked, DaylightOptions{});
  const rdb::RasterRdb rdb = rdb::buildRasterRdb(loaded.scene, &*loaded.lightMaps);
  const std::vector<SensorReading> readings =
      probeSensors(rdb, *loaded.lightMaps, loaded.scene, sensors, float(o.maxDistanceM), o.points, o.baked);
  writeFileAtomic(o.out, probeCsv(sensors, readings));
  size_t fromTextures = 0;
  for (const SensorReading& r : readings) fromTextures += r.lux.fromLightTexture;
  std::fprintf(stderr, "probe: %zu point%s (%zu from light textures, %zu from vertices) -> %s\n",
               readings.size(), readings.size() == 1 ? "" : "s", fromTextures, readings.size() - fromTextures,
               o.out.c_str());
  return 0;
}

}  // namespace

Command addProbeCommand(CLI::App& app) {
  auto o = std::make_shared<ProbeOptions>();
  CLI::App* sub = app.add_subcommand(
      "probe",
      "The baked light maps' illuminance (lux) and standard error at sensor points, as fly view's lux "
      "probe reads them");
  sub->add_option("BAKED", o->baked, "baked scene directory (fly bake SCENE --out DIR)")->required();
  sub->add_option(
         "--points", o->points,
         "sensor file (.csv), as fly illuminance reads it: a header naming the columns x,y,z,nx,ny,nz "
         "(metres, world space; the sensor's normal, which picks the side read), one row per sensor; "
         "other columns are kept")
      ->required();
  sub->add_option("--out", o->out,
                  "output .csv: the sensor rows with illuminance_lux and std_error_lux (as fly illuminance "
                  "writes them), source (vertices or light-texture) and distance_m (to the surface read)")
      ->required();
  sub->add_option("--max-distance", o->maxDistanceM,
                  "read the surface nearest each point along its normal within this many metres on either "
                  "side (default 0.05)")
      ->type_name("METRES");
  return {sub, [o] { return runProbe(*o); }};
}

}  // namespace fly::cli
