// libFuzzer target: EnergyPlus weather files (sunsky::parseEpw) and sampling the weather they give.
#include <cmath>

#include "sunsky/epw.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fly::fuzz::quietLog();
  fly::fuzz::expectOnlyInputErrors([&] {
    const fly::sunsky::EpwFile f = fly::sunsky::parseEpw(fly::fuzz::asText(data, size), "fuzz.epw");
    fly::fuzz::require(!f.records.empty(), "an accepted file has records");
    const fly::sunsky::EpwRecord& first = f.records.front();
    // The first record's own day at its mid-point, and the hour after: both inside what the file covers.
    const fly::sunsky::EpwSample s =
        fly::sunsky::sampleAt(f, first.month, first.day, first.representativeHour());
    for (const auto& v : {s.ghiWm2, s.dniWm2, s.dhiWm2, s.ghiLux, s.dniLux, s.dhiLux}) {
      fly::fuzz::require(!v || (std::isfinite(*v) && *v >= 0.0), "sampled radiation is finite and >= 0");
    }
    fly::sunsky::sampleAt(f, first.month, first.day, std::min(24.0, first.representativeHour() + 1.0));
  });
  return 0;
}
