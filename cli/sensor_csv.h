// The sensor file of `fly illuminance --points FILE.csv`: a header line naming the columns (x, y, z, nx, ny,
// nz among any others, in any order), then one row per sensor: position in metres, world space, and the
// direction the sensor faces (normalised here). Rows keep their text, so that the output repeats them.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "base/math.h"

namespace fly::cli {

struct SensorTable {
  std::string header;              // the header line as written
  std::vector<std::string> lines;  // one per sensor, as written (a trailing '\r' removed)
  std::vector<vec3> positionsM;    // world space, metres
  std::vector<vec3> normals;       // unit length
  std::vector<int> lineNumbers;    // each sensor's line in the file (1-based); empty for a generated table
};

// The comma-separated fields of one line, as written (an empty last field after a trailing comma included).
std::vector<std::string> splitCsvFields(const std::string& line);

// `v` as the sensor files and fly's sensor outputs write numbers: 6 significant digits (%.6g).
std::string csvNumber(double v);

// `s` without leading and trailing blanks (space, tab, carriage return).
std::string trimBlanks(const std::string& s);

// Parses sensor-file text; `fileName` names it in errors. InputError with the line for: quoted fields, a
// header without one of x,y,z,nx,ny,nz, a row whose field count differs from the header's, a value that is
// not a finite decimal number, a zero normal, and a file without header or sensors.
SensorTable parseSensorCsv(std::string_view text, const std::string& fileName);

}  // namespace fly::cli
