// The sensors of `--grid HEIGHT,SPACING` (fly illuminance, fly daylight-factor): a horizontal work plane
// HEIGHT m above every floor, sensors SPACING m apart (raytracer/sensor_grid.h), as a sensor table.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base/math.h"
#include "cli/sensor_csv.h"
#include "raytracer/embree_scene.h"
#include "rdb/trace_rdb.h"

namespace fly::cli {

struct GridSpec {
  float heightM = 0.0f;   // above the floors, > 0
  float spacingM = 0.0f;  // ≥ 0.01
  // --area: only sensors with x in [min.x, max.x] and z in [min.y, max.y] (world, metres); none = all.
  std::optional<std::pair<dvec2, dvec2>> areaM;
};

// --grid HEIGHT,SPACING in metres, e.g. 0.85,0.5, and --area XMIN,ZMIN,XMAX,ZMAX ("" = none). UsageError
// naming the option for a malformed or out-of-range value.
GridSpec parseGridSpec(const std::string& spec, const std::string& area = "");

// The sensor options of fly illuminance and fly daylight-factor: exactly one of --points FILE.csv and --grid
// HEIGHT,SPACING, and --area only with --grid. UsageError otherwise; a bad grid fails here, before the scene is
// loaded. Returns the grid (an empty GridSpec with --points).
GridSpec parseSensorOptions(const std::string& points, const std::string& grid, const std::string& area);

struct GridSensors {
  SensorTable table;                 // columns x,y,z,nx,ny,nz
  std::vector<float> floorHeightsM;  // the floor under each sensor (y, metres)
  float spacingM = 0.0f;
};

// The grid's sensors over the scene's floors. UsageError naming --grid when the spacing would give more than
// 10^6 sensors; InputError naming the scene when no floor (within the area) has the height's free space above
// it.
GridSensors gridSensors(const std::string& spec, const GridSpec& grid, const std::string& scenePath,
                        const rdb::TraceRdb& rdb, const raytracer::EmbreeScene& embree);

// The sensors of --points (the CSV file) or, when it is "", of --grid `gridText` (parsed as `grid`).
GridSensors loadSensors(const std::string& points, const std::string& gridText, const GridSpec& grid,
                        const std::string& scenePath, const rdb::TraceRdb& rdb,
                        const raytracer::EmbreeScene& embree);

}  // namespace fly::cli
