// What glTF lacks for daylight: the site on Earth, the local date and time, the sky. Interpreted by sunsky/.
#pragma once

#include <optional>
#include <string>

namespace fly::sdb {

struct Site {
  double latitudeDeg = 0.0;   // geodetic (WGS84), [−90, 90], north positive
  double longitudeDeg = 0.0;  // [−180, 180], east positive
  double elevationM = 0.0;    // above mean sea level, metres, [−500, 9000]
  // IANA time-zone name ("Europe/Helsinki") or a fixed UTC offset ("+03:00", "-07:00", "Z").
  std::string timeZone = "Z";
  // Angle in degrees from the scene's −Z axis to the model's north, clockwise seen from above (+Y),
  // [−360, 360]. The model's north is true north, or grid north when the model is drawn on a map grid (below).
  // 0 = the model's north along −Z (glTF's "forward").
  double northAngleDeg = 0.0;
  // The map grid a model is drawn on, whose grid north differs from true north by the meridian convergence
  // (applied by sunsky's site frame): none, a UTM zone, or a transverse-Mercator grid by its central meridian
  // (e.g. ETRS-TM35FIN: 27° E).
  enum class Grid { kNone, kUtm, kTransverseMercator };
  Grid grid = Grid::kNone;
  int utmZone = 0;                      // 1..60, with Grid::kUtm
  double gridCentralMeridianDeg = 0.0;  // [−180, 180], with Grid::kTransverseMercator
};

enum class SkyModel {
  kNone,    // no sky light
  kCie,     // CIE standard general sky (ISO 15469), type `cieType`
  kPerez,   // Perez all-weather sky (from weather data or given irradiances)
  kClear,     // Hosek–Wilkie clear sky and its sun (sunsky/hosek_wilkie.h)
  kPreetham,  // Preetham et al.'s clear sky at the IES Handbook level, with the clear-atmosphere sun
};

// The clear skies, whose light follows the turbidity.
inline bool isClearSky(SkyModel m) { return m == SkyModel::kClear || m == SkyModel::kPreetham; }

const char* skyModelName(SkyModel m);
// "none", "utm:35", "tm:27" — as the scene file writes it.
std::string gridName(const Site& site);  // "none", "cie", "perez", "clear", "preetham"

struct SkySettings {
  SkyModel model = SkyModel::kNone;
  int cieType = 12;          // CIE standard sky type, 1..15 (12 = CIE standard clear sky, low turbidity)
  double turbidity = 3.0;    // Linke turbidity, [1.7, 10]
  std::string weatherFile;   // EnergyPlus EPW file driving the Perez sky; "" = none
  bool sun = false;          // the sun as a light source (disc of 0.533°)
  // Reflectance of the open ground around the site, [0, 1]: the clear sky's (Hosek–Wilkie's ground albedo) and
  // that of the ground the GL engine draws below the horizon. 0.2: grass, soil and pavement.
  double groundAlbedo = 0.2;
};

// The sun placed directly instead of by the site's date and time (the FLY paper, §3: "direct specification
// of sun position"). Its light is that of the sky model for this position; the Earth–Sun distance is the mean
// one (rdb::kDirectSunDayOfYear).
struct SunDirection {
  double azimuthDeg = 0.0;    // clockwise from the site's north (Site::northAngleDeg from −Z), [0, 360)
  double elevationDeg = 0.0;  // apparent elevation above the horizon (as seen, refraction included), [−90, 90]
};

// When the sun stands: the local civil date and time at the site, ISO 8601 ("2026-06-21T12:00" or with
// seconds; the zone is Site::timeZone unless the text carries one), or a sun placed directly. At most one
// of the two is set.
struct SiteTime {
  std::string localDateTime;
  std::optional<SunDirection> sunDirection;
};

}  // namespace fly::sdb
