#include "rdb/site_lowering.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "base/error.h"
#include "sunsky/cie_sky.h"
#include "sunsky/civil_time.h"
#include "sunsky/clear_sky.h"
#include "sunsky/hosek_wilkie.h"
#include "sunsky/epw.h"
#include "sunsky/perez_sky.h"

namespace fly::rdb {

sunsky::NorthReference northReference(const sdb::Site& site) {
  sunsky::NorthReference n;
  n.angleDeg = site.northAngleDeg;
  switch (site.grid) {
    case sdb::Site::Grid::kNone: n.kind = sunsky::NorthReference::Kind::kTrueNorth; break;
    case sdb::Site::Grid::kUtm:
      n.kind = sunsky::NorthReference::Kind::kUtmGridNorth;
      n.utmZone = site.utmZone;
      break;
    case sdb::Site::Grid::kTransverseMercator:
      n.kind = sunsky::NorthReference::Kind::kTransverseMercatorGridNorth;
      n.centralMeridianDeg = site.gridCentralMeridianDeg;
      break;
  }
  return n;
}

double cieSkyDefaultDiffuseLux(int cieType, double sunElevationDeg, double sunAzimuthDeg, double turbidity) {
  const double sinAlpha = std::sin(degToRad(std::clamp(sunElevationDeg, 0.0, 90.0)));
  const double daylightLux = cieType <= 5 ? 1000.0 * (0.3 + 21.0 * sinAlpha)  // IES Handbook, overcast sky
                                          : sunsky::iesClearSkyDiffuseLux(sunElevationDeg);
  if (sunElevationDeg >= 0.0) return daylightLux;
  const sunsky::ClearSky twilight = sunsky::makeClearSky(turbidity, 90.0 - sunElevationDeg, sunAzimuthDeg,
                                                         std::nullopt, sunsky::ClearSkyLevel::kIesHandbook);
  return daylightLux * sunsky::horizontalIlluminanceLux(twilight) / sunsky::iesClearSkyDiffuseLux(0.0);
}

std::optional<SceneDaylight> lowerDaylight(const sdb::Scene& scene) {
  const sdb::SkySettings& settings = scene.sky();
  if (settings.model == sdb::SkyModel::kNone && !settings.sun) return std::nullopt;
  const std::optional<sdb::SunDirection>& direct = scene.time().sunDirection;
  if (!direct && (!scene.hasSite() || scene.time().localDateTime.empty())) {
    throw std::invalid_argument(
        "lowerDaylight: a sky or sun needs the scene's site and local time, or a sun direction");
  }
  if (direct && settings.model == sdb::SkyModel::kPerez) {
    throw std::invalid_argument("lowerDaylight: a Perez sky's weather record needs a time, not a sun direction");
  }
  const sdb::Site site = scene.hasSite() ? scene.site() : sdb::Site{};
  const SourceLocation where{scene.sourcePath.string()};

  SceneDaylight d;
  d.groundAlbedo = settings.groundAlbedo;
  d.frame = sunsky::makeSiteFrame(site.latitudeDeg, site.longitudeDeg, northReference(site), where);
  int dayOfYear = kDirectSunDayOfYear;
  sunsky::UtcTime utc;  // of the scene's time; unset for a sun placed directly
  if (direct) {
    d.sunPosition.azimuthDeg = direct->azimuthDeg;
    d.sunPosition.apparentZenithDeg = 90.0 - direct->elevationDeg;
    d.sunPosition.trueZenithDeg = d.sunPosition.apparentZenithDeg;
  } else {
    sunsky::SpaInput spa;
    spa.utc = sunsky::parseTime(scene.time().localDateTime, site.timeZone, "the scene's time");
    utc = spa.utc;
    spa.latitudeDeg = site.latitudeDeg;
    spa.longitudeDeg = site.longitudeDeg;
    spa.elevationM = site.elevationM;
    d.sunPosition = sunsky::sunPosition(spa);
    dayOfYear = sunsky::dayOfYear(spa.utc);
  }
  const sunsky::SunPosition& sun = d.sunPosition;
  d.sunDirWorld = d.frame.worldFromEnu(
      sunsky::directionFromAzimuthElevation(sun.azimuthDeg, sun.apparentElevationDeg()));

  sunsky::SunDiscInput disc;
  disc.zenithDeg = sun.apparentZenithDeg;
  disc.azimuthDeg = sun.azimuthDeg;
  disc.turbidity = settings.turbidity;
  // The clear-atmosphere model's valid pressure range; a site above ~9 km is outside what it was made for.
  disc.pressureHpa = std::clamp(sunsky::standardPressureHpa(site.elevationM), 300.0, 1100.0);
  disc.dayOfYear = dayOfYear;

  std::optional<double> directNormalLux;  // the weather's, for the sun of a Perez sky
  switch (settings.model) {
    case sdb::SkyModel::kNone: break;
    case sdb::SkyModel::kClear:
      d.sky = std::make_unique<sunsky::HosekWilkieSky>(
          sunsky::makeHosekWilkieSky(settings.turbidity, settings.groundAlbedo, sun.apparentZenithDeg,
                                     sun.azimuthDeg, disc.dayOfYear));
      break;
    case sdb::SkyModel::kPreetham:
      d.sky = std::make_unique<sunsky::ClearSky>(sunsky::makeClearSky(
          settings.turbidity, sun.apparentZenithDeg, sun.azimuthDeg, std::nullopt, sunsky::ClearSkyLevel::kIesHandbook));
      break;
    case sdb::SkyModel::kCie: {
      const double levelLux = cieSkyDefaultDiffuseLux(settings.cieType, sun.apparentElevationDeg(), sun.azimuthDeg,
                                                      settings.turbidity);
      d.sky = std::make_unique<sunsky::CieSky>(sunsky::makeCieSky(
          settings.cieType, sun.apparentZenithDeg, sun.azimuthDeg,
          sunsky::CieNormalisation::diffuseHorizontalLux(levelLux)));
      break;
    }
    case sdb::SkyModel::kPerez: {
      // The scene-file reader has already resolved the path against the scene file's folder.
      const sunsky::EpwFile epw = sunsky::loadEpw(settings.weatherFile);
      const sunsky::EpwSample w = sunsky::sampleAtUtc(epw, utc);
      if (!w.dniWm2 || !w.dhiWm2) {
        throw InputError({epw.fileName},
                         "the weather record at " + scene.time().localDateTime +
                             " has no direct normal or diffuse horizontal radiation",
                         "choose another time in the scene");
      }
      sunsky::PerezSkyInput in;
      in.sunZenithDeg = sun.apparentZenithDeg;
      in.sunAzimuthDeg = sun.azimuthDeg;
      in.units = sunsky::PerezSkyInput::Units::kIrradianceWm2;
      in.directNormal = *w.dniWm2;
      in.diffuseHorizontal = *w.dhiWm2;
      in.dayOfYear = disc.dayOfYear;
      if (w.dewPointC) in.dewPointC = *w.dewPointC;
      const sunsky::PerezSky perez = sunsky::makePerezSky(in);
      directNormalLux = perez.directNormalLux();
      d.sky = std::make_unique<sunsky::PerezSky>(perez);
      break;
    }
  }
  if (settings.sun && sun.apparentElevationDeg() > 0.0) {
    d.sun = directNormalLux                                ? sunsky::sunDiscWithIlluminance(disc, *directNormalLux)
            : settings.model == sdb::SkyModel::kClear ? sunsky::hosekWilkieSunDisc(disc)
                                                      : sunsky::clearSkySunDisc(disc);
  }
  return d;
}

}  // namespace fly::rdb
