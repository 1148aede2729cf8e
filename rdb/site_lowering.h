// Where the SDB meets sunsky (docs/architecture.md: rdb/ calls sunsky once per change and stores the result in both RDBs):
// a scene's site, local time and sky settings lowered to a site frame, the sun's position, the sky model and the
// sun's disc. Both RDBs take their daylight from here, so the baker and the GL engine light a scene alike.
#pragma once

#include <memory>
#include <optional>

#include "sdb/scene.h"
#include "sdb/site.h"
#include "sunsky/site_frame.h"
#include "sunsky/sky.h"
#include "sunsky/sun_disc.h"
#include "sunsky/sun_position.h"

namespace fly::rdb {

// The orientation a scene's site gives its model: north angle and map grid.
sunsky::NorthReference northReference(const sdb::Site& site);

// The absolute level of a CIE standard sky when the scene gives none (sdb::SkySettings has no level): the
// diffuse horizontal illuminance, lux, of the IES Lighting Handbook's daylight-availability formulas (9th ed.,
// ch. 8) for solar elevation α:
//   types 1–5 (overcast):  Dv = 0.3 + 21.0·sin α klx
//   types 6–15:            Dv = 0.8 + 15.5·√(sin α) klx, the clear sky (sunsky::iesClearSkyDiffuseLux); the
//                          Handbook has no level of its own for the intermediate types 6–10, and their
//                          luminance distributions are those of a sky with the sun visible.
// With the sun below the horizon (α < 0) the level at α = 0 fades as the clear sky's twilight does
// (sunsky/clear_sky.h: the AMS Glossary's twilight illuminances, then the night sky), using `turbidity`
// ([1.7, 10]) and the sun's azimuth (degrees clockwise from north) for that clear sky.
double cieSkyDefaultDiffuseLux(int cieType, double sunElevationDeg, double sunAzimuthDeg, double turbidity);

// The day of the year whose Earth–Sun distance a sun placed directly (sdb::SunDirection) is given: 3 April,
// when the distance is the mean one (Spencer 1971's eccentricity correction is 1.000, sunsky/sun_disc.h).
inline constexpr int kDirectSunDayOfYear = 93;

// Daylight of a scene at its site and local time, or for its sun placed directly.
struct SceneDaylight {
  sunsky::SiteFrame frame;
  sunsky::SunPosition sunPosition;
  std::unique_ptr<sunsky::Sky> sky;   // null when the sky model is none
  std::optional<sunsky::SunDisc> sun; // absent when the scene asks for no sun or the sun is below the horizon
  dvec3 sunDirWorld{0.0, 1.0, 0.0};   // unit, towards the sun (its apparent position), world space
  double groundAlbedo = 0.2;          // sdb::SkySettings::groundAlbedo
};

// The scene's daylight, or nullopt when it asks for neither a sky nor a sun. The sun's position: from the site
// and local time by sunsky::sunPosition, or as placed directly (sdb::SiteTime::sunDirection; then a scene
// without a site stands at latitude 0, longitude 0 with north along −Z, which only orients the azimuth).
// Sky models (sdb::SkyModel):
//   clear: sunsky::makeHosekWilkieSky over the scene's ground albedo, with sunsky::hosekWilkieSunDisc;
//   preetham: sunsky::makeClearSky at the IES Lighting Handbook level (ClearSkyLevel::kIesHandbook);
//   cie:   sunsky::makeCieSky at cieSkyDefaultDiffuseLux;
//   perez: sunsky::makePerezSky from the weather file's direct normal and diffuse horizontal irradiance at the
//          instant (EPW hours are local standard time at the file's zone, sunsky/epw.h).
// The sun (SkySettings::sun): with a Perez sky the weather file's direct normal illuminance
// (sunDiscWithIlluminance), with the clear sky Hosek and Wilkie's (hosekWilkieSunDisc), otherwise the
// clear-atmosphere disc of the scene's turbidity (clearSkySunDisc), at
// the standard-atmosphere station pressure of the site's elevation. InputError (from sunsky) for a bad time or
// time zone, a site out of range, or a missing or bad weather file; std::invalid_argument when the scene asks
// for a sky or sun without a site and a local time or a sun direction (the scene-file reader and the CLI
// already reject that), or for a Perez sky from a weather file with a sun direction (the record needs a time).
std::optional<SceneDaylight> lowerDaylight(const sdb::Scene& scene);

}  // namespace fly::rdb
