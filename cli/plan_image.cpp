#include "cli/plan_image.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "base/error.h"
#include "cli/false_colour_plan.h"
#include "cli/plan_section.h"
#include "rdb/site_lowering.h"
#include "sunsky/site_frame.h"

namespace fly::cli {

namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// A value as a plan's caption gives it: whole units from 100 up (34660 lx, not 3.466e+04), else 3 digits.
std::string quantity(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, std::fabs(v) >= 100.0 ? "%.0f" : "%.3g", v);
  return buf;
}

std::optional<std::pair<double, double>> parseRange(const std::string& s, bool logarithmic) {
  if (s.empty()) return std::nullopt;
  const std::vector<std::string> fields = splitCsvFields(s);
  double v[2] = {0.0, 0.0};
  bool ok = fields.size() == 2;
  for (size_t i = 0; ok && i < 2; ++i) {
    const std::string f = trimBlanks(fields[i]);
    const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v[i]);
    ok = ec == std::errc() && ptr == f.data() + f.size() && std::isfinite(v[i]);
  }
  if (!ok) throw UsageError("--range " + s + ": expected MIN,MAX, e.g. 100,10000");
  if (!(v[0] < v[1])) throw UsageError("--range " + s + ": MIN must be less than MAX");
  if (logarithmic && !(v[0] > 0.0)) {
    throw UsageError("--range " + s + ": a log scale needs MIN > 0; give a positive MIN or --scale linear");
  }
  return std::pair(v[0], v[1]);
}

}  // namespace

void PlanImageOptions::add(CLI::App& sub, const std::string& quantity) {
  sub.add_option(
      "--image", path,
      "also draw a false-colour plan of the " + quantity +
          " (PNG; needs --grid): cubehelix colour map, legend, iso-lines at the legend's ticks, the "
          "scene's section at the sensors' height, north arrow and scale bar");
  sub.add_option("--scale", scale, "the plan's colour scale: log (default) or linear");
  sub.add_option("--range", range,
                 "the plan's legend range MIN,MAX (default: the data's, widened to 1-2-5 values)")
      ->type_name("MIN,MAX");
  addDpiOption(sub, &dotsPerInch);
  sub.add_option(
      "--print-width", printWidthMm,
      "the plan's printed width in millimetres (with --dpi: pixels = mm / 25.4 × dpi); default 1600 "
      "pixels");
  sub.add_option(
         "--storey", storeyM,
         "draw only the storey whose floors lie at this height (y, metres; floors less than 2 m above "
         "a storey's lowest are on it); default: one plan per storey, PLAN-storeyK.png (K from 0, "
         "the lowest) when the grid has several")
      ->type_name("HEIGHT");
}

void PlanImageOptions::check(bool hasGrid) const {
  if (path.empty()) {
    if (!range.empty() || printWidthMm != 0.0 || storeyM) {
      throw UsageError("--range, --print-width and --storey set the plan image: give --image plan.png too");
    }
    return;
  }
  if (storeyM && !std::isfinite(*storeyM)) throw UsageError("--storey must be a finite height in metres");
  if (!hasGrid)
    throw UsageError("--image " + path + ": a plan needs sensors on a grid; give --grid HEIGHT,SPACING");
  if (std::filesystem::path(path).extension() != ".png") {
    throw UsageError("--image " + path + ": the plan is written as PNG; give a file name ending in .png");
  }
  if (scale != "log" && scale != "linear") throw UsageError("--scale " + scale + ": expected log or linear");
  parseRange(range, scale == "log");
  if (printWidthMm != 0.0) {
    if (dotsPerInch == 0.0) throw UsageError("--print-width needs --dpi (pixels = mm / 25.4 × dpi)");
    const double px = printWidthMm / 25.4 * dotsPerInch;
    if (!(px >= 400.0 && px <= 20000.0)) {
      throw UsageError("--print-width " + number(printWidthMm) + " at --dpi " + number(dotsPerInch) +
                       " gives " + number(px) + " pixels; the plan must be 400 to 20000 pixels wide");
    }
  }
}

PlanStoreys planStoreys(const PlanImageOptions& o, const GridSensors& sensors) {
  PlanStoreys p;
  p.all = gridStoreys(sensors.floorHeightsM);
  if (o.storeyM) {
    p.drawn.push_back(storeyAt(p.all, *o.storeyM));
  } else {
    for (size_t k = 0; k < p.all.size(); ++k) p.drawn.push_back(k);
  }
  return p;
}

