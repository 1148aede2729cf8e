// Goniometric light distributions from IES LM-63 files (LM-63-1995 and LM-63-2002; photometry types C, B and
// A; TILT=NONE only). Candela values are interpolated between measured angles; the total flux in lumens is
// integrated from the table.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace fly::sdb {

enum class IesFormat { kLm63_1986, kLm63_1991, kLm63_1995, kLm63_2002 };
enum class PhotometryType { kC = 1, kB = 2, kA = 3 };

struct IesProfile {
  IesFormat format = IesFormat::kLm63_2002;
  PhotometryType type = PhotometryType::kC;
  std::vector<std::string> keywords;  // "[KEY] value" header lines as they appear

  // Measured angles in degrees, ascending, as in the file: vertical (type C: γ from nadir, 0..180;
  // types A/B: elevation −90..90) and horizontal (type C: C-plane 0..360; types A/B: −90..90).
  std::vector<double> verticalDeg;
  std::vector<double> horizontalDeg;
  // candela[h][v], luminous intensity in cd with the file's candela multiplier, ballast factor and
  // ballast-lamp photometric factor applied.
  std::vector<std::vector<double>> candela;

  double lampLumens = 0.0;   // rated lumens per lamp × number of lamps; −1 in the file (absolute photometry) → 0
  double inputWatts = 0.0;   // input power, W
  double widthM = 0.0;       // luminous opening, metres (converted from feet when the file says so)
  double lengthM = 0.0;
  double heightM = 0.0;

  // Luminous intensity in cd towards the photometric direction (vertical, horizontal) in degrees, in the
  // type's own angles, interpolated bilinearly between measured angles; symmetric files (one C-plane,
  // 0–90°, 0–180° ...) are unfolded as LM-63 specifies. Directions outside the measured range give 0.
  double candelaAt(double verticalDeg, double horizontalDeg) const;

  // Luminous intensity in cd towards a unit direction in the light's frame: for type C, z = photometric axis
  // pointing to nadir (γ = 0), x in the C = 0° plane, y in C = 90°. For types A and B the axis convention of
  // LM-63 (x = lateral, z = forward) is used.
  double candelaTowards(double x, double y, double z) const;

  // Total luminous flux in lumens: ∫ I(ω) dω over the sphere of the interpolated distribution.
  double totalFluxLm() const;
  // Largest candela value in the table.
  double maxCandela() const;
};

// Parses LM-63 text. `fileName` names the source in errors (InputError with the line number and a hint).
IesProfile parseIes(std::string_view text, const std::string& fileName);

// Reads and parses an IES file (InputError for a missing, empty or malformed file).
IesProfile loadIes(const std::filesystem::path& path);

}  // namespace fly::sdb
