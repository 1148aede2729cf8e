// The plan image of a sensor grid's results (`--image plan.png` of fly illuminance and fly daylight-factor):
// its options, the sensors drawn, and the false-colour plan (cli/false_colour_plan.h) with the
// scene's section, north arrow and metadata.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli/grid_sensors.h"
#include "cli/image_metadata.h"
#include "rdb/trace_rdb.h"
#include "sdb/scene.h"

namespace fly::cli {

struct PlanImageOptions {
  std::string path;           // "" = no image
  std::string scale = "log";  // "log" or "linear"
  std::string range;          // "MIN,MAX" in the quantity's unit; "" = from the data
  double dotsPerInch = 0.0;   // 0 = none written
  double printWidthMm = 0.0;  // 0 = 1600 px wide

  // Registers --image, --scale, --range, --dpi and --print-width; `quantity` names what is shown.
  void add(CLI::App& sub, const std::string& quantity);
  // UsageError naming the option for a path that is not .png, a malformed --scale or --range, --print-width
  // without --dpi or giving under 400 or over 20000 pixels, and --image without a grid (`hasGrid` false).
  void check(bool hasGrid) const;
};

// What the plan shows.
struct PlanContent {
  std::string title;  // e.g. "Illuminance, 0.85 m above the floor at y = 0 m"
  std::string subtitle;
  std::string unit;            // "lx", "%"
  std::vector<double> values;  // one per grid sensor
  double defaultMax = 0.0;     // the legend's top without --range (e.g. 100 % of daylight); 0 = the data's
  ImageSettings settings;      // metadata beside the command line
};

// Draws the plan and returns a line that says what it shows. Each place of the lattice shows its lowest
// sensor: the ground floor and the ground around a building form one plan; upper storeys, roofs and furniture
// tops show only where nothing lies below them. The section is cut at the lowest shown sensors' height; north
// is the scene site's (true north, or its map grid's north converted by the meridian convergence).
std::string writePlanImage(const PlanImageOptions& options, const GridSensors& sensors,
                           const PlanContent& content, const rdb::TraceRdb& rdb, const sdb::Scene& scene);

}  // namespace fly::cli