PlanSheet planSheet(const PlanImageOptions& o, const GridSensors& sensors, const PlanContent& content,
                    const PlanStoreys& storeys, size_t k, const rdb::TraceRdb& rdb, const sdb::Scene& scene) {
  // The lattice (shared by every storey, raytracer/sensor_grid.h): columns and rows counted from the
  // storey's sensors' smallest x and z. Each cell shows the storey's lowest sensor there.
  const SensorTable& t = sensors.table;
  const Storey& storey = storeys.all.at(k);
  const double spacing = sensors.spacingM;
  dvec2 lo(INFINITY);
  for (const size_t i : storey.sensors) lo = glm::min(lo, dvec2(t.positionsM[i].x, t.positionsM[i].z));
  PlanSheet sheet;
  PlanGrid& grid = sheet.grid;
  grid.originM = lo;
  grid.spacingM = spacing;
  std::vector<std::pair<int, int>> cells;
  for (const size_t i : storey.sensors) {
    const vec3& p = t.positionsM[i];
    cells.emplace_back(int(std::lround((p.x - lo.x) / spacing)), int(std::lround((p.z - lo.y) / spacing)));
    grid.values.columns = std::max(grid.values.columns, cells.back().first + 1);
    grid.values.rows = std::max(grid.values.rows, cells.back().second + 1);
  }
  const size_t cellCount = size_t(grid.values.columns) * size_t(grid.values.rows);
  grid.values.values.assign(cellCount, NAN);
  std::vector<size_t> shownSensor(cellCount, SIZE_MAX);
  for (size_t j = 0; j < cells.size(); ++j) {
    const size_t i = storey.sensors[j];
    const size_t cell = size_t(cells[j].second) * size_t(grid.values.columns) + size_t(cells[j].first);
    if (shownSensor[cell] == SIZE_MAX || t.positionsM[i].y < t.positionsM[shownSensor[cell]].y) {
      shownSensor[cell] = i;
      grid.values.values[cell] = content.values[i];
    }
  }
  std::vector<double> shown;
  double sectionY = INFINITY;
  for (const size_t i : shownSensor) {
    if (i == SIZE_MAX) continue;
    shown.push_back(content.values[i]);
    sectionY = std::min(sectionY, double(t.positionsM[i].y));
  }

  const bool logarithmic = o.scale == "log";
  const bool several = storeys.all.size() > 1;
  const std::string storeyName = "storey " + std::to_string(k) + " of " + std::to_string(storeys.all.size()) +
                                 " (floor at y = " + number(storey.mainFloorM) + " m)";
  PlanDrawing& d = sheet.drawing;
  d.title = several ? content.title + ", " + storeyName : content.title;
  d.subtitle = content.subtitle;
  d.unit = content.unit;
  std::optional<std::pair<double, double>> range = parseRange(o.range, logarithmic);
  if (!range && content.defaultMax > 0.0) {
    FalseColourScale fromData = falseColourScale(shown, logarithmic);
    if (fromData.minValue >= content.defaultMax)
      fromData.minValue = logarithmic ? content.defaultMax / 10.0 : 0.0;
    range = std::pair(fromData.minValue, content.defaultMax);
  }
  d.scale = falseColourScale(shown, logarithmic, range);
  d.outlineM = horizontalSection(rdb, sectionY);
  const sdb::Site& site = scene.site();
  const sunsky::SiteFrame frame =
      sunsky::makeSiteFrame(site.latitudeDeg, site.longitudeDeg, rdb::northReference(site), {});
  const dvec3 north = frame.worldFromEnu(dvec3(0.0, 1.0, 0.0));
  d.northPlan = glm::normalize(dvec2(north.x, north.z));
  if (o.printWidthMm > 0.0) d.widthPx = int(std::lround(o.printWidthMm / 25.4 * o.dotsPerInch));
  double sum = 0.0, minimum = INFINITY;
  for (const double v : shown) {
    sum += v;
    minimum = std::min(minimum, v);
  }
  const double mean = sum / double(shown.size());
  d.caption = "mean " + quantity(mean) + " " + content.unit + "  ·  min " + quantity(minimum) + " " +
              content.unit + "  ·  uniformity (min/mean) " +
              (mean > 0.0 ? quantity(minimum / mean) : std::string("–")) + "  ·  " +
              std::to_string(shown.size()) + " sensors, " + number(spacing) + " m apart";
  ImageSettings settings = content.settings;
  if (several) {
    settings.emplace_back("fly:storey", storeyName + ", floors from y = " + number(storey.lowestFloorM) +
                                            " to " + number(storey.highestFloorM) + " m");
  }
  settings.emplace_back("fly:scale", std::string(logarithmic ? "log" : "linear") + ", " +
                                         number(d.scale.minValue) + " to " + number(d.scale.maxValue) + " " +
                                         content.unit);
  d.metadata = imageMetadata(d.title, settings, o.dotsPerInch);
  sheet.path = o.path;
  if (storeys.drawn.size() > 1) {
    const std::filesystem::path p(o.path);
    sheet.path =
        p.parent_path() / (p.stem().string() + "-storey" + std::to_string(k) + p.extension().string());
  }
  sheet.line = "plan of " + std::to_string(shown.size()) + " of " + std::to_string(t.positionsM.size()) +
               " sensors" + (several ? ", " + storeyName : std::string()) +
               ", section at y = " + number(sectionY) + " m -> " + sheet.path.string();
  return sheet;
}

std::vector<std::string> writePlanImage(const PlanImageOptions& o, const GridSensors& sensors,
                                        const PlanContent& content, const PlanStoreys& storeys,
                                        const rdb::TraceRdb& rdb, const sdb::Scene& scene) {
  std::vector<std::string> lines;
  for (const size_t k : storeys.drawn) {
    const PlanSheet sheet = planSheet(o, sensors, content, storeys, k, rdb, scene);
    drawFalseColourPlan(sheet.grid, sheet.drawing, sheet.path);
    lines.push_back(sheet.line);
  }
  return lines;
}

}  // namespace fly::cli
