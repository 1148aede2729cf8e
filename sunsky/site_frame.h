// The site's local frame (east, north, up) in world space, for models drawn to true north, rotated by a north
// angle, or drawn to the grid north of a UTM zone or another transverse-Mercator grid.
//
// World space is glTF's: right-handed, +Y up, metres (docs/architecture.md). ENU is right-handed too: x east, y north,
// z up. Angles "clockwise seen from above" are seen looking down −Y, where a turn from −Z goes towards +X.
// With true north along world −Z (the default), east is +X, up is +Y and south is +Z.
#pragma once

#include "base/error.h"
#include "base/math.h"

namespace fly::sunsky {

// Which north a model is drawn to, and by how much it is turned from world −Z.
struct NorthReference {
  enum class Kind {
    kTrueNorth,                    // the model's north is true (geographic) north
    kUtmGridNorth,                 // the model's north is grid north of UTM zone `utmZone`
    kTransverseMercatorGridNorth,  // the model's north is grid north of a transverse-Mercator grid whose
                                   // central meridian is `centralMeridianDeg` (e.g. ETRS-TM35FIN: 27° E)
  };
  Kind kind = Kind::kTrueNorth;
  // Degrees, clockwise seen from above, from world −Z to the model's north (true north for kTrueNorth, grid
  // north for the grid kinds), [−360, 360]. 0 = the model's north lies along −Z.
  double angleDeg = 0.0;
  int utmZone = 0;  // kUtmGridNorth only: 1..60; zone N has its central meridian at 6N − 183° E
  double centralMeridianDeg = 0.0;  // kTransverseMercatorGridNorth only: degrees east, [−180, 180]
};

// A rotation about world +Y between ENU and world space; the origin of both is the site (a tangent plane:
// fine for the extent of a building site). Make one with makeSiteFrame().
class SiteFrame {
 public:
  double latitudeDeg() const { return latitudeDeg_; }
  double longitudeDeg() const { return longitudeDeg_; }

  // Meridian convergence γ at the site in degrees: the bearing of grid north measured clockwise from true
  // north (GeographicLib's convention for TransverseMercator::Forward and UTMUPS::Forward). 0 for kTrueNorth.
  // East of the central meridian in the northern hemisphere γ > 0; Helsinki on TM35 (27° E): γ ≈ −1.79°.
  double meridianConvergenceDeg() const { return meridianConvergenceDeg_; }

  // The total turn, degrees clockwise seen from above, from world −Z to true north, (−180, 180]:
  // NorthReference::angleDeg − γ (a model drawn to grid north has true north at −γ from its grid north).
  double trueNorthFromWorldMinusZDeg() const { return trueNorthFromWorldMinusZDeg_; }

  // Directions or positions (metres, relative to the site origin).
  dvec3 worldFromEnu(const dvec3& enu) const;
  dvec3 enuFromWorld(const dvec3& world) const;

 private:
  friend SiteFrame makeSiteFrame(double, double, const NorthReference&, const SourceLocation&);

  double latitudeDeg_ = 0.0;
  double longitudeDeg_ = 0.0;
  double meridianConvergenceDeg_ = 0.0;
  double trueNorthFromWorldMinusZDeg_ = 0.0;
  dvec3 eastWorld_{1.0, 0.0, 0.0};
  dvec3 northWorld_{0.0, 0.0, -1.0};
};

// The frame of a site at geodetic (WGS84) latitude [−90, 90] and longitude [−180, 180] (degrees, north and
// east positive). Throws InputError at `where` (the scene file or flag the values came from; may be empty)
// for a value out of range, a UTM zone outside 1..60, or a site too far from its grid's central meridian:
// more than 500 km of easting (GeographicLib's UTMUPS allows UTM eastings 0..1000 km, i.e. ±500 km about the
// central meridian; national grids are narrower) or more than 90° of longitude (the far side of the globe).
// No drawing is made on a grid that far away, and γ grows with the distance, so the zone or meridian is
// surely wrong. UTM also stops at about 84° N and 80° S (UPS beyond), as UTMUPS enforces.
SiteFrame makeSiteFrame(double latitudeDeg, double longitudeDeg, const NorthReference& north,
                        const SourceLocation& where = {});

// The unit ENU direction towards azimuth `azimuthDeg` (clockwise from true north: 90 = east) and elevation
// `elevationDeg` above the horizon ([−90, 90]; e.g. the sun's 90° − zenith).
dvec3 directionFromAzimuthElevation(double azimuthDeg, double elevationDeg);

}  // namespace fly::sunsky
