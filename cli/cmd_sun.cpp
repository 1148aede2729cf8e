// `fly sun`: the sun's position, sunrise/transit/sunset and daylight illuminance for a site and time, and the
// sun-path diagram of the site.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "base/error.h"
#include "cli/command.h"
#include "cli/daylight.h"
#include "cli/image_metadata.h"
#include "cli/site_options.h"
#include "cli/sun_path_diagram.h"

namespace fly::cli {

namespace {

struct SunOptions {
  SiteTimeOptions site;
  double turbidity = 3.0;
  bool json = false;
  bool path = false;
  std::string out;
  int sizePx = 1200;
  double dotsPerInch = 0.0;
  bool turbidityGiven = false;  // --turbidity on the command line (else a scene's is the default)
};

std::string fixed(double v, int decimals) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << v;
  return s.str();
}

// "06:12:43" local clock time of a UTC instant.
std::string clock(const sunsky::UtcTime& utc, double offsetHours) {
  return localIso(utc, offsetHours).substr(11);
}

int runSun(const SunOptions& o) {
  const SiteTime st = resolveSiteTime(o.site);
  const double turbidity = st.sceneSky && !o.turbidityGiven ? st.sceneSky->turbidity : o.turbidity;
  if (o.path && o.out.empty()) throw UsageError("--path needs --out FILE.png");
  if (!o.path && !o.out.empty()) throw UsageError("--out is for the sun-path diagram; add --path");
  const sunsky::SunPosition sun = sunsky::sunPosition(st.spa);
  const sunsky::SunTimes times = sunsky::sunTimes(st.spa, st.utcOffsetHours);
  const ClearDaylight light = clearDaylight(st, sun, turbidity);
  // With a scene: where the sun is in the model's world frame (north angle and map grid applied).
  std::optional<sunsky::SiteFrame> frame;
  std::optional<dvec3> sunWorld;
  if (st.north) {
    frame = sunsky::makeSiteFrame(st.spa.latitudeDeg, st.spa.longitudeDeg, *st.north);
    sunWorld = frame->worldFromEnu(
        sunsky::directionFromAzimuthElevation(sun.azimuthDeg, sun.apparentElevationDeg()));
  }

  if (o.path) {
    char where[96];
    std::snprintf(where, sizeof where, "latitude %.4f°, longitude %.4f°, elevation %.0f m, time zone ",
                  st.spa.latitudeDeg, st.spa.longitudeDeg, st.spa.elevationM);
    const ImageSettings settings = {{"fly:site", where + st.timeZone}, {"fly:time", st.localIso}};
    drawSunPath({.spa = st.spa,
                 .timeZone = st.timeZone,
                 .sizePx = o.sizePx,
                 .metadata = imageMetadata("Sun path", settings, o.dotsPerInch)},
                o.out);
  }

  const char* polar = times.kind == sunsky::SunTimes::Kind::kPolarDay     ? "polar day"
                      : times.kind == sunsky::SunTimes::Kind::kPolarNight ? "polar night"
                                                                          : nullptr;
  if (o.json) {
    nlohmann::json j;
    j["latitude_deg"] = st.spa.latitudeDeg;
    j["longitude_deg"] = st.spa.longitudeDeg;
    j["elevation_m"] = st.spa.elevationM;
    j["time_utc"] = st.spa.utc.iso();
    j["time_local"] = st.localIso;
    j["time_zone"] = st.timeZone;
    j["utc_offset_h"] = st.utcOffsetHours;
    j["true_zenith_deg"] = sun.trueZenithDeg;
    j["apparent_zenith_deg"] = sun.apparentZenithDeg;
    j["true_elevation_deg"] = sun.trueElevationDeg();
    j["apparent_elevation_deg"] = sun.apparentElevationDeg();
    j["azimuth_deg"] = sun.azimuthDeg;
    j["declination_deg"] = sun.declinationDeg;
    j["equation_of_time_min"] = sun.equationOfTimeMinutes;
    j["transit_local"] = localIso(times.transit, st.utcOffsetHours);
    j["sunrise_local"] =
        polar ? nlohmann::json(nullptr) : nlohmann::json(localIso(times.sunrise, st.utcOffsetHours));
    j["sunset_local"] =
        polar ? nlohmann::json(nullptr) : nlohmann::json(localIso(times.sunset, st.utcOffsetHours));
    j["polar"] = polar ? nlohmann::json(polar) : nlohmann::json(nullptr);
    j["turbidity"] = turbidity;
    j["direct_normal_illuminance_lux"] = light.directNormalLux;
    j["direct_horizontal_illuminance_lux"] = light.directHorizontalLux;
    j["diffuse_horizontal_illuminance_lux"] = light.diffuseHorizontalLux;
    j["global_horizontal_illuminance_lux"] = light.directHorizontalLux + light.diffuseHorizontalLux;
    if (o.path) j["sun_path_png"] = o.out;
    if (sunWorld) {
      j["sun_direction_world"] = {sunWorld->x, sunWorld->y, sunWorld->z};
      j["meridian_convergence_deg"] = frame->meridianConvergenceDeg();
      j["true_north_from_minus_z_deg"] = frame->trueNorthFromWorldMinusZDeg();
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream t;
  t << "site         " << fixed(std::abs(st.spa.latitudeDeg), 4) << "° "
    << (st.spa.latitudeDeg >= 0 ? "N" : "S") << ", " << fixed(std::abs(st.spa.longitudeDeg), 4) << "° "
    << (st.spa.longitudeDeg >= 0 ? "E" : "W") << ", " << fixed(st.spa.elevationM, 0) << " m\n";
  t << "time         " << st.localIso << " " << st.timeZone << " (UTC" << (st.utcOffsetHours >= 0 ? "+" : "")
    << fixed(st.utcOffsetHours, 2) << " h) = " << st.spa.utc.iso() << "\n";
  t << "zenith       " << fixed(sun.trueZenithDeg, 4) << "° true, " << fixed(sun.apparentZenithDeg, 4)
    << "° apparent (refracted)\n";
  t << "elevation    " << fixed(sun.trueElevationDeg(), 4) << "° true, "
    << fixed(sun.apparentElevationDeg(), 4) << "° apparent\n";
  t << "azimuth      " << fixed(sun.azimuthDeg, 4) << "° (clockwise from north)\n";
  t << "declination  " << fixed(sun.declinationDeg, 4) << "°, equation of time "
    << fixed(sun.equationOfTimeMinutes, 2) << " min\n";
  if (polar) {
    t << "sun times    " << polar << ", transit " << clock(times.transit, st.utcOffsetHours) << "\n";
  } else {
    t << "sun times    sunrise " << clock(times.sunrise, st.utcOffsetHours) << ", transit "
      << clock(times.transit, st.utcOffsetHours) << ", sunset " << clock(times.sunset, st.utcOffsetHours)
      << " (local)\n";
  }
  t << "daylight     clear sky, turbidity " << fixed(turbidity, 1) << ": direct normal "
    << fixed(light.directNormalLux, 0) << " lx, direct horizontal " << fixed(light.directHorizontalLux, 0)
    << " lx, diffuse horizontal " << fixed(light.diffuseHorizontalLux, 0) << " lx, global horizontal "
    << fixed(light.directHorizontalLux + light.diffuseHorizontalLux, 0) << " lx\n";
  if (sunWorld) {
    t << "in the model toward the sun (" << fixed(sunWorld->x, 4) << ", " << fixed(sunWorld->y, 4) << ", "
      << fixed(sunWorld->z, 4) << ") world; true north " << fixed(frame->trueNorthFromWorldMinusZDeg(), 3)
      << "° clockwise from -Z (meridian convergence " << fixed(frame->meridianConvergenceDeg(), 3) << "°)\n";
  }
  if (o.path) t << "sun path     " << o.out << "\n";
  std::cout << t.str();
  return 0;
}

}  // namespace

Command addSunCommand(CLI::App& app) {
  auto o = std::make_shared<SunOptions>();
  CLI::App* sub = app.add_subcommand("sun",
                                     "The sun's position (NREL SPA), sunrise/transit/sunset and clear-sky "
                                     "illuminance (lux) at a site and time");
  o->site.add(*sub);
  sub->add_option("--turbidity", o->turbidity, "Linke turbidity of the clear sky, [1.7, 10]")
      ->capture_default_str();
  sub->add_flag("--json", o->json, "print one JSON object instead of text");
  sub->add_flag("--path", o->path, "draw the site's sun-path diagram into --out (PNG)");
  sub->add_option("--out", o->out, "sun-path diagram file (.png), with --path");
  addDpiOption(*sub, &o->dotsPerInch);
  sub->add_option("--size", o->sizePx, "sun-path diagram size, pixels, [300, 8000]")
      ->capture_default_str()
      ->check(CLI::Range(300, 8000));
  return {sub, [o, sub] {
            o->turbidityGiven = sub->count("--turbidity") > 0;
            return runSun(*o);
          }};
}

}  // namespace fly::cli
