// libFuzzer target: IES LM-63 photometric files (sdb::parseIes) and what a light does with a profile
// (interpolated intensity, total flux, peak).
#include <cmath>

#include "sdb/ies.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fly::fuzz::quietLog();
  fly::fuzz::expectOnlyInputErrors([&] {
    const fly::sdb::IesProfile p = fly::sdb::parseIes(fly::fuzz::asText(data, size), "fuzz.ies");
    // An accepted profile is usable: finite, non-negative intensities and flux everywhere.
    const double flux = p.totalFluxLm();
    fly::fuzz::require(std::isfinite(flux) && flux >= 0.0, "total flux is finite and >= 0");
    const double peak = p.maxCandela();
    fly::fuzz::require(std::isfinite(peak) && peak >= 0.0, "max candela is finite and >= 0");
    for (const double z : {-1.0, -0.5, 0.0, 0.5, 1.0}) {
      for (const double x : {-1.0, 0.0, 1.0}) {
        const double cd = p.candelaTowards(x, 0.3, z);
        fly::fuzz::require(std::isfinite(cd) && cd >= 0.0, "candelaTowards is finite and >= 0");
      }
    }
  });
  return 0;
}
