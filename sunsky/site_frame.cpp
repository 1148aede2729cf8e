#include "sunsky/site_frame.h"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/TransverseMercator.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include <cmath>
#include <cstdio>
#include <string>

namespace fly::sunsky {
namespace {

// Half the easting range GeographicLib's UTMUPS accepts for a UTM zone (0..1000 km about the false easting
// 500 km; UTMUPS.hpp, Reverse), applied to every transverse-Mercator grid.
constexpr double kMaxGridEastingM = 500e3;

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string siteText(double latitudeDeg, double longitudeDeg) {
  return "the site (latitude " + fmt(latitudeDeg) + ", longitude " + fmt(longitudeDeg) + ")";
}

void checkRange(double v, double lo, double hi, const char* what, const char* hint,
                const SourceLocation& where) {
  if (!(v >= lo && v <= hi)) {  // also rejects NaN
    throw InputError(
        where, std::string(what) + " " + fmt(v) + " is outside [" + fmt(lo) + ", " + fmt(hi) + "]", hint);
  }
}

// γ of UTM zone `zone` at the site, from GeographicLib's UTMUPS (which also rejects a site outside the zone's
// coordinate range).
double utmConvergenceDeg(double latitudeDeg, double longitudeDeg, int zone, const SourceLocation& where) {
  if (zone < GeographicLib::UTMUPS::MINUTMZONE || zone > GeographicLib::UTMUPS::MAXUTMZONE) {
    throw InputError(
        where, "UTM zone " + std::to_string(zone) + " does not exist",
        "UTM zones are numbered 1 to 60; zone N spans longitudes 6N - 186 to 6N - 180 degrees east");
  }
  const int standardZone = GeographicLib::UTMUPS::StandardZone(latitudeDeg, longitudeDeg);
  const std::string standardHint =
      standardZone == GeographicLib::UTMUPS::UPS
          ? "UTM does not reach this latitude (80 S to 84 N); draw the model to true north with a north angle"
          : "the site lies in UTM zone " + std::to_string(standardZone) + " (central meridian " +
                fmt(6.0 * standardZone - 183.0) + " degrees east); check the zone of the drawing";
  int zoneOut = 0;
  bool northp = true;
  double x = 0.0, y = 0.0, gamma = 0.0, k = 0.0;
  try {
    GeographicLib::UTMUPS::Forward(latitudeDeg, longitudeDeg, zoneOut, northp, x, y, gamma, k, zone);
  } catch (const GeographicLib::GeographicErr&) {
    throw InputError(where,
                     siteText(latitudeDeg, longitudeDeg) + " is outside UTM zone " + std::to_string(zone) +
                         ", whose grid covers 500 km either side of its central meridian " +
                         fmt(6.0 * zone - 183.0) + " degrees east",
                     standardHint);
  }
  return gamma;
}

// γ of a transverse-Mercator grid with central meridian `lon0Deg`. γ does not depend on the central scale
// factor or the false easting and northing, so any grid on that meridian (ETRS-TM35FIN, Gauss–Krüger, UTM)
// has the same γ; the easting is checked with scale 1 (true distance along the central meridian).
double tmConvergenceDeg(double latitudeDeg, double longitudeDeg, double lon0Deg,
                        const SourceLocation& where) {
  checkRange(lon0Deg, -180.0, 180.0, "central meridian", "give the grid's central meridian in degrees east",
             where);
  const GeographicLib::TransverseMercator tm(GeographicLib::Constants::WGS84_a(),
                                             GeographicLib::Constants::WGS84_f(), 1.0);
  double x = 0.0, y = 0.0, gamma = 0.0, k = 0.0;
  tm.Forward(lon0Deg, latitudeDeg, longitudeDeg, x, y, gamma, k);
  // Beyond 90° of longitude the site lies on the far half of the central meridian's great circle, where the
  // easting is small again but the grid is upside down.
  const double dLonDeg = std::abs(std::remainder(longitudeDeg - lon0Deg, 360.0));
  if (dLonDeg > 90.0 || !(std::abs(x) <= kMaxGridEastingM)) {
    const std::string distance = dLonDeg > 90.0 ? fmt(std::round(dLonDeg)) + " degrees of longitude"
                                                : fmt(std::round(std::abs(x) / 1e3)) + " km";
    throw InputError(where,
                     siteText(latitudeDeg, longitudeDeg) + " is " + distance + " from the central meridian " +
                         fmt(lon0Deg) +
                         " degrees east; a transverse-Mercator grid is used within 500 km of it",
                     "check the grid's central meridian (ETRS-TM35FIN: 27; UTM zone N: 6N - 183)");
  }
  return gamma;
}

// `deg` wrapped to (−180, 180].
double wrapDeg(double deg) {
  double r = std::remainder(deg, 360.0);  // [−180, 180]
  if (r == -180.0) r = 180.0;
  return r;
}

}  // namespace

SiteFrame makeSiteFrame(double latitudeDeg, double longitudeDeg, const NorthReference& north,
                        const SourceLocation& where) {
  checkRange(latitudeDeg, -90.0, 90.0, "latitude", "give degrees north, [-90, 90]; south is negative", where);
  checkRange(longitudeDeg, -180.0, 180.0, "longitude", "give degrees east, [-180, 180]; west is negative",
             where);
  checkRange(north.angleDeg, -360.0, 360.0, "north angle",
             "give degrees clockwise seen from above, from the model's -Z axis to its north", where);

  SiteFrame f;
  f.latitudeDeg_ = latitudeDeg;
  f.longitudeDeg_ = longitudeDeg;
  switch (north.kind) {
    case NorthReference::Kind::kTrueNorth:
      f.meridianConvergenceDeg_ = 0.0;
      break;
    case NorthReference::Kind::kUtmGridNorth:
      f.meridianConvergenceDeg_ = utmConvergenceDeg(latitudeDeg, longitudeDeg, north.utmZone, where);
      break;
    case NorthReference::Kind::kTransverseMercatorGridNorth:
      f.meridianConvergenceDeg_ =
          tmConvergenceDeg(latitudeDeg, longitudeDeg, north.centralMeridianDeg, where);
      break;
  }
  // Grid north is γ clockwise from true north, so true north is −γ clockwise from grid north, which the model
  // has at angleDeg clockwise from −Z.
  f.trueNorthFromWorldMinusZDeg_ = wrapDeg(north.angleDeg - f.meridianConvergenceDeg_);

  // A turn by θ clockwise seen from above takes −Z to (sin θ, 0, −cos θ) and +X to (cos θ, 0, sin θ).
  const double theta = degToRad(f.trueNorthFromWorldMinusZDeg_);
  f.northWorld_ = dvec3(std::sin(theta), 0.0, -std::cos(theta));
  f.eastWorld_ = dvec3(std::cos(theta), 0.0, std::sin(theta));
  return f;
}

dvec3 SiteFrame::worldFromEnu(const dvec3& enu) const {
  return enu.x * eastWorld_ + enu.y * northWorld_ + dvec3(0.0, enu.z, 0.0);
}

dvec3 SiteFrame::enuFromWorld(const dvec3& world) const {
  return dvec3(glm::dot(world, eastWorld_), glm::dot(world, northWorld_), world.y);
}

dvec3 directionFromAzimuthElevation(double azimuthDeg, double elevationDeg) {
  const double az = degToRad(azimuthDeg);
  const double el = degToRad(elevationDeg);
  return dvec3(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
}

}  // namespace fly::sunsky
