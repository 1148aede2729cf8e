#include "cli/site_options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "base/error.h"
#include "rdb/site_lowering.h"
#include "sdb/scene_load.h"

namespace fly::cli {

void SiteTimeOptions::add(CLI::App& sub) {
  sub.add_option("--scene", scene, "scene file (.json) whose site and time are the defaults");
  sub.add_option("--lat", latitudeDeg, "latitude, degrees north, [-90, 90]");
  sub.add_option("--lon", longitudeDeg, "longitude, degrees east, [-180, 180]");
  sub.add_option("--elevation", elevationM, "elevation above sea level, metres (default 0)");
  sub.add_option("--time", time,
                 "local time 2026-06-21T12:00 (in --tz), UTC 2026-06-21T09:00:00Z or with an offset "
                 "2026-06-21T12:00+03:00");
  sub.add_option("--tz", timeZone,
                 "time zone: IANA name (Europe/Helsinki, daylight saving applied) or offset +03:00");
  sub.add_option("--delta-t", deltaTSeconds, "TT - UT1, seconds (default: Espenak-Meeus polynomials)");
  sub.add_option("--dut1", dut1Seconds, "UT1 - UTC, seconds (default 0)")->capture_default_str();
  sub.add_option("--pressure", pressureHpa,
                 "mean air pressure, hPa (default: standard atmosphere at the elevation)");
  sub.add_option("--temperature", temperatureC,
                 "mean air temperature, degrees Celsius (default: standard atmosphere at the elevation)");
}

void DaylightOptions::add(CLI::App& sub, std::string* timeLimit) {
  const std::string group =
      "Daylight (each overrides the scene file's value; a plain glTF without lights is put in a clear sky with "
      "the sun at 45° elevation, azimuth 135°, unless these place it; --sun-dir excludes --lat, --lon, --time "
      "and --tz)";
  if (timeLimit) {
    sub.remove_option(sub.get_option("--time"));
    sub.add_option_function<std::vector<std::string>>(
           "--time",
           [this, timeLimit](const std::vector<std::string>& values) {
             for (const std::string& v : values) {
               const bool date = v.size() >= 5 && std::all_of(v.begin(), v.begin() + 4, ::isdigit) && v[4] == '-';
               std::string& target = date ? time : *timeLimit;
               if (!target.empty()) {
                 throw UsageError(std::string("--time given twice as a ") + (date ? "date and time" : "time limit") +
                                  " (" + target + ", " + v + "): give one of each at most");
               }
               target = v;
             }
           },
           "the site's date and time (as below), and/or the run-time limit (e.g. 60s or 5m; default: the "
           "scene's bake.time): a value in the form of a date is the former, any other the latter; give "
           "--time twice for both")
        ->type_name("TIME");
  } else {
    sub.add_option("--time", time,
                   "date and time at the site: local 2026-06-21T15:00 (in --tz or the scene's zone), UTC "
                   "2026-06-21T12:00Z or with an offset 2026-06-21T15:00+03:00 (default: the scene's)")
        ->group(group);
  }
  sub.add_option("--lat", latitudeDeg, "latitude of the site, degrees north, [-90, 90]; with --lon")
      ->group(group);
  sub.add_option("--lon", longitudeDeg, "longitude of the site, degrees east, [-180, 180]; with --lat")
      ->group(group);
  sub.add_option("--elevation", elevationM, "elevation of the site above sea level, metres, [-500, 9000] (default: the scene's, else 0)")
      ->group(group);
  sub.add_option("--north", northAngleDeg,
                 "angle from the model's -Z axis to north, degrees clockwise seen from above, [-360, 360] "
                 "(default: the scene's, else 0: north along -Z)")
      ->group(group);
  sub.add_option("--tz", timeZone,
                 "time zone of the site: IANA name (Europe/Helsinki, daylight saving applied) or offset +03:00 "
                 "(default: the scene's, else the zone --time carries)")
      ->group(group);
  sub.add_option("--sky", sky,
                 "sky model: clear (Hosek-Wilkie sky and sun), preetham (Preetham distribution and colour at the IES "
                 "Handbook level, with the clear-atmosphere sun), "
                 "cie:N (CIE standard general sky type N = 1..15 at the IES Handbook level; 1-5 overcast "
                 "without the sun, 6-15 with it) or perez (Perez all-weather sky and sun from --weather); "
                 "default: the scene's, else clear")
      ->group(group);
  sub.add_option("--turbidity", turbidity,
                 "Linke turbidity of the clear sky and the sun, [1.7, 10] (default: the scene's, else 3: clear)")
      ->group(group);
  sub.add_option("--ground-albedo", groundAlbedo,
                 "reflectance of the ground around the site, [0, 1]: the clear sky's and the ground drawn below the "
                 "horizon (default: the scene's, else 0.2)")
      ->group(group);
  sub.add_option("--weather", weatherFile, "EnergyPlus weather file (.epw) for --sky perez")->group(group);
  sub.add_option("--sun-dir", sunDirection,
                 "the sun placed directly instead of by site and time: AZIMUTH,ELEVATION in degrees (azimuth "
                 "clockwise from north, [0, 360); apparent elevation, [-90, 90]), e.g. 135,45")
      ->type_name("AZ,EL")
      ->group(group);
}

std::vector<std::string> DaylightOptions::given() const {
  std::vector<std::string> names;
  if (latitudeDeg) names.push_back("--lat");
  if (longitudeDeg) names.push_back("--lon");
  if (elevationM) names.push_back("--elevation");
  if (northAngleDeg) names.push_back("--north");
  if (!time.empty()) names.push_back("--time");
  if (!timeZone.empty()) names.push_back("--tz");
  if (!sky.empty()) names.push_back("--sky");
  if (turbidity) names.push_back("--turbidity");
  if (groundAlbedo) names.push_back("--ground-albedo");
  if (!weatherFile.empty()) names.push_back("--weather");
  if (!sunDirection.empty()) names.push_back("--sun-dir");
  return names;
}

std::string localIso(const sunsky::UtcTime& utc, double utcOffsetHours) {
  const sunsky::UtcTime l = sunsky::addHours(utc, utcOffsetHours);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d", l.year, l.month, l.day, l.hour, l.minute,
                int(std::floor(l.second)));
  return buf;
}

