#include "cli/daylight.h"

#include <cmath>

#include "base/error.h"
#include "sunsky/cie_sky.h"
#include "sunsky/clear_sky.h"
#include "sunsky/hosek_wilkie.h"
#include "sunsky/perez_sky.h"

namespace fly::cli {

double stationPressureHpa(const sunsky::SpaInput& spa) {
  return std::isnan(spa.pressureHpa) ? sunsky::standardPressureHpa(spa.elevationM) : spa.pressureHpa;
}

namespace {

sunsky::SunDiscInput sunDiscInput(const SiteTime& st, const sunsky::SunPosition& sun, double turbidity) {
  sunsky::SunDiscInput in;
  in.zenithDeg = sun.apparentZenithDeg;
  in.azimuthDeg = sun.azimuthDeg;
  in.turbidity = turbidity;
  // The clear-sky model's valid pressure range; a site above ~9 km is outside what it was made for.
  in.pressureHpa = std::clamp(stationPressureHpa(st.spa), 300.0, 1100.0);
  in.dayOfYear = sunsky::dayOfYear(st.spa.utc);
  return in;
}

double directHorizontal(const sunsky::SunDisc& disc) {
  return std::max(0.0, double(luminance(disc.normalIlluminanceLux)) * disc.dirEnu.z);
}

}  // namespace

ClearDaylight clearDaylight(const SiteTime& st, const sunsky::SunPosition& sun, double turbidity) {
  const sunsky::SunDiscInput in = sunDiscInput(st, sun, turbidity);
  const sunsky::SunDisc disc = sunsky::hosekWilkieSunDisc(in);
  const sunsky::HosekWilkieSky sky = sunsky::makeHosekWilkieSky(
      turbidity, sunsky::kDefaultGroundAlbedo, sun.apparentZenithDeg, sun.azimuthDeg, in.dayOfYear);
  ClearDaylight d;
  d.directNormalLux = luminance(disc.normalIlluminanceLux);
  d.directHorizontalLux = directHorizontal(disc);
  d.diffuseHorizontalLux = sunsky::horizontalIlluminanceLux(sky);
  return d;
}

Daylight makeDaylight(const SkyRequest& r, const SiteTime& st, const sunsky::SunPosition& sun) {
  Daylight d;
  const sunsky::SunDiscInput discIn = sunDiscInput(st, sun, r.turbidity);
  if (r.model == "clear") {
    d.description = "clear sky and sun (Hosek and Wilkie 2012, 2013), turbidity " +
                    std::to_string(r.turbidity).substr(0, 4) + ", ground albedo " +
                    std::to_string(r.groundAlbedo).substr(0, 4);
    d.sky = std::make_unique<sunsky::HosekWilkieSky>(
        sunsky::makeHosekWilkieSky(r.turbidity, r.groundAlbedo, sun.apparentZenithDeg,
                                   sun.azimuthDeg, discIn.dayOfYear, r.diffuseHorizontalLux));
    d.sun = r.directNormalLux ? sunsky::sunDiscWithIlluminance(discIn, *r.directNormalLux)
                              : sunsky::hosekWilkieSunDisc(discIn);
    return d;
  }
  if (r.model == "preetham") {
    d.description =
        "clear sky (Preetham et al. 1999 distribution and colour, IES Lighting Handbook level), turbidity " +
        std::to_string(r.turbidity).substr(0, 4);
    d.sky = std::make_unique<sunsky::ClearSky>(sunsky::makeClearSky(r.turbidity, sun.apparentZenithDeg,
                                                                    sun.azimuthDeg, r.diffuseHorizontalLux,
                                                                    sunsky::ClearSkyLevel::kIesHandbook));
    d.sun = r.directNormalLux ? sunsky::sunDiscWithIlluminance(discIn, *r.directNormalLux)
                              : sunsky::clearSkySunDisc(discIn);
    return d;
  }
  if (r.model.rfind("cie:", 0) == 0) {
    int type = 0;
    try {
      size_t used = 0;
      type = std::stoi(r.model.substr(4), &used);
      if (used != r.model.size() - 4) type = 0;
    } catch (const std::exception&) {
      type = 0;
    }
    if (type < 1 || type > 15) {
      throw UsageError("--sky " + r.model +
                       ": the CIE standard sky type must be 1..15 (e.g. cie:1 overcast, cie:12 clear)");
    }
    std::optional<double> dhi = r.diffuseHorizontalLux;
    std::optional<double> dni = r.directNormalLux;
    if (r.weather && !dhi && !r.zenithLuminanceCdM2) {
      const sunsky::EpwSample w = sunsky::sampleAtUtc(*r.weather, st.spa.utc);
      dhi = w.dhiLux;
      if (!dni) dni = w.dniLux;
    }
    if (dhi && r.zenithLuminanceCdM2) throw UsageError("give either --dhi or --zenith-luminance, not both");
    if (!dhi && !r.zenithLuminanceCdM2) {
      throw UsageError(
          "a CIE sky needs its absolute level: give --dhi LUX (diffuse horizontal illuminance) or "
          "--zenith-luminance CD_M2, or --weather FILE.epw");
    }
    const sunsky::CieNormalisation norm =
        dhi ? sunsky::CieNormalisation::diffuseHorizontalLux(*dhi)
            : sunsky::CieNormalisation::zenithLuminanceCdM2(*r.zenithLuminanceCdM2);
    d.description = "CIE standard general sky type " + std::to_string(type) + " (ISO 15469)";
    d.sky = std::make_unique<sunsky::CieSky>(
        sunsky::makeCieSky(type, sun.apparentZenithDeg, sun.azimuthDeg, norm));
    if (dni) d.sun = sunsky::sunDiscWithIlluminance(discIn, *dni);
    return d;
  }
  if (r.model == "perez") {
    sunsky::PerezSkyInput in;
    in.sunZenithDeg = sun.apparentZenithDeg;
    in.sunAzimuthDeg = sun.azimuthDeg;
    in.dayOfYear = discIn.dayOfYear;
    in.dewPointC = r.dewPointC;
    const bool wm2 = r.directNormalWm2 || r.diffuseHorizontalWm2;
    const bool lux = r.directNormalLux || r.diffuseHorizontalLux;
    if (wm2 && lux)
      throw UsageError("give the Perez sky's inputs either in W/m² (--dni-wm2, --dhi-wm2) or in lux");
    if (wm2 || lux) {
      if (wm2 && !(r.directNormalWm2 && r.diffuseHorizontalWm2))
        throw UsageError("give both --dni-wm2 and --dhi-wm2");
      if (lux && !(r.directNormalLux && r.diffuseHorizontalLux))
        throw UsageError("give both --dni and --dhi");
      in.units =
          wm2 ? sunsky::PerezSkyInput::Units::kIrradianceWm2 : sunsky::PerezSkyInput::Units::kIlluminanceLux;
      in.directNormal = wm2 ? *r.directNormalWm2 : *r.directNormalLux;
      in.diffuseHorizontal = wm2 ? *r.diffuseHorizontalWm2 : *r.diffuseHorizontalLux;
      d.description = "Perez all-weather sky (Perez et al. 1993)";
    } else if (r.weather) {
      const sunsky::EpwSample w = sunsky::sampleAtUtc(*r.weather, st.spa.utc);
      if (!w.dniWm2 || !w.dhiWm2) {
        throw InputError(
            {r.weather->fileName},
            "the weather record at " + st.localIso + " has no direct normal or diffuse horizontal radiation",
            "choose another time, or give --dni-wm2 and --dhi-wm2");
      }
      in.units = sunsky::PerezSkyInput::Units::kIrradianceWm2;
      in.directNormal = *w.dniWm2;
      in.diffuseHorizontal = *w.dhiWm2;
      if (w.dewPointC) in.dewPointC = *w.dewPointC;
      d.description = "Perez all-weather sky (Perez et al. 1993) from " + r.weather->fileName;
    } else {
      throw UsageError(
          "the Perez sky needs weather data: --weather FILE.epw, or --dni-wm2 and --dhi-wm2 (W/m²), "
          "or --dni and --dhi (lux)");
    }
    const sunsky::PerezSky sky = sunsky::makePerezSky(in);
    d.sun = sunsky::sunDiscWithIlluminance(discIn, sky.directNormalLux());
    d.sky = std::make_unique<sunsky::PerezSky>(sky);
    return d;
  }
  throw UsageError("--sky " + r.model + ": expected clear, perez or cie:N (N = 1..15)");
}

}  // namespace fly::cli
