#include "cli/sensor_csv.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "base/error.h"

namespace fly::cli {

std::vector<std::string> splitCsvFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream s(line);
  while (std::getline(s, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string csvNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string trimBlanks(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  const size_t b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

SensorTable parseSensorCsv(std::string_view text, const std::string& fileName) {
  SensorTable t;
  std::istringstream in{std::string(text)};
  std::string line;
  int lineNo = 0;
  int col[6] = {-1, -1, -1, -1, -1, -1};
  static const char* kNames[6] = {"x", "y", "z", "nx", "ny", "nz"};
  size_t columns = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trimBlanks(line).empty()) continue;
    if (line.find('"') != std::string::npos) {
      throw InputError({fileName, lineNo}, "quoted fields are not supported",
                       "write plain comma-separated numbers");
    }
    const std::vector<std::string> fields = splitCsvFields(line);
    if (t.header.empty()) {
      t.header = line;
      columns = fields.size();
      for (size_t i = 0; i < fields.size(); ++i) {
        for (int k = 0; k < 6; ++k) {
          if (trimBlanks(fields[i]) == kNames[k]) col[k] = int(i);
        }
      }
      for (int k = 0; k < 6; ++k) {
        if (col[k] < 0) {
          throw InputError(
              {fileName, lineNo}, std::string("the header has no column \"") + kNames[k] + "\"",
              "the first line must name the columns, e.g. x,y,z,nx,ny,nz (metres, world space; the "
              "sensor's normal)");
        }
      }
      continue;
    }
    if (fields.size() != columns) {
      throw InputError(
          {fileName, lineNo},
          "has " + std::to_string(fields.size()) + " fields, the header " + std::to_string(columns),
          "give every row the header's columns");
    }
    float v[6];
    for (int k = 0; k < 6; ++k) {
      const std::string f = trimBlanks(fields[size_t(col[k])]);
      const char* end = f.data() + f.size();
      const auto [ptr, ec] = std::from_chars(f.data(), end, v[k]);
      if (ec != std::errc() || ptr != end || !std::isfinite(v[k])) {
        throw InputError(
            {fileName, lineNo},
            std::string("column \"") + kNames[k] + "\": '" + printableExcerpt(f) + "' is not a finite number",
            "write decimal numbers such as 1.25 or -3e2");
      }
    }
    // In double: the squared length of a float vector neither overflows (3e38) nor underflows (1e-30).
    const dvec3 n(v[3], v[4], v[5]);
    const double length = glm::length(n);
    if (!(length > 0.0)) {
      throw InputError({fileName, lineNo}, "the sensor's normal (nx, ny, nz) is zero",
                       "give the direction the sensor faces, e.g. 0,1,0 for a horizontal sensor facing up");
    }
    t.lines.push_back(line);
    t.positionsM.emplace_back(v[0], v[1], v[2]);
    t.normals.emplace_back(n / length);
    t.lineNumbers.push_back(lineNo);
  }
  if (t.header.empty())
    throw InputError({fileName}, "the sensor file has no header line", "start with x,y,z,nx,ny,nz");
  if (t.lines.empty())
    throw InputError({fileName}, "the sensor file has no sensors", "add one row per sensor");
  return t;
}

}  // namespace fly::cli
