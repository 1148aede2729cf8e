#include "cli/grid_sensors.h"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "base/error.h"
#include "base/file_io.h"
#include "raytracer/sensor_grid.h"

namespace fly::cli {

namespace {

// The most sensors --grid may place: beyond this a spacing is surely a slip (10^6 sensors take minutes).
constexpr double kMaxGridSensors = 1e6;

}  // namespace

GridSpec parseGridSpec(const std::string& s, const std::string& area) {
  const std::vector<std::string> fields = splitCsvFields(s);
  GridSpec g;
  float* values[2] = {&g.heightM, &g.spacingM};
  bool ok = fields.size() == 2;
  for (size_t i = 0; ok && i < 2; ++i) {
    const std::string f = trimBlanks(fields[i]);
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
  if (area.empty()) return g;
  const std::vector<std::string> a = splitCsvFields(area);
  double v[4] = {0.0, 0.0, 0.0, 0.0};
  ok = a.size() == 4;
  for (size_t i = 0; ok && i < 4; ++i) {
    const std::string f = trimBlanks(a[i]);
    const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v[i]);
    ok = ec == std::errc() && ptr == f.data() + f.size() && std::isfinite(v[i]);
  }
  if (!ok) throw UsageError("--area " + area + ": expected XMIN,ZMIN,XMAX,ZMAX in metres, e.g. -4,-3,4,3");
  if (!(v[0] < v[2] && v[1] < v[3]))
    throw UsageError("--area " + area + ": XMIN must be < XMAX and ZMIN < ZMAX");
  g.areaM = std::pair(dvec2(v[0], v[1]), dvec2(v[2], v[3]));
  return g;
}

GridSensors gridSensors(const std::string& spec, const GridSpec& g, const std::string& scenePath,
                        const rdb::TraceRdb& rdb, const raytracer::EmbreeScene& embree) {
  const double columns = raytracer::floorGridColumnCount(rdb, g.spacingM);
  if (columns > kMaxGridSensors) {
    throw UsageError("--grid " + spec + ": a spacing of " + csvNumber(g.spacingM) + " m gives " +
                     csvNumber(columns) + " grid columns over the scene's " + csvNumber(rdb.boundsM.size().x) +
                     " m × " + csvNumber(rdb.boundsM.size().z) +
                     " m, more than the limit of 10^6 sensors; give a larger spacing");
  }
  std::vector<raytracer::GridSensor> grid = raytracer::floorSensorGrid(rdb, embree, g.heightM, g.spacingM);
  if (g.areaM) {
    const auto [lo, hi] = *g.areaM;
    std::erase_if(grid, [&](const raytracer::GridSensor& s) {
      return s.positionM.x < lo.x || s.positionM.x > hi.x || s.positionM.z < lo.y || s.positionM.z > hi.y;
    });
  }
  if (double(grid.size()) > kMaxGridSensors) {
    throw UsageError("--grid " + spec + ": " + std::to_string(grid.size()) +
                     " sensors over all floors, more than the limit of 10^6; give a larger spacing");
  }
  if (grid.empty()) {
    throw InputError(
        {scenePath},
        "--grid " + spec + ": the scene has no floor with " + csvNumber(g.heightM) +
            " m of free space above it" + (g.areaM ? " within --area" : ""),
        "a floor is a surface facing up (within 25.8° of +Y); give a smaller height or use --points");
  }
  GridSensors out;
  out.spacingM = g.spacingM;
  SensorTable& t = out.table;
  t.header = "x,y,z,nx,ny,nz";
  for (const raytracer::GridSensor& s : grid) {
    t.lines.push_back(csvNumber(s.positionM.x) + "," + csvNumber(s.positionM.y) + "," + csvNumber(s.positionM.z) +
                      "," + csvNumber(s.normal.x) + "," + csvNumber(s.normal.y) + "," + csvNumber(s.normal.z));
    t.positionsM.push_back(s.positionM);
    t.normals.push_back(s.normal);
    out.floorHeightsM.push_back(s.floorHeightM);
  }
  return out;
}

GridSpec parseSensorOptions(const std::string& points, const std::string& grid, const std::string& area) {
  if (!area.empty() && grid.empty()) throw UsageError("--area " + area + " limits --grid; give --grid too");
  if (points.empty() == grid.empty()) {
    throw UsageError(
        "give exactly one of --points FILE.csv (your sensors) and --grid HEIGHT,SPACING (a grid "
        "over the floors)");
  }
  return grid.empty() ? GridSpec{} : parseGridSpec(grid, area);
}

GridSensors loadSensors(const std::string& points, const std::string& gridText, const GridSpec& grid,
                        const std::string& scenePath, const rdb::TraceRdb& rdb,
                        const raytracer::EmbreeScene& embree) {
  if (!points.empty()) return GridSensors{parseSensorCsv(readInputFile(points, "sensor file"), points), {}, 0.0f};
  return gridSensors(gridText, grid, scenePath, rdb, embree);
}

}  // namespace fly::cli
