// libFuzzer target: the sensor file of `fly illuminance --points` (cli::parseSensorCsv).
#include <cmath>

#include "cli/sensor_csv.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fly::fuzz::expectOnlyInputErrors([&] {
    const fly::cli::SensorTable t = fly::cli::parseSensorCsv(fly::fuzz::asText(data, size), "fuzz.csv");
    fly::fuzz::require(
        !t.lines.empty() && t.lines.size() == t.positionsM.size() && t.lines.size() == t.normals.size(),
        "one position and normal per sensor line");
    for (size_t i = 0; i < t.lines.size(); ++i) {
      const fly::vec3 p = t.positionsM[i];
      fly::fuzz::require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
                         "positions are finite");
      const float length = glm::length(t.normals[i]);
      fly::fuzz::require(std::abs(length - 1.0f) < 1e-5f, "normals have unit length");
    }
  });
  return 0;
}
