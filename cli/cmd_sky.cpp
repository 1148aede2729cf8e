// `fly sky`: the sky dome of a site and time as a hemispherical fisheye image (physical values in EXR,
// tone-mapped PNG), from a CIE standard sky, the Perez all-weather sky (weather file or given irradiances) or
// the clear sky with colour.
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "base/error.h"
#include "base/tone_map.h"
#include "cli/command.h"
#include "cli/daylight.h"
#include "cli/image_metadata.h"
#include "cli/sky_image.h"
#include "sunsky/epw.h"

namespace fly::cli {

namespace {

struct SkyOptions {
  SiteTimeOptions site;
  SkyRequest request;
  std::string weather;
  std::string out;
  int sizePx = 512;
  double dotsPerInch = 0.0;
  std::optional<double> exposureEv100;
  bool json = false;
  bool skyGiven = false;        // --sky on the command line (else a scene's sky is the default)
  bool turbidityGiven = false;  // --turbidity on the command line
  bool groundAlbedoGiven = false;
};

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// "+02:00" for a whole or fractional number of hours.
std::string offsetZone(double hours) {
  const int minutes = int(std::lround(std::abs(hours) * 60.0));
  char buf[16];
  std::snprintf(buf, sizeof buf, "%c%02d:%02d", hours < 0 ? '-' : '+', minutes / 60, minutes % 60);
  return buf;
}

int runSky(SkyOptions o) {
  const std::string ext = lowerExtension(o.out);
  if (ext != ".exr" && ext != ".png") {
    throw UsageError("--out " + o.out + ": give a .exr (physical values, cd/m²) or .png (tone-mapped) file");
  }
  std::optional<sunsky::EpwFile> epw;
  if (!o.weather.empty()) {
    epw = sunsky::loadEpw(o.weather);
    // The weather file's site and standard-time zone are the defaults.
    if (!o.site.latitudeDeg && o.site.scene.empty()) o.site.latitudeDeg = epw->location.latitudeDeg;
    if (!o.site.longitudeDeg && o.site.scene.empty()) o.site.longitudeDeg = epw->location.longitudeDeg;
    if (!o.site.elevationM && o.site.scene.empty()) o.site.elevationM = epw->location.elevationM;
    if (o.site.timeZone.empty() && o.site.scene.empty())
      o.site.timeZone = offsetZone(epw->location.timeZoneHours);
    o.request.weather = &*epw;
  }
  SiteTime st = resolveSiteTime(o.site);
  // A scene's sky is the default: its model, CIE type, turbidity and weather file.
  if (st.sceneSky && !o.skyGiven && st.sceneSky->model != sdb::SkyModel::kNone) {
    const sdb::SkySettings& sky = *st.sceneSky;
    o.request.model = sky.model == sdb::SkyModel::kCie     ? "cie:" + std::to_string(sky.cieType)
                      : sky.model == sdb::SkyModel::kPerez    ? "perez"
                      : sky.model == sdb::SkyModel::kPreetham ? "preetham"
                                                              : "clear";
    if (!sky.weatherFile.empty() && !epw) {
      epw = sunsky::loadEpw(sky.weatherFile);
      o.request.weather = &*epw;
    }
  }
  if (st.sceneSky && !o.turbidityGiven) o.request.turbidity = st.sceneSky->turbidity;
  if (st.sceneSky && !o.groundAlbedoGiven) o.request.groundAlbedo = st.sceneSky->groundAlbedo;
  const sunsky::SunPosition sun = sunsky::sunPosition(st.spa);
  const Daylight day = makeDaylight(o.request, st, sun);
  const ImageRgbF image = renderSkyFisheye(*day.sky, day.sun, o.sizePx);

  const double diffuseLux = sunsky::horizontalIlluminanceLux(*day.sky);
  const double directNormalLux = day.sun ? luminance(day.sun->normalIlluminanceLux) : 0.0;
  const double directHorizontalLux = day.sun ? std::max(0.0, directNormalLux * day.sun->dirEnu.z) : 0.0;
  double ev100 = 0.0;
  ImageSettings settings = {
      {"fly:projection",
       "equidistant fisheye looking up: zenith at the centre, horizon on the circle, north up, east left"},
      {"fly:sky", day.description},
      {"fly:site", std::to_string(st.spa.latitudeDeg) + " N, " + std::to_string(st.spa.longitudeDeg) +
                       " E, " + std::to_string(st.spa.elevationM) + " m"},
      {"fly:time", st.localIso + " " + st.timeZone + " = " + st.spa.utc.iso()}};
  if (ext == ".exr") {
    ExrAttributes attributes = exrAttributes(imageMetadata("Sky", settings, o.dotsPerInch));
    attributes.emplace_back("units",
                            "cd/m^2 (linear Rec.709 RGB, luminance Y = 0.2126 R + 0.7152 G + 0.0722 B)");
    writeExr(o.out, image, attributes);
  } else {
    std::vector<float> lum;
    lum.reserve(image.rgb.size() / 3);
    for (size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
      lum.push_back(luminance(Rgb(image.rgb[i], image.rgb[i + 1], image.rgb[i + 2])));
    }
    ev100 = o.exposureEv100 ? *o.exposureEv100 : autoExposureEv100(lum);
    const std::vector<uint8_t> px = toneMapToSrgb8(image.rgb, ev100, ToneOperator::kReinhard);
    settings.emplace_back("fly:exposure", "EV100 " + std::to_string(ev100) + ", Reinhard tone mapping, sRGB");
    writePng(o.out, image.width, image.height, 3, px.data(), imageMetadata("Sky", settings, o.dotsPerInch));
  }

  if (o.json) {
    nlohmann::json j;
    j["sky"] = day.description;
    j["time_local"] = st.localIso;
    j["time_zone"] = st.timeZone;
    j["time_utc"] = st.spa.utc.iso();
    j["sun_apparent_zenith_deg"] = sun.apparentZenithDeg;
    j["sun_azimuth_deg"] = sun.azimuthDeg;
    j["diffuse_horizontal_illuminance_lux"] = diffuseLux;
    j["direct_normal_illuminance_lux"] = directNormalLux;
    j["global_horizontal_illuminance_lux"] = diffuseLux + directHorizontalLux;
    j["zenith_luminance_cd_m2"] = sunsky::zenithLuminanceCdM2(*day.sky);
    j["out"] = o.out;
    if (ext == ".png") j["exposure_ev100"] = ev100;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream t;
  t.setf(std::ios::fixed);
  t.precision(0);
  t << "sky          " << day.description << "\n";
  t << "time         " << st.localIso << " " << st.timeZone << " = " << st.spa.utc.iso() << "\n";
  t.precision(2);
  t << "sun          apparent zenith " << sun.apparentZenithDeg << "°, azimuth " << sun.azimuthDeg << "°\n";
  t.precision(0);
  t << "illuminance  diffuse horizontal " << diffuseLux << " lx, direct normal " << directNormalLux
    << " lx, global horizontal " << diffuseLux + directHorizontalLux << " lx\n";
  t << "zenith       " << sunsky::zenithLuminanceCdM2(*day.sky) << " cd/m²\n";
  t << "image        " << o.out << " (" << o.sizePx << "×" << o.sizePx
    << ", equidistant fisheye looking up: north up, east left";
  if (ext == ".png") {
    t.precision(2);
    t << "; exposure EV100 " << ev100 << ", Reinhard";
  } else {
    t << "; radiance in cd/m²";
  }
  t << ")\n";
  std::cout << t.str();
  return 0;
}

}  // namespace

Command addSkyCommand(CLI::App& app) {
  auto o = std::make_shared<SkyOptions>();
  CLI::App* sub = app.add_subcommand(
      "sky",
      "Render the sky dome of a site and time as a fisheye image (EXR in cd/m², or tone-mapped PNG); with "
      "--scene, the scene's site, time and sky are the defaults");
  o->site.add(*sub);
  sub->add_option(
         "--sky", o->request.model,
         "sky model: clear (Hosek-Wilkie sky and sun), preetham (Preetham, colour follows the sun), perez (all-weather; needs --weather or "
         "--dni-wm2/--dhi-wm2), cie:N (CIE standard sky type 1..15; needs --dhi or --zenith-luminance)")
      ->capture_default_str();
  sub->add_option("--weather", o->weather,
                  "EnergyPlus weather file (.epw): drives the Perez sky (or scales a CIE sky); its site and "
                  "standard-time zone are the defaults");
  sub->add_option("--turbidity", o->request.turbidity, "Linke turbidity of the clear sky and sun, [1.7, 10]")
      ->capture_default_str();
  sub->add_option("--ground-albedo", o->request.groundAlbedo,
                  "reflectance of the ground around the site for the clear sky, [0, 1]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--dhi", o->request.diffuseHorizontalLux, "diffuse horizontal illuminance, lux");
  sub->add_option("--dni", o->request.directNormalLux, "direct normal illuminance of the sun, lux");
  sub->add_option("--zenith-luminance", o->request.zenithLuminanceCdM2,
                  "zenith luminance of a CIE sky, cd/m²");
  sub->add_option("--dni-wm2", o->request.directNormalWm2,
                  "direct normal irradiance for the Perez sky, W/m²");
  sub->add_option("--dhi-wm2", o->request.diffuseHorizontalWm2,
                  "diffuse horizontal irradiance for the Perez sky, W/m²");
  sub->add_option("--dew-point", o->request.dewPointC, "dew point for the Perez luminous efficacy, °C")
      ->capture_default_str();
  sub->add_option("--out", o->out, "image file: .exr (radiance, cd/m²) or .png (tone-mapped)")->required();
  addDpiOption(*sub, &o->dotsPerInch);
  sub->add_option("--size", o->sizePx, "image width and height, pixels, [16, 8192]")
      ->capture_default_str()
      ->check(CLI::Range(16, 8192));
  sub->add_option("--exposure", o->exposureEv100, "PNG exposure, EV100 (default: automatic from the image)");
  sub->add_flag("--json", o->json, "print one JSON object instead of text");
  return {sub, [o, sub] {
            o->skyGiven = sub->count("--sky") > 0;
            o->turbidityGiven = sub->count("--turbidity") > 0;
            o->groundAlbedoGiven = sub->count("--ground-albedo") > 0;
            return runSky(*o);
          }};
}

}  // namespace fly::cli
