// Daylight for a site and instant as the CLI builds it: the sky model the user chose and the sun's disc.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "cli/site_options.h"
#include "sunsky/epw.h"
#include "sunsky/sky.h"
#include "sunsky/sun_disc.h"

namespace fly::cli {

// Station pressure of the site: the --pressure value, or the standard atmosphere at its elevation.
double stationPressureHpa(const sunsky::SpaInput& spa);

// Clear-sky daylight (the Hosek–Wilkie sky and sun) on unobstructed surfaces, lux.
struct ClearDaylight {
  double directNormalLux = 0.0;
  double directHorizontalLux = 0.0;   // directNormalLux · cos(apparent zenith); 0 below the horizon
  double diffuseHorizontalLux = 0.0;  // ∫ L cos θ dω of the sky
};
ClearDaylight clearDaylight(const SiteTime& st, const sunsky::SunPosition& sun, double turbidity);

// What the user asked for with --sky and its inputs.
struct SkyRequest {
  std::string model = "clear";  // "clear", "preetham", "perez", "cie:N" (N = 1..15)
  double turbidity = 3.0;
  double groundAlbedo = 0.2;                   // the clear sky's ground albedo, [0, 1]
  std::optional<double> diffuseHorizontalLux;  // CIE normalisation, or Perez input (with directNormalLux)
  std::optional<double> zenithLuminanceCdM2;   // CIE normalisation
  std::optional<double> directNormalLux;       // the sun's disc for CIE and Perez skies
  std::optional<double> directNormalWm2;       // Perez input in W/m² (with diffuseHorizontalWm2)
  std::optional<double> diffuseHorizontalWm2;
  double dewPointC = 10.0;                   // Perez luminous efficacy input
  const sunsky::EpwFile* weather = nullptr;  // drives the Perez sky when set
};

struct Daylight {
  std::string description;  // e.g. "CIE standard sky type 12", "Perez all-weather (weather file …)"
  std::unique_ptr<sunsky::Sky> sky;
  std::optional<sunsky::SunDisc> sun;  // absent: the model has no sun (a CIE sky without --dni)
};

// Builds the sky and sun. UsageError for a missing or contradictory option, InputError for bad values.
Daylight makeDaylight(const SkyRequest& request, const SiteTime& st, const sunsky::SunPosition& sun);

}  // namespace fly::cli