SiteTime resolveSiteTime(const SiteTimeOptions& o) {
  SiteTime st;
  std::string time = o.time;
  st.timeZone = o.timeZone;
  if (!o.scene.empty()) {
    const sdb::Scene scene = sdb::loadScene(o.scene);
    if (scene.hasSite()) {
      st.spa.latitudeDeg = scene.site().latitudeDeg;
      st.spa.longitudeDeg = scene.site().longitudeDeg;
      st.spa.elevationM = scene.site().elevationM;
      if (st.timeZone.empty()) st.timeZone = scene.site().timeZone;
      st.north = rdb::northReference(scene.site());
    } else if (!o.latitudeDeg || !o.longitudeDeg) {
      throw UsageError("scene " + o.scene + " has no site; give --lat and --lon");
    }
    if (time.empty()) time = scene.time().localDateTime;
    st.sceneSky = scene.sky();
  } else if (!o.latitudeDeg || !o.longitudeDeg) {
    throw UsageError("give --lat and --lon (or --scene with a site)");
  }
  if (o.latitudeDeg) st.spa.latitudeDeg = *o.latitudeDeg;
  if (o.longitudeDeg) st.spa.longitudeDeg = *o.longitudeDeg;
  if (o.elevationM) st.spa.elevationM = *o.elevationM;
  if (time.empty()) throw UsageError("give --time (or --scene with a time)");
  st.spa.utc = sunsky::parseTime(time, st.timeZone, "--time");
  // A time that carries its own zone ("…Z", "…+03:00") is shown in that zone when no --tz is given.
  if (st.timeZone.empty()) st.timeZone = sunsky::zoneOfTime(time);
  if (o.deltaTSeconds) st.spa.deltaTSeconds = *o.deltaTSeconds;
  st.spa.dut1Seconds = o.dut1Seconds;
  if (o.pressureHpa) st.spa.pressureHpa = *o.pressureHpa;
  if (o.temperatureC) st.spa.temperatureC = *o.temperatureC;
  st.utcOffsetHours = sunsky::utcOffsetHours(st.timeZone, st.spa.utc);
  st.localIso = localIso(st.spa.utc, st.utcOffsetHours);
  return st;
}

}  // namespace fly::cli
