#include "cli/scene_daylight.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "base/error.h"
#include "base/file_io.h"
#include "rdb/site_lowering.h"
#include "sdb/scene_load.h"
#include "sdb/scene_stats.h"
#include "sunsky/civil_time.h"

namespace fly::cli {

namespace {

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

void checkRange(const std::optional<double>& v, const char* name, double lo, double hi, const char* unit) {
  if (v && !(*v >= lo && *v <= hi)) {
    throw UsageError(std::string(name) + " " + format("%g", *v) + ": expected " + unit + " in [" +
                     format("%g", lo) + ", " + format("%g", hi) + "]");
  }
}

// A finite number that fills `text` entirely.
std::optional<double> parseNumber(const std::string& text) {
  double v = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (ec != std::errc() || ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

// --sun-dir AZIMUTH,ELEVATION in degrees.
std::optional<sdb::SunDirection> parseSunDirection(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const size_t comma = text.find(',');
  const std::optional<double> az = comma == std::string::npos ? std::nullopt : parseNumber(text.substr(0, comma));
  const std::optional<double> el = comma == std::string::npos ? std::nullopt : parseNumber(text.substr(comma + 1));
  if (!az || !el) {
    throw UsageError("--sun-dir " + text +
                     ": expected AZIMUTH,ELEVATION in degrees, e.g. 135,45 (azimuth clockwise from north, "
                     "elevation above the horizon)");
  }
  if (!(*az >= 0.0 && *az < 360.0)) {
    throw UsageError("--sun-dir " + text + ": the azimuth must be in [0, 360) degrees, clockwise from north");
  }
  if (!(*el >= -90.0 && *el <= 90.0)) {
    throw UsageError("--sun-dir " + text + ": the elevation must be in [-90, 90] degrees above the horizon");
  }
  return sdb::SunDirection{*az, *el};
}

// --sky: clear, preetham, perez or cie:N. Sets the model, the CIE type, and the sun: clear and Perez skies have it,
// CIE skies of types 6–15 (those with the sun visible) too, the overcast types 1–5 not.
void parseSky(const std::string& text, sdb::SkySettings& sky) {
  if (text == "clear" || text == "preetham") {
    sky.model = text == "clear" ? sdb::SkyModel::kClear : sdb::SkyModel::kPreetham;
    sky.sun = true;
    return;
  }
  if (text == "perez") {
    sky.model = sdb::SkyModel::kPerez;
    sky.sun = true;
    return;
  }
  if (text.rfind("cie:", 0) == 0) {
    const std::optional<double> n = parseNumber(text.substr(4));
    if (n && *n >= 1 && *n <= 15 && *n == std::floor(*n)) {
      sky.model = sdb::SkyModel::kCie;
      sky.cieType = int(*n);
      sky.sun = sky.cieType >= 6;
      return;
    }
    throw UsageError("--sky " + text + ": the CIE standard sky type must be 1..15 (e.g. cie:1 overcast, cie:12 clear)");
  }
  throw UsageError("--sky " + text + ": expected clear, preetham, perez or cie:N (N = 1..15)");
}

// Validates a time against a zone: the sunsky parser's message, as a usage error naming the option.
void checkTime(const std::string& time, const std::string& zone, const char* what) {
  try {
    sunsky::parseTime(time, zone, what);
  } catch (const InputError& e) {
    throw UsageError(e.what());
  }
}

// Lights, or materials that emit light in physical units (KHR_materials_emissive_strength, or a scene file's
// emission in cd/m²): a model that declares its own light gets no daylight added, however dim, and auto
// exposure shows it by that light. Emission without the extension is a display colour (sdb::Material::
// emissionDisplay), no light source.
bool hasLightSources(const sdb::Scene& scene) {
  if (!scene.lights().empty()) return true;
  for (const auto& [id, mesh] : scene.meshes()) {
    if (scene.material(mesh.material).isEmissive()) return true;
  }
  return false;
}

std::string degrees(double v) { return format("%.1f°", v); }

// "south-east" for an azimuth in degrees clockwise from north.
std::string compassPoint(double azimuthDeg) {
  static const char* kPoints[8] = {"north", "north-east", "east", "south-east",
                                   "south", "south-west", "west", "north-west"};
  const double a = std::fmod(std::fmod(azimuthDeg, 360.0) + 360.0, 360.0);
  return kPoints[int(std::lround(a / 45.0)) % 8];
}

}  // namespace

bool isPlainModel(const std::filesystem::path& scenePath) {
  std::string ext = scenePath.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".gltf" || ext == ".glb";
}

bool applyDaylightOptions(sdb::Scene& scene, const DaylightOptions& o, bool plainModel) {
  checkRange(o.latitudeDeg, "--lat", -90.0, 90.0, "degrees north");
  checkRange(o.longitudeDeg, "--lon", -180.0, 180.0, "degrees east");
  checkRange(o.elevationM, "--elevation", -500.0, 9000.0, "metres above sea level");
  checkRange(o.northAngleDeg, "--north", -360.0, 360.0, "degrees");
  checkRange(o.turbidity, "--turbidity", 1.7, 10.0, "a Linke turbidity");
  checkRange(o.groundAlbedo, "--ground-albedo", 0.0, 1.0, "a reflectance");
  const std::optional<sdb::SunDirection> sunDirection = parseSunDirection(o.sunDirection);
  const std::vector<std::string> given = o.given();
  const auto isGiven = [&](const char* name) { return std::find(given.begin(), given.end(), name) != given.end(); };

  // A sun placed directly excludes the options that place it by the site and time.
  if (sunDirection) {
    for (const char* name : {"--lat", "--lon", "--time", "--tz"}) {
      if (isGiven(name)) {
        throw UsageError(std::string("--sun-dir places the sun directly and ") + name +
                         " places it by the site and time: give either --sun-dir AZIMUTH,ELEVATION or the "
                         "site and time (--lat, --lon, --time, --tz), not both");
      }
    }
  }
  const std::string where = plainModel ? scene.sourcePath.filename().string() + " is a glTF model without a site"
                                       : "the scene " + scene.sourcePath.string() + " has no \"site\"";
  if (!scene.hasSite() && o.latitudeDeg.has_value() != o.longitudeDeg.has_value()) {
    throw UsageError(std::string(o.latitudeDeg ? "--lat" : "--lon") +
                     " places the model on Earth together with " + (o.latitudeDeg ? "--lon" : "--lat") +
                     " (" + where + "): give both");
  }
  const bool hasSite = scene.hasSite() || (o.latitudeDeg && o.longitudeDeg);
  if (!hasSite) {
    for (const char* name : {"--elevation", "--north", "--time", "--tz"}) {
      if (isGiven(name)) {
        throw UsageError(std::string(name) + " needs a site (" + where + "): give --lat and --lon too" +
                         (std::string(name) == "--north" || std::string(name) == "--elevation"
                              ? ", or place the sun directly with --sun-dir AZIMUTH,ELEVATION"
                              : ""));
      }
    }
  }

  sdb::SkySettings sky = scene.sky();
  const bool hadDaylight = sky.model != sdb::SkyModel::kNone || sky.sun;
  if (!o.sky.empty()) parseSky(o.sky, sky);
  if (o.turbidity) sky.turbidity = *o.turbidity;
  if (o.groundAlbedo) sky.groundAlbedo = *o.groundAlbedo;
  if (!o.weatherFile.empty()) {
    if (sky.model != sdb::SkyModel::kPerez) {
      throw UsageError("--weather " + o.weatherFile + " drives the Perez sky: give --sky perez too");
    }
    checkInputFile(o.weatherFile, "weather file");
    sky.weatherFile = o.weatherFile;
  }
  if (sky.model == sdb::SkyModel::kPerez && sky.weatherFile.empty()) {
    throw UsageError("--sky perez takes its light from a weather file: give --weather FILE.epw");
  }
  if (!given.empty() && !hadDaylight && o.sky.empty()) {  // daylight asked for: the clear sky with the sun
    sky.model = sdb::SkyModel::kClear;
    sky.sun = true;
  }

  sdb::Site site = scene.site();
  if (o.latitudeDeg) site.latitudeDeg = *o.latitudeDeg;
  if (o.longitudeDeg) site.longitudeDeg = *o.longitudeDeg;
  if (o.elevationM) site.elevationM = *o.elevationM;
  if (o.northAngleDeg) site.northAngleDeg = *o.northAngleDeg;
  if (!o.timeZone.empty()) site.timeZone = o.timeZone;

  sdb::SiteTime time = scene.time();
  if (sunDirection) {
    time = sdb::SiteTime{"", sunDirection};
  } else if (!o.time.empty()) {
    if (o.timeZone.empty() && !scene.hasSite()) {
      site.timeZone = sunsky::zoneOfTime(o.time);
      if (site.timeZone.empty()) {
        throw UsageError("--time " + o.time +
                         " is a local time and the site has no time zone: give --tz (an IANA zone such as "
                         "Europe/Helsinki, or an offset such as +03:00), or the time in UTC (e.g. " +
                         o.time.substr(0, 16) + "Z)");
      }
    }
    checkTime(o.time, site.timeZone, "--time");
    time = sdb::SiteTime{o.time, std::nullopt};
  } else if (!o.timeZone.empty() && !time.localDateTime.empty()) {
    checkTime(time.localDateTime, site.timeZone, "--tz");
  } else if (!o.timeZone.empty()) {
    checkTime("2000-01-01T12:00", site.timeZone, "--tz");
  }

  bool defaultDaylight = false;
  if (given.empty() && plainModel && !hadDaylight && !hasLightSources(scene)) {
    sky = sdb::SkySettings{};
    sky.model = sdb::SkyModel::kClear;
    sky.turbidity = kDefaultTurbidity;
    sky.sun = true;
    defaultDaylight = true;
  }
  const bool wantsDaylight = sky.model != sdb::SkyModel::kNone || sky.sun;
  if (wantsDaylight && time.localDateTime.empty() && !time.sunDirection) {
    if (hasSite) {
      throw UsageError("the daylight needs the site's date and time: give --time (e.g. 2026-06-21T12:00), or "
                       "place the sun directly with --sun-dir AZIMUTH,ELEVATION");
    }
    time.sunDirection = sdb::SunDirection{kDefaultSunAzimuthDeg, kDefaultSunElevationDeg};
  }
  if (time.sunDirection && sky.model == sdb::SkyModel::kPerez) {
    throw UsageError(std::string(sunDirection ? "--sun-dir" : "the Perez sky") +
                     ": a Perez sky takes its light from the weather file's record at a time; give --time "
                     "and a site (--lat, --lon), or another --sky");
  }

  if (hasSite) scene.setSite(site);
  scene.setTime(time);
  scene.setSky(sky);
  return defaultDaylight;
}

std::string describeLight(const sdb::Scene& scene, bool defaultDaylight) {
  const sdb::SceneStats stats = sdb::computeStats(scene);
  std::string lights;
  if (stats.lights > 0) lights = std::to_string(stats.lights) + (stats.lights > 1 ? " lights" : " light");
  if (stats.emissiveMeshes > 0) {
    lights += (lights.empty() ? "" : ", ") + std::to_string(stats.emissiveMeshes) +
              (stats.emissiveMeshes > 1 ? " emissive meshes" : " emissive mesh");
  }
  const std::optional<rdb::SceneDaylight> d = rdb::lowerDaylight(scene);
  if (!d) {
    return lights.empty() ? "none: no lights, no emissive materials and no daylight (give --lat --lon --time, or "
                            "--sun-dir AZIMUTH,ELEVATION, to add daylight)"
                          : lights;
  }
  const sdb::SkySettings& sky = scene.sky();
  std::string text;
  switch (sky.model) {
    case sdb::SkyModel::kNone: text = "no sky"; break;
    case sdb::SkyModel::kClear:
      text = "clear sky (Hosek-Wilkie), turbidity " + format("%.1f", sky.turbidity) +
             (sky.groundAlbedo != 0.2 ? ", ground albedo " + format("%.2f", sky.groundAlbedo) : "");
      break;
    case sdb::SkyModel::kPreetham:
      text = "clear sky (Preetham, IES Handbook level), turbidity " + format("%.1f", sky.turbidity);
      break;
    case sdb::SkyModel::kCie: text = "CIE standard sky type " + std::to_string(sky.cieType); break;
    case sdb::SkyModel::kPerez:
      text = "Perez sky from " + std::filesystem::path(sky.weatherFile).filename().string();
      break;
  }
  const sunsky::SunPosition& p = d->sunPosition;
  const std::optional<sdb::SunDirection>& direct = scene.time().sunDirection;
  if (!sky.sun) {
    text += ", no sun";
  } else {
    text += std::string(", sun ") + (direct ? "placed " : "") +
            (p.apparentElevationDeg() > 0.0 ? "at " : "below the horizon, at ") +
            degrees(p.apparentElevationDeg()) + " elevation, azimuth " + degrees(p.azimuthDeg) + " (" +
            compassPoint(p.azimuthDeg) + ")";
  }
  if (!direct) {
    const sdb::Site& s = scene.site();
    text += "; site " + format("%.4f°", std::abs(s.latitudeDeg)) + (s.latitudeDeg >= 0 ? " N, " : " S, ") +
            format("%.4f°", std::abs(s.longitudeDeg)) + (s.longitudeDeg >= 0 ? " E" : " W") + ", " +
            scene.time().localDateTime + " " + s.timeZone;
  }
  if (scene.site().northAngleDeg != 0.0 || !direct) {
    text += ", north " + degrees(scene.site().northAngleDeg) + " from -Z";
  } else {
    text += ", north along -Z";
  }
  const double sunLux = d->sun ? double(luminance(d->sun->normalIlluminanceLux)) * std::max(0.0, d->sun->dirEnu.z)
                               : 0.0;
  const double skyLux = d->sky ? sunsky::horizontalIlluminanceLux(*d->sky) : 0.0;
  text += "; global horizontal " + format("%.0f", sunLux + skyLux) + " lx (sun " + format("%.0f", sunLux) +
          ", sky " + format("%.0f", skyLux) + ")";
  if (defaultDaylight) {
    return "default daylight (no lights in " + scene.sourcePath.filename().string() + "): " + text +
           "; give --lat --lon --time (or --sun-dir AZIMUTH,ELEVATION) to set the sun";
  }
  return (lights.empty() ? "" : lights + " and ") + "daylight: " + text;
}

LitScene loadLitScene(const std::filesystem::path& scenePath, const DaylightOptions& options,
                      const nlohmann::json& baked, const std::string& bakedFile) {
  LitScene r;
  r.scene = sdb::loadScene(scenePath);
  const bool bakedDefault = !baked.is_null() && applyDaylightJson(r.scene, baked, bakedFile);
  r.defaultDaylight = applyDaylightOptions(r.scene, options, isPlainModel(scenePath));
  if (bakedDefault && options.given().empty()) r.defaultDaylight = true;
  r.light = describeLight(r.scene, r.defaultDaylight);
  return r;
}

namespace {

// "+03:00" for a UTC offset in hours.
std::string offsetText(double hours) {
  const int minutes = int(std::lround(hours * 60.0));  // |offset| ≤ 26 h
  char b[32];
  std::snprintf(b, sizeof b, "%c%02d:%02d", minutes < 0 ? '-' : '+', std::abs(minutes) / 60,
                std::abs(minutes) % 60);
  return b;
}

}  // namespace

std::string sceneLocalTime(const sdb::Scene& scene, double addHours) {
  const sdb::Site& site = scene.site();
  const sunsky::UtcTime utc = sunsky::addHours(
      sunsky::parseTime(scene.time().localDateTime, site.timeZone, "the scene's time"), addHours);
  const double offsetH = sunsky::utcOffsetHours(site.timeZone, utc);
  std::string local = sunsky::addHours(utc, offsetH).iso();
  local.pop_back();  // the "Z"
  return local + offsetText(offsetH);
}

nlohmann::json daylightJson(const sdb::Scene& scene, bool defaultDaylight) {
  nlohmann::json j;
  j["default"] = defaultDaylight;
  if (scene.hasSite()) {
    const sdb::Site& s = scene.site();
    j["site"] = {{"latitude_deg", s.latitudeDeg},
                 {"longitude_deg", s.longitudeDeg},
                 {"elevation_m", s.elevationM},
                 {"time_zone", s.timeZone},
                 {"north_angle_deg", s.northAngleDeg}};
  } else {
    j["site"] = nullptr;
  }
  j["time"] = scene.time().localDateTime.empty() ? nlohmann::json(nullptr) : nlohmann::json(scene.time().localDateTime);
  if (const std::optional<sdb::SunDirection>& d = scene.time().sunDirection) {
    j["sun_direction"] = {{"azimuth_deg", d->azimuthDeg}, {"elevation_deg", d->elevationDeg}};
  } else {
    j["sun_direction"] = nullptr;
  }
  const sdb::SkySettings& sky = scene.sky();
  j["sky"] = {{"model", sdb::skyModelName(sky.model)},
              {"cie_type", sky.cieType},
              {"turbidity", sky.turbidity},
              {"weather_file", sky.weatherFile},
              {"sun", sky.sun},
              {"ground_albedo", sky.groundAlbedo}};
  return j;
}

bool applyDaylightJson(sdb::Scene& scene, const nlohmann::json& j, const std::string& file) {
  try {
    if (!j.at("site").is_null()) {
      const nlohmann::json& s = j.at("site");
      sdb::Site site = scene.site();
      site.latitudeDeg = s.at("latitude_deg").get<double>();
      site.longitudeDeg = s.at("longitude_deg").get<double>();
      site.elevationM = s.at("elevation_m").get<double>();
      site.timeZone = s.at("time_zone").get<std::string>();
      site.northAngleDeg = s.at("north_angle_deg").get<double>();
      scene.setSite(site);
    }
    sdb::SiteTime time;
    if (!j.at("time").is_null()) time.localDateTime = j.at("time").get<std::string>();
    if (!j.at("sun_direction").is_null()) {
      time.sunDirection = sdb::SunDirection{j.at("sun_direction").at("azimuth_deg").get<double>(),
                                            j.at("sun_direction").at("elevation_deg").get<double>()};
    }
    scene.setTime(time);
    const nlohmann::json& s = j.at("sky");
    sdb::SkySettings sky;
    const std::string model = s.at("model").get<std::string>();
    bool known = false;
    for (sdb::SkyModel m : {sdb::SkyModel::kNone, sdb::SkyModel::kCie, sdb::SkyModel::kPerez, sdb::SkyModel::kClear,
                          sdb::SkyModel::kPreetham}) {
      if (model == sdb::skyModelName(m)) {
        sky.model = m;
        known = true;
      }
    }
    if (!known) throw std::invalid_argument("unknown sky model \"" + model + "\"");
    sky.cieType = s.at("cie_type").get<int>();
    sky.turbidity = s.at("turbidity").get<double>();
    sky.weatherFile = s.at("weather_file").get<std::string>();
    sky.sun = s.at("sun").get<bool>();
    sky.groundAlbedo = s.value("ground_albedo", sky.groundAlbedo);  // bakes that predate it: the default
    scene.setSky(sky);
    return j.at("default").get<bool>();
  } catch (const std::exception& e) {
    throw InputError({file, 0, 0, "/daylight"}, std::string("the recorded daylight is malformed (") + e.what() + ")",
                     "bake the scene again with this fly");
  }
}

}  // namespace fly::cli
