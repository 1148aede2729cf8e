// Goniometric light distributions from EULUMDAT files (.ldt; A. W. Stockmar, "EULUMDAT – ein
// Leuchtendatenformat für den europäischen Beleuchtungsplaner", Licht '90, and the line-by-line layout that
// lighting software documents), read into the representation IES LM-63 files give (IesProfile, photometry
// type C), so that a light does not care which format its distribution came from.
//
// The layout: lines 1–25 identify the luminaire and give the type indicator Ityp, the symmetry indicator
// Isym, the numbers of C-planes Mc and of γ angles Ng, dimensions in mm, the downward flux fraction, the
// light output ratio LORL and a conversion factor for the intensities; line 26 the number n of lamp sets;
// then six groups of n lines (number of lamps, lamp type, total luminous flux of the set's lamps in lm,
// colour temperature or appearance, colour rendering, wattage); 10 direct ratios; the Mc C-plane angles and
// the Ng γ angles; and the intensities in cd per 1000 lm of lamp flux for the C-planes the symmetry leaves, γ
// fastest.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sdb/ies.h"

namespace fly::sdb {

// One of the file's lamp sets (lines 26a–26f). The intensities refer to the first set.
struct EulumdatLampSet {
  // Number of lamps; negative means absolute photometry (LED luminaires measured whole): the flux is then the
  // luminaire's own, and |count| the number of lamps.
  int count = 1;
  std::string type;
  // Total luminous flux of all the set's lamps, lm (not per lamp); for absolute photometry the luminaire's.
  double totalFluxLm = 0.0;
  std::string colourTemperature;  // as written: "3000", "3000K", "WW" …
  std::string colourRendering;    // as written: "1B", "80" …
  double watts = 0.0;             // including ballast
};

struct Eulumdat {
  // Lines 1 and 8–12.
  std::string company;
  std::string reportNumber;
  std::string luminaireName;
  std::string luminaireNumber;
  std::string fileName;
  std::string dateUser;
  int typeIndicator = 1;  // Ityp: 0 point source without symmetry, 1 rotational, 2 linear, 3 other
  // Isym: 0 none, 1 about the vertical axis, 2 about the C0–C180 plane, 3 about the C90–C270 plane, 4 about
  // both.
  int symmetry = 0;
  int cPlaneCount = 0;                       // Mc, C-planes over 0–360°
  int gammaCount = 0;                        // Ng, γ angles per C-plane
  double downwardFluxFractionPercent = 0.0;  // DFF
  double lightOutputRatioPercent = 0.0;      // LORL: luminaire flux / lamp flux, %; 0 = not stated
  double conversionFactor = 1.0;             // multiplies the intensities
  double tiltDeg = 0.0;                      // tilt during measurement
  std::vector<EulumdatLampSet> lampSets;     // at least one
  std::array<double, 10> directRatios{};     // for room indices k = 0.6 … 5

  // The distribution in candela (γ angles as in the file, 0 beyond them), expanded to every C-plane: the
  // file's Mc angles and 360° (a copy of 0°), or for Isym 1 the single plane C = 0° that IesProfile reads as
  // rotationally symmetric. Candela = the file's cd/klm × the first lamp set's |total flux| / 1000 × the
  // conversion factor. lampLumens is that flux.
  IesProfile profile;

  bool absolutePhotometry() const { return lampSets.front().count < 0; }
  // The luminaire's flux the file states, lm: the first set's lamp flux × LORL / 100; 0 when LORL is 0 (not
  // stated).
  double statedLuminaireFluxLm() const { return profile.lampLumens * lightOutputRatioPercent / 100.0; }
};

// Parses EULUMDAT text. `fileName` names the source in errors (InputError with the 1-based line and a hint).
Eulumdat parseEulumdat(std::string_view text, const std::string& fileName);

// Reads and parses an EULUMDAT file (InputError for a missing, empty or malformed file).
Eulumdat loadEulumdat(const std::filesystem::path& path);

}  // namespace fly::sdb
