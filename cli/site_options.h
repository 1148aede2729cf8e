// The site and time options: those `fly sun` and `fly sky` share (with their defaults from a scene file), and
// the daylight options of the commands that light a scene (render, view, bake, illuminance, info).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sdb/site.h"
#include "sunsky/civil_time.h"
#include "sunsky/site_frame.h"
#include "sunsky/sun_position.h"

namespace fly::cli {

struct SiteTimeOptions {
  std::string scene;  // scene file whose site and time are the defaults
  std::optional<double> latitudeDeg;
  std::optional<double> longitudeDeg;
  std::optional<double> elevationM;
  std::string time;
  std::string timeZone;
  std::optional<double> deltaTSeconds;
  double dut1Seconds = 0.0;
  std::optional<double> pressureHpa;
  std::optional<double> temperatureC;

  // Registers --scene, --lat, --lon, --elevation, --time, --tz, --delta-t, --dut1, --pressure, --temperature.
  void add(CLI::App& sub);
};

// Where and when a scene stands and its sky, from the command line: they override a scene file's values and
// put a plain glTF model in daylight (cli/scene_daylight.h applies them). Unset: the scene's value.
struct DaylightOptions {
  std::optional<double> latitudeDeg;   // [−90, 90], north positive
  std::optional<double> longitudeDeg;  // [−180, 180], east positive
  std::optional<double> elevationM;    // above sea level, metres, [−500, 9000]
  std::optional<double> northAngleDeg; // from the model's −Z to north, clockwise seen from above, [−360, 360]
  std::string time;                    // local (in --tz or the site's zone), UTC "…Z" or with an offset
  std::string timeZone;                // IANA name or offset, e.g. Europe/Helsinki, +03:00
  std::string sky;                     // clear, preetham, cie:N (N = 1..15) or perez
  std::optional<double> turbidity;     // Linke turbidity of the clear sky and the sun, [1.7, 10]
  std::optional<double> groundAlbedo;  // reflectance of the ground around the site, [0, 1]
  std::string weatherFile;             // EnergyPlus weather file driving the Perez sky
  std::string sunDirection;            // "AZIMUTH,ELEVATION" in degrees: the sun placed directly

  // Registers --lat, --lon, --elevation, --north, --time, --tz, --sky, --turbidity, --ground-albedo,
  // --weather, --sun-dir.
  // `timeLimit`: the run-time limit of a command's sampling options (bake, illuminance), whose --time this
  // --time takes over: a value in the form of a date (2026-06-21T15:00) is the site's time, any other a
  // time limit (90s, 5m), and --time may be given twice, once for each.
  void add(CLI::App& sub, std::string* timeLimit = nullptr);
  // The names of the options given (e.g. "--lat"), in the order above.
  std::vector<std::string> given() const;
};

// The resolved site and instant.
struct SiteTime {
  sunsky::SpaInput spa;
  std::string timeZone;   // --tz, the scene's zone, or the zone the time carries ("Z", "+03:00")
  double utcOffsetHours;  // at the instant, DST included
  std::string localIso;   // local civil time, "2026-06-21T12:00:00"
  // How the scene's model is oriented and its sky, when the site came from a scene (--scene).
  std::optional<sunsky::NorthReference> north;
  std::optional<sdb::SkySettings> sceneSky;
};

// Resolves the options (flags override the scene's values). UsageError for a missing latitude, longitude or
// time; InputError for invalid values.
SiteTime resolveSiteTime(const SiteTimeOptions& o);

// "2026-06-21T12:00:00" for a UTC instant shown at a UTC offset.
std::string localIso(const sunsky::UtcTime& utc, double utcOffsetHours);

}  // namespace fly::cli
