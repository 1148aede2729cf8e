// The plan images of a sensor grid's results (`--image plan.png` of fly illuminance and fly daylight-factor):
// their options, one plan per storey (cli/storeys.h) with the sensors drawn, and the false-colour plan
// (cli/false_colour_plan.h) with the storey's section, north arrow and metadata.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cli/false_colour_plan.h"
#include "cli/grid_sensors.h"
#include "cli/image_metadata.h"
#include "cli/storeys.h"
#include "rdb/trace_rdb.h"
#include "sdb/scene.h"

namespace fly::cli {

struct PlanImageOptions {
  std::string path;           // "" = no image
  std::string scale = "log";  // "log" or "linear"
  std::string range;          // "MIN,MAX" in the quantity's unit; "" = from the data
  double dotsPerInch = 0.0;   // 0 = none written
  double printWidthMm = 0.0;  // 0 = 1600 px wide
  std::optional<double> storeyM;  // --storey: the storey with its floors at this height (y, metres); none = all

  // Registers --image, --scale, --range, --dpi, --print-width and --storey; `quantity` names what is shown.
  void add(CLI::App& sub, const std::string& quantity);
  // UsageError naming the option for a path that is not .png, a malformed --scale or --range, --print-width
  // without --dpi or giving under 400 or over 20000 pixels, --storey not finite, and --image without a grid
  // (`hasGrid` false).
  void check(bool hasGrid) const;
};

// The grid's storeys and those the plans show: with --storey the one at that height (UsageError when none
// is: storeyAt), else every one. Made before the sensors are estimated, so that a wrong --storey costs
// nothing.
struct PlanStoreys {
  std::vector<Storey> all;   // gridStoreys of the sensors' floors
  std::vector<size_t> drawn;  // indices into `all`, from the lowest up
};
PlanStoreys planStoreys(const PlanImageOptions& options, const GridSensors& sensors);

// What the plan shows.
struct PlanContent {
  std::string title;  // e.g. "Illuminance, 0.85 m above the floor at y = 0 m"
  std::string subtitle;
  std::string unit;            // "lx", "%"
  std::vector<double> values;  // one per grid sensor
  double defaultMax = 0.0;     // the legend's top without --range (e.g. 100 % of daylight); 0 = the data's
  ImageSettings settings;      // metadata beside the command line
};

// One storey's plan: the lattice of its sensors, the drawing, and the file it goes to.
struct PlanSheet {
  PlanGrid grid;
  PlanDrawing drawing;
  std::filesystem::path path;
  std::string line;  // what it shows, for the command's output
};

// The plan of storey k of storeys.all: each place of the lattice shows the storey's lowest sensor there
// (its floor, not a furniture top above it), its caption the storey's mean, minimum and uniformity; the
// section is cut at the lowest shown sensors' height; north is the scene site's (true north, or its map
// grid's north converted by the meridian convergence). A single plan drawn goes to options.path, several
// each to its name with "-storeyK" before the extension (K from 0, the lowest). When the grid has several
// storeys the title names the storey and its main floor's height.
PlanSheet planSheet(const PlanImageOptions& options, const GridSensors& sensors, const PlanContent& content,
                    const PlanStoreys& storeys, size_t k, const rdb::TraceRdb& rdb, const sdb::Scene& scene);

// Draws the plans of storeys.drawn and returns a line for each that says what it shows.
std::vector<std::string> writePlanImage(const PlanImageOptions& options, const GridSensors& sensors,
                                        const PlanContent& content, const PlanStoreys& storeys,
                                        const rdb::TraceRdb& rdb, const sdb::Scene& scene);

}  // namespace fly::cli
