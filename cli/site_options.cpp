#include "cli/site_options.h"

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
