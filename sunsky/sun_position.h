// The sun's position from site and time: the NREL Solar Position Algorithm (Reda & Andreas, "Solar position
// algorithm for solar radiation applications", Solar Energy 76 (2004) 577–589; NREL/TP-560-34302 rev. 2008),
// implemented from the paper. Uncertainty ±0.0003° for years −2000..6000.
#pragma once

#include <cmath>
#include <limits>

#include "sunsky/civil_time.h"

namespace fly::sunsky {

struct SpaInput {
  UtcTime utc;
  double latitudeDeg = 0.0;   // geodetic, [−90, 90], north positive
  double longitudeDeg = 0.0;  // [−180, 180], east positive
  double elevationM = 0.0;    // above sea level, [−500, 11000] (Dead Sea shore to above Everest; the troposphere
                              // that the standard-atmosphere defaults model)
  // ΔT = TT − UT1 in seconds, |ΔT| ≤ 100000; NaN = the Espenak–Meeus polynomials (deltaTSeconds()).
  double deltaTSeconds = std::numeric_limits<double>::quiet_NaN();
  double dut1Seconds = 0.0;   // UT1 − UTC, seconds, (−1, 1)
  // Mean annual local pressure (hPa, [0, 1200]; 0 = no refraction) and temperature (°C, [−100, 100]) for
  // refraction; NaN = the standard atmosphere (ICAO / US 1976) at elevationM.
  double pressureHpa = std::numeric_limits<double>::quiet_NaN();
  double temperatureC = std::numeric_limits<double>::quiet_NaN();
};

struct SunPosition {
  double trueZenithDeg = 0.0;      // topocentric, airless (no refraction), [0, 180]
  double apparentZenithDeg = 0.0;  // with SPA's refraction (eq. 42), none once the sun is below −0.8333°
  // Topocentric azimuth, clockwise from north, [0, 360). At the poles and with the sun at the zenith, where
  // azimuth is undefined, the convention in sun_position.cpp applies; never NaN.
  double azimuthDeg = 0.0;
  double declinationDeg = 0.0;         // geocentric declination
  double rightAscensionDeg = 0.0;      // geocentric right ascension, [0, 360)
  double hourAngleDeg = 0.0;           // observer local hour angle, [0, 360)
  double equationOfTimeMinutes = 0.0;  // apparent − mean solar time, minutes, about [−17, +17]
  double earthSunDistanceAu = 1.0;

  double trueElevationDeg() const { return 90.0 - trueZenithDeg; }
  double apparentElevationDeg() const { return 90.0 - apparentZenithDeg; }
};

// The sun's position at an instant. Validates the input (InputError for latitude 91°, an invalid date …).
// Allocation-free unless it throws.
SunPosition sunPosition(const SpaInput& in);

// SPA's intermediate quantities (the paper's table A5.1 lists them for its worked example), for tests and
// diagnostics. Angles in degrees.
struct SpaDetail {
  double julianDay = 0.0;                // JD, UT1 (eq. 4)
  double julianEphemerisDay = 0.0;       // JDE, TT (eq. 5)
  double deltaTSeconds = 0.0;            // the ΔT used
  double heliocentricLongitudeDeg = 0.0;  // L, [0, 360) (eq. 11–12)
  double heliocentricLatitudeDeg = 0.0;   // B
  double radiusVectorAu = 0.0;            // R
  double geocentricLongitudeDeg = 0.0;    // Θ, [0, 360) (eq. 13)
  double geocentricLatitudeDeg = 0.0;     // β (eq. 14)
  double nutationLongitudeDeg = 0.0;      // Δψ (eq. 22)
  double nutationObliquityDeg = 0.0;      // Δε (eq. 23)
  double trueObliquityDeg = 0.0;          // ε (eq. 25)
  double apparentSunLongitudeDeg = 0.0;   // λ, [0, 360) (eq. 27)
  double apparentSiderealTimeDeg = 0.0;   // ν at Greenwich, [0, 360) (eq. 29)
  double topocentricRightAscensionDeg = 0.0;  // α′, [0, 360) (eq. 38)
  double topocentricDeclinationDeg = 0.0;     // δ′ (eq. 39)
  double topocentricHourAngleDeg = 0.0;       // H′, [0, 360) (eq. 40)
  double pressureHpa = 0.0;               // used for refraction (given or standard atmosphere)
  double temperatureC = 0.0;
  SunPosition position;
};
SpaDetail sunPositionDetail(const SpaInput& in);

// Sunrise, transit and sunset on the local calendar day (at UTC offset `utcOffsetHours`, [−18, 18]) that contains
// in.utc, as UTC instants (SPA, appendix A.2, with the day starting at local midnight instead of 0 UT: the paper's
// own example, run on the UT day, reports the sunset at 00:20 UT that ends the previous local day). Sunrise and
// sunset: the sun's upper limb on the horizon with standard refraction (h0' = −0.8333°), each the crossing that
// falls within the local day. Polar day and polar night are reported as such, not as NaN.
struct SunTimes {
  enum class Kind { kNormal, kPolarDay, kPolarNight };
  Kind kind = Kind::kNormal;
  UtcTime transit;   // always defined
  UtcTime sunrise;   // defined when kind == kNormal
  UtcTime sunset;    // defined when kind == kNormal
};
SunTimes sunTimes(const SpaInput& in, double utcOffsetHours);

// ΔT = TT − UT1 in seconds for a decimal year, from the Espenak–Meeus polynomials (NASA eclipse web site,
// "Polynomial expressions for Delta T"), −1999..3000 and the long-term parabola outside. InputError unless finite.
double deltaTSeconds(double decimalYear);

// Standard-atmosphere pressure (hPa) and temperature (°C) at an elevation (US Standard Atmosphere 1976,
// troposphere: T = 15 − 0.0065·h, p = 1013.25·(1 − 2.25577e−5·h)^5.25588). InputError outside [−500, 11000] m.
double standardPressureHpa(double elevationM);
double standardTemperatureC(double elevationM);

}  // namespace fly::sunsky
