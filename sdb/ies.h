// Goniometric light distributions from IES LM-63 files (LM-63-1986, -1991, -1995 and -2002; photometry
// types C, B and A; TILT=NONE only). Candela values are interpolated between measured angles; the total flux
// in lumens is integrated from the table. EULUMDAT files are read into the same representation
// (sdb/eulumdat.h).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace fly::sdb {

// The file format a profile was read from: the LM-63 versions, or EULUMDAT (sdb/eulumdat.h).
enum class IesFormat { kLm63_1986, kLm63_1991, kLm63_1995, kLm63_2002, kEulumdat };
enum class PhotometryType { kC = 1, kB = 2, kA = 3 };

struct IesProfile {
  IesFormat format = IesFormat::kLm63_2002;
  PhotometryType type = PhotometryType::kC;
  // "[KEY] value" header lines as they appear, [MORE] lines included; LM-63-1986 files have free-text label
  // lines instead, kept the same way. Blank lines are left out.
  std::vector<std::string> keywords;

  // Measured angles in degrees, ascending, as in the file: vertical (type C: γ from nadir, 0..180;
  // types A/B: V, −90..90) and horizontal (type C: C-plane 0..360; types A/B: H, −90..90); see
  // candelaTowards.
  std::vector<double> verticalDeg;
  std::vector<double> horizontalDeg;
  // candela[h][v], luminous intensity in cd with the file's candela multiplier, ballast factor and
  // ballast-lamp photometric factor applied.
  std::vector<std::vector<double>> candela;

  double lampLumens = 0.0;   // rated lumens per lamp × number of lamps; −1 in the file (absolute photometry) → 0
  double inputWatts = 0.0;   // input power, W
  // Luminous opening, metres (converted from feet when the file says so). Signs are kept: LM-63-2002 uses
  // negative values for round and spherical openings.
  double widthM = 0.0;
  double lengthM = 0.0;
  double heightM = 0.0;

  // Luminous intensity in cd towards the photometric direction (vertical, horizontal) in degrees, in the
  // type's own angles, interpolated bilinearly between measured angles; symmetric files (one C-plane,
  // 0–90°, 0–180° ...) are unfolded as LM-63 specifies. Directions outside the measured range give 0.
  double candelaAt(double verticalDeg, double horizontalDeg) const;

  // Luminous intensity in cd towards a direction in the light's frame (normalised here; zero length gives 0).
  // Type C: z = photometric axis pointing to nadir (γ = 0), x in the C = 0° plane, y in C = 90°;
  //   γ = acos z, C = atan2(y, x) in [0°, 360°).
  // Types A and B: z = forward (H = V = 0°), x = lateral (H = +90°, V = 0°), y = z × x = the
  //   direction V = −90°. With V = +90° pointing up, +x is then to the right of the beam, as LM-63-2002
  //   measures horizontal angles of types A and B clockwise seen from above.
  //   Type A (planes share the vertical axis y, as for automotive lamps): V = elevation = asin(−y),
  //     H = atan2(x, z); direction = (cos V sin H, −sin V, cos V cos H); dω = cos V dV dH.
  //   Type B (planes share the lateral axis x, as for floodlights): V = tilt of the plane
  //     = atan2(−y, z), H = angle within the plane = asin x;
  //     direction = (sin H, −cos H sin V, cos H cos V); dω = cos H dH dV.
  //   Both cover the hemisphere z ≥ 0; behind it (|H| or |V| > 90°) the intensity is 0.
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
