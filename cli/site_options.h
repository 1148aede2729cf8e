// The site and time options that `fly sun` and `fly sky` share, and their defaults from a scene file.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

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
