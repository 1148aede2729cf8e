// libFuzzer target: EULUMDAT photometric files (sdb::parseEulumdat) and what a light does with the profile they
// give (interpolated intensity, total flux, peak).
#include <cmath>

#include "sdb/eulumdat.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fly::fuzz::quietLog();
  fly::fuzz::expectOnlyInputErrors([&] {
    const fly::sdb::Eulumdat e = fly::sdb::parseEulumdat(fly::fuzz::asText(data, size), "fuzz.ldt");
    const fly::sdb::IesProfile& p = e.profile;
    // An accepted file is usable: at least one lamp set, finite, non-negative intensities and flux everywhere.
    fly::fuzz::require(!e.lampSets.empty(), "at least one lamp set");
    fly::fuzz::require(p.candela.size() == p.horizontalDeg.size(), "one intensity row per C-plane");
    const double flux = p.totalFluxLm();
    fly::fuzz::require(std::isfinite(flux) && flux >= 0.0, "total flux is finite and >= 0");
    const double stated = e.statedLuminaireFluxLm();
    fly::fuzz::require(std::isfinite(stated) && stated >= 0.0, "stated luminaire flux is finite and >= 0");
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
