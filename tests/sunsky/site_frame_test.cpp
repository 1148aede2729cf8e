#include "sunsky/site_frame.h"

#include <gtest/gtest.h>

#include <GeographicLib/UTMUPS.hpp>

#include <cmath>
#include <string>

#include "base/error.h"
#include "base/math.h"

namespace fly::sunsky {
namespace {

constexpr double kHelsinkiLat = 60.17;
constexpr double kHelsinkiLon = 24.94;

void expectNear(const dvec3& a, const dvec3& b, double tol = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// `v` turned by `deg` clockwise seen from above (+Y): −Z goes towards +X.
dvec3 turnClockwise(const dvec3& v, double deg) {
  const double t = degToRad(deg);
  return dvec3(v.x * std::cos(t) - v.z * std::sin(t), v.y, v.x * std::sin(t) + v.z * std::cos(t));
}

std::string errorOf(double lat, double lon, const NorthReference& north) {
  try {
    makeSiteFrame(lat, lon, north, {"scene.json", 3, 5});
  } catch (const InputError& e) {
    EXPECT_FALSE(e.hint().empty()) << e.what();
    EXPECT_EQ(e.location().file, "scene.json");
    return e.what();
  }
  return "no error";
}

TEST(SiteFrame, TrueNorthIsMinusZAndSouthSunIsPlusZ) {
  const SiteFrame f = makeSiteFrame(kHelsinkiLat, kHelsinkiLon, {});
  EXPECT_EQ(f.meridianConvergenceDeg(), 0.0);
  EXPECT_EQ(f.trueNorthFromWorldMinusZDeg(), 0.0);
  expectNear(f.worldFromEnu({1, 0, 0}), {1, 0, 0});   // east = +X
  expectNear(f.worldFromEnu({0, 1, 0}), {0, 0, -1});  // north = −Z
  expectNear(f.worldFromEnu({0, 0, 1}), {0, 1, 0});   // up = +Y
  const dvec3 sun = f.worldFromEnu(directionFromAzimuthElevation(180.0, 30.0));
  expectNear(sun, {0.0, std::sin(degToRad(30.0)), std::cos(degToRad(30.0))});
}

TEST(SiteFrame, AzimuthElevationDirections) {
  expectNear(directionFromAzimuthElevation(0, 0), {0, 1, 0});
  expectNear(directionFromAzimuthElevation(90, 0), {1, 0, 0});
  expectNear(directionFromAzimuthElevation(270, 0), {-1, 0, 0});
  expectNear(directionFromAzimuthElevation(123, 90), {0, 0, 1});
  expectNear(directionFromAzimuthElevation(45, -90), {0, 0, -1});
  EXPECT_NEAR(glm::length(directionFromAzimuthElevation(211.3, 17.9)), 1.0, 1e-15);
}

TEST(SiteFrame, NorthAngleTurnsDirectionsClockwise) {
  const SiteFrame f = makeSiteFrame(kHelsinkiLat, kHelsinkiLon, {.angleDeg = 90.0});
  EXPECT_EQ(f.trueNorthFromWorldMinusZDeg(), 90.0);
  expectNear(f.worldFromEnu({0, 1, 0}), {1, 0, 0});  // true north along +X
  expectNear(f.worldFromEnu({1, 0, 0}), {0, 0, 1});  // east along +Z
  // The south sun at 30° now shines from −X.
  const dvec3 sun = f.worldFromEnu(directionFromAzimuthElevation(180.0, 30.0));
  expectNear(sun, {-std::cos(degToRad(30.0)), std::sin(degToRad(30.0)), 0.0});
  // −270° and 450°-like inputs agree with +90° once wrapped.
  EXPECT_NEAR(makeSiteFrame(0, 0, {.angleDeg = -270.0}).trueNorthFromWorldMinusZDeg(), 90.0, 1e-12);
  EXPECT_EQ(makeSiteFrame(0, 0, {.angleDeg = -180.0}).trueNorthFromWorldMinusZDeg(), 180.0);
}

TEST(SiteFrame, HelsinkiTm35ConvergenceMatchesGeographicLib) {
  // GeographicLib directly: UTM zone 35 has the central meridian of ETRS-TM35FIN (27° E).
  int zone = 0;
  bool northp = false;
  double x = 0, y = 0, gamma = 0, k = 0;
  GeographicLib::UTMUPS::Forward(kHelsinkiLat, kHelsinkiLon, zone, northp, x, y, gamma, k, 35);
  EXPECT_NEAR(gamma, -1.8, 0.05);

  const SiteFrame utm =
      makeSiteFrame(kHelsinkiLat, kHelsinkiLon, {.kind = NorthReference::Kind::kUtmGridNorth, .utmZone = 35});
  EXPECT_NEAR(utm.meridianConvergenceDeg(), gamma, 1e-12);
  const SiteFrame tm =
      makeSiteFrame(kHelsinkiLat, kHelsinkiLon,
                    {.kind = NorthReference::Kind::kTransverseMercatorGridNorth, .centralMeridianDeg = 27.0});
  EXPECT_NEAR(tm.meridianConvergenceDeg(), gamma, 1e-12);
  EXPECT_NEAR(tm.meridianConvergenceDeg(), -1.787, 0.001);
  // Grid north is west of true north here, so true north lies 1.79° clockwise from the model's −Z.
  EXPECT_NEAR(tm.trueNorthFromWorldMinusZDeg(), -gamma, 1e-12);
}

TEST(SiteFrame, GridModelTurnsEveryDirectionByMinusGamma) {
  const SiteFrame trueNorth = makeSiteFrame(kHelsinkiLat, kHelsinkiLon, {});
  const SiteFrame grid =
      makeSiteFrame(kHelsinkiLat, kHelsinkiLon, {.kind = NorthReference::Kind::kUtmGridNorth, .utmZone = 35});
  const double gamma = grid.meridianConvergenceDeg();
  for (double az = 0.0; az < 360.0; az += 22.5) {
    for (double el : {-10.0, 0.0, 30.0, 89.0}) {
      const dvec3 enu = directionFromAzimuthElevation(az, el);
      expectNear(grid.worldFromEnu(enu), turnClockwise(trueNorth.worldFromEnu(enu), -gamma));
    }
  }
  // The north angle adds to the grid's turn: a grid drawing rotated 10° has true north at 10° − γ.
  const SiteFrame turned =
      makeSiteFrame(kHelsinkiLat, kHelsinkiLon,
                    {.kind = NorthReference::Kind::kUtmGridNorth, .angleDeg = 10.0, .utmZone = 35});
  EXPECT_NEAR(turned.trueNorthFromWorldMinusZDeg(), 10.0 - gamma, 1e-12);
}

TEST(SiteFrame, ConvergenceSignsAcrossHemispheres) {
  // East of the central meridian γ > 0 in the north and < 0 in the south (γ ≈ Δλ sin φ near the meridian).
  const auto tmGamma = [](double lat, double lon) {
    return makeSiteFrame(
               lat, lon,
               {.kind = NorthReference::Kind::kTransverseMercatorGridNorth, .centralMeridianDeg = 27.0})
        .meridianConvergenceDeg();
  };
  EXPECT_GT(tmGamma(60.0, 29.0), 0.0);
  EXPECT_LT(tmGamma(-30.0, 29.0), 0.0);
  EXPECT_NEAR(tmGamma(0.0, 29.0), 0.0, 1e-12);
  EXPECT_NEAR(tmGamma(45.0, 28.0), 1.0 * std::sin(degToRad(45.0)), 0.01);
}

TEST(SiteFrame, WorldEnuRoundTrip) {
  for (const NorthReference& n :
       {NorthReference{}, NorthReference{.angleDeg = 37.5}, NorthReference{.angleDeg = -200.0},
        NorthReference{.kind = NorthReference::Kind::kUtmGridNorth, .angleDeg = 5.0, .utmZone = 35}}) {
    const SiteFrame f = makeSiteFrame(kHelsinkiLat, kHelsinkiLon, n);
    for (const dvec3& p : {dvec3(1, 2, 3), dvec3(-40.5, 0.25, 1e3), dvec3(0, 0, 0), dvec3(-7, -8, -9)}) {
      expectNear(f.enuFromWorld(f.worldFromEnu(p)), p, 1e-9);
      expectNear(f.worldFromEnu(f.enuFromWorld(p)), p, 1e-9);
      EXPECT_NEAR(glm::length(f.worldFromEnu(p)), glm::length(p), 1e-9);
    }
  }
}

TEST(SiteFrame, PolesAndDateLineNeverNaN) {
  for (double lat : {-90.0, -89.999, 0.0, 89.999, 90.0}) {
    for (double lon : {-180.0, -179.999, 0.0, 179.999, 180.0}) {
      for (const NorthReference& n :
           {NorthReference{}, NorthReference{.angleDeg = 360.0},
            NorthReference{.kind = NorthReference::Kind::kTransverseMercatorGridNorth,
            .centralMeridianDeg = std::remainder(lon + 1.0, 360.0)}}) {
        const SiteFrame f = makeSiteFrame(lat, lon, n);
        EXPECT_TRUE(std::isfinite(f.meridianConvergenceDeg())) << lat << " " << lon;
        EXPECT_TRUE(std::isfinite(f.trueNorthFromWorldMinusZDeg())) << lat << " " << lon;
        const dvec3 d = f.worldFromEnu(directionFromAzimuthElevation(135.0, 20.0));
        EXPECT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z)) << lat << " " << lon;
        EXPECT_NEAR(glm::length(d), 1.0, 1e-12);
      }
    }
  }
  // The ±180° meridian is one meridian: a grid on 180° sees the same γ from either side's spelling.
  const auto gammaAt = [](double lon) {
    return makeSiteFrame(-40.0, lon, {.kind = NorthReference::Kind::kUtmGridNorth, .utmZone = 60})
        .meridianConvergenceDeg();
  };
  EXPECT_NEAR(gammaAt(180.0), gammaAt(-180.0), 1e-12);
}

TEST(SiteFrame, InvalidInputIsAnInputErrorWithAHint) {
  EXPECT_NE(errorOf(91.0, 0.0, {}).find("latitude 91 is outside [-90, 90]"), std::string::npos);
  EXPECT_NE(errorOf(std::nan(""), 0.0, {}).find("latitude nan is outside"), std::string::npos);
  EXPECT_NE(errorOf(0.0, -180.5, {}).find("longitude -180.5 is outside [-180, 180]"), std::string::npos);
  EXPECT_NE(errorOf(0.0, 0.0, {.angleDeg = 400.0}).find("north angle 400 is outside"), std::string::npos);
  EXPECT_EQ(
      errorOf(kHelsinkiLat, kHelsinkiLon, {.kind = NorthReference::Kind::kUtmGridNorth, .utmZone = 61}),
      "scene.json:3:5: UTM zone 61 does not exist\n  hint: UTM zones are numbered 1 to 60; zone N spans "
      "longitudes 6N - 186 to 6N - 180 degrees east");
  EXPECT_NE(errorOf(kHelsinkiLat, kHelsinkiLon, {.kind = NorthReference::Kind::kUtmGridNorth})
                .find("UTM zone 0 does not exist"),
            std::string::npos);
  // Zone 1 (central meridian 177° W) is half the world away from Helsinki.
  const std::string farZone =
      errorOf(kHelsinkiLat, kHelsinkiLon, {.kind = NorthReference::Kind::kUtmGridNorth, .utmZone = 1});
  EXPECT_NE(farZone.find("is outside UTM zone 1"), std::string::npos) << farZone;
  EXPECT_NE(farZone.find("hint: the site lies in UTM zone 35 (central meridian 27 degrees east)"),
            std::string::npos)
      << farZone;
  // Zone 31 (3° E) is 22° of longitude, about 1200 km, away: also not a grid a drawing of Helsinki is made
  // on.
  EXPECT_NE(errorOf(kHelsinkiLat, kHelsinkiLon, {.kind = NorthReference::Kind::kUtmGridNorth, .utmZone = 31})
                .find("is outside UTM zone 31"),
            std::string::npos);
  const std::string farMeridian =
      errorOf(kHelsinkiLat, kHelsinkiLon,
              {.kind = NorthReference::Kind::kTransverseMercatorGridNorth, .centralMeridianDeg = -153.0});
  EXPECT_NE(farMeridian.find("is 178 degrees of longitude from the central meridian -153 degrees east"),
            std::string::npos)
      << farMeridian;
  const std::string wideMeridian =
      errorOf(kHelsinkiLat, kHelsinkiLon,
              {.kind = NorthReference::Kind::kTransverseMercatorGridNorth, .centralMeridianDeg = 15.0});
  EXPECT_NE(wideMeridian.find("is 550 km from the central meridian 15 degrees east"), std::string::npos)
      << wideMeridian;
  EXPECT_NE(errorOf(0.0, 0.0,
                    {.kind = NorthReference::Kind::kTransverseMercatorGridNorth, .centralMeridianDeg = 181.0})
                .find("central meridian 181 is outside [-180, 180]"),
            std::string::npos);
  // UTM stops at 84° N; beyond it the hint points away from UTM.
  const std::string polar = errorOf(88.0, 24.0, {.kind = NorthReference::Kind::kUtmGridNorth, .utmZone = 35});
  EXPECT_NE(polar.find("UTM does not reach this latitude"), std::string::npos) << polar;
}

}  // namespace
}  // namespace fly::sunsky
