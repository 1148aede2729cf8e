#include "sunsky/sun_position.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <span>
#include <string>

#include "base/error.h"
#include "base/math.h"

// Equation numbers below are those of Reda & Andreas, NREL/TP-560-34302 (revised 2008); "A" numbers are its
// appendix. Tables A4.2 (Earth periodic terms) and A4.3 (nutation) are transcribed from the report.
//
// Azimuth conventions where the azimuth is undefined (never NaN):
// - At a pole (latitude ±90° exactly) eq. 45 is evaluated as it stands. It then gives the azimuth in the frame
//   that is the limit of the local (east, north, up) frame when the pole is approached along the input
//   longitude: "north" at the North Pole points along the meridian opposite to that longitude, at the South Pole
//   along that longitude. GeographicLib's local frame at a pole is the same limit, so the two agree.
// - With the sun within 1e-9° of the zenith (numerator and denominator of eq. 45 both vanish) the azimuth is 180°.

namespace fly::sunsky {
namespace {

// ---- Table A4.2: Earth periodic terms. Each row: A (1e-8 rad, or 1e-8 AU for R), B (rad), C (rad per millennium).
struct PeriodicTerm {
  double a, b, c;
};

constexpr PeriodicTerm kL0[] = {
    {175347046, 0, 0},        {3341656, 4.6692568, 6283.07585}, {34894, 4.6261, 12566.1517},
    {3497, 2.7441, 5753.3849}, {3418, 2.8289, 3.5231},           {3136, 3.6277, 77713.7715},
    {2676, 4.4181, 7860.4194}, {2343, 6.1352, 3930.2097},        {1324, 0.7425, 11506.7698},
    {1273, 2.0371, 529.691},   {1199, 1.1096, 1577.3435},        {990, 5.233, 5884.927},
    {902, 2.045, 26.298},      {857, 3.508, 398.149},            {780, 1.179, 5223.694},
    {753, 2.533, 5507.553},    {505, 4.583, 18849.228},          {492, 4.205, 775.523},
    {357, 2.92, 0.067},        {317, 5.849, 11790.629},          {284, 1.899, 796.298},
    {271, 0.315, 10977.079},   {243, 0.345, 5486.778},           {206, 4.806, 2544.314},
    {205, 1.869, 5573.143},    {202, 2.458, 6069.777},           {156, 0.833, 213.299},
    {132, 3.411, 2942.463},    {126, 1.083, 20.775},             {115, 0.645, 0.98},
    {103, 0.636, 4694.003},    {102, 0.976, 15720.839},          {102, 4.267, 7.114},
    {99, 6.21, 2146.17},       {98, 0.68, 155.42},               {86, 5.98, 161000.69},
    {85, 1.3, 6275.96},        {85, 3.67, 71430.7},              {80, 1.81, 17260.15},
    {79, 3.04, 12036.46},      {75, 1.76, 5088.63},              {74, 3.5, 3154.69},
    {74, 4.68, 801.82},        {70, 0.83, 9437.76},              {62, 3.98, 8827.39},
    {61, 1.82, 7084.9},        {57, 2.78, 6286.6},               {56, 4.39, 14143.5},
    {56, 3.47, 6279.55},       {52, 0.19, 12139.55},             {52, 1.33, 1748.02},
    {51, 0.28, 5856.48},       {49, 0.49, 1194.45},              {41, 5.37, 8429.24},
    {41, 2.4, 19651.05},       {39, 6.17, 10447.39},             {37, 6.04, 10213.29},
    {37, 2.57, 1059.38},       {36, 1.71, 2352.87},              {36, 1.78, 6812.77},
    {33, 0.59, 17789.85},      {30, 0.44, 83996.85},             {30, 2.74, 1349.87},
    {25, 3.16, 4690.48},
};
constexpr PeriodicTerm kL1[] = {
    {628331966747, 0, 0}, {206059, 2.678235, 6283.07585}, {4303, 2.6351, 12566.1517}, {425, 1.59, 3.523},
    {119, 5.796, 26.298}, {109, 2.966, 1577.344},         {93, 2.59, 18849.23},       {72, 1.14, 529.69},
    {68, 1.87, 398.15},   {67, 4.41, 5507.55},            {59, 2.89, 5223.69},        {56, 2.17, 155.42},
    {45, 0.4, 796.3},     {36, 0.47, 775.52},             {29, 2.65, 7.11},           {21, 5.34, 0.98},
    {19, 1.85, 5486.78},  {19, 4.97, 213.3},              {17, 2.99, 6275.96},        {16, 0.03, 2544.31},
    {16, 1.43, 2146.17},  {15, 1.21, 10977.08},           {12, 2.83, 1748.02},        {12, 3.26, 5088.63},
    {12, 5.27, 1194.45},  {12, 2.08, 4694},               {11, 0.77, 553.57},         {10, 1.3, 6286.6},
    {10, 4.24, 1349.87},  {9, 2.7, 242.73},               {9, 5.64, 951.72},          {8, 5.3, 2352.87},
    {6, 2.65, 9437.76},   {6, 4.67, 4690.48},
};
constexpr PeriodicTerm kL2[] = {
    {52919, 0, 0},      {8720, 1.0721, 6283.0758}, {309, 0.867, 12566.152}, {27, 0.05, 3.52},
    {16, 5.19, 26.3},   {16, 3.68, 155.42},        {10, 0.76, 18849.23},    {9, 2.06, 77713.77},
    {7, 0.83, 775.52},  {5, 4.66, 1577.34},        {4, 1.03, 7.11},         {4, 3.44, 5573.14},
    {3, 5.14, 796.3},   {3, 6.05, 5507.55},        {3, 1.19, 242.73},       {3, 6.12, 529.69},
    {3, 0.31, 398.15},  {3, 2.28, 553.57},         {2, 4.38, 5223.69},      {2, 3.75, 0.98},
};
constexpr PeriodicTerm kL3[] = {
    {289, 5.844, 6283.076}, {35, 0, 0}, {17, 5.49, 12566.15}, {3, 5.2, 155.42},
    {1, 4.72, 3.52},        {1, 5.3, 18849.23}, {1, 5.97, 242.73},
};
constexpr PeriodicTerm kL4[] = {{114, 3.142, 0}, {8, 4.13, 6283.08}, {1, 3.84, 12566.15}};
constexpr PeriodicTerm kL5[] = {{1, 3.14, 0}};

constexpr PeriodicTerm kB0[] = {
    {280, 3.199, 84334.662}, {102, 5.422, 5507.553}, {80, 3.88, 5223.69}, {44, 3.7, 2352.87}, {32, 4, 1577.34},
};
constexpr PeriodicTerm kB1[] = {{9, 3.9, 5507.55}, {6, 1.73, 5223.69}};

constexpr PeriodicTerm kR0[] = {
    {100013989, 0, 0},        {1670700, 3.0984635, 6283.07585}, {13956, 3.05525, 12566.1517},
    {3084, 5.1985, 77713.7715}, {1628, 1.1739, 5753.3849},       {1576, 2.8469, 7860.4194},
    {925, 5.453, 11506.77},   {542, 4.564, 3930.21},            {472, 3.661, 5884.927},
    {346, 0.964, 5507.553},   {329, 5.9, 5223.694},             {307, 0.299, 5573.143},
    {243, 4.273, 11790.629},  {212, 5.847, 1577.344},           {186, 5.022, 10977.079},
    {175, 3.012, 18849.228},  {110, 5.055, 5486.778},           {98, 0.89, 6069.78},
    {86, 5.69, 15720.84},     {86, 1.27, 161000.69},            {65, 0.27, 17260.15},
    {63, 0.92, 529.69},       {57, 2.01, 83996.85},             {56, 5.24, 71430.7},
    {49, 3.25, 2544.31},      {47, 2.58, 775.52},               {45, 5.54, 9437.76},
    {43, 6.01, 6275.96},      {39, 5.36, 4694},                 {38, 2.39, 8827.39},
    {37, 0.83, 19651.05},     {37, 4.9, 12139.55},              {36, 1.67, 12036.46},
    {35, 1.84, 2942.46},      {33, 0.24, 7084.9},               {32, 0.18, 5088.63},
    {32, 1.78, 398.15},       {28, 1.21, 6286.6},               {28, 1.9, 6279.55},
    {26, 4.59, 10447.39},
};
constexpr PeriodicTerm kR1[] = {
    {103019, 1.10749, 6283.07585}, {1721, 1.0644, 12566.1517}, {702, 3.142, 0},     {32, 1.02, 18849.23},
    {31, 2.84, 5507.55},           {25, 1.32, 5223.69},        {18, 1.42, 1577.34}, {10, 5.91, 10977.08},
    {9, 1.42, 6275.96},            {9, 0.27, 5486.78},
};
constexpr PeriodicTerm kR2[] = {
    {4359, 5.7846, 6283.0758}, {124, 5.579, 12566.152}, {12, 3.14, 0},
    {9, 3.63, 77713.77},       {6, 1.87, 5573.14},      {3, 5.47, 18849.23},
};
constexpr PeriodicTerm kR3[] = {{145, 4.273, 6283.076}, {7, 3.92, 12566.15}};
constexpr PeriodicTerm kR4[] = {{4, 2.56, 6283.08}};

constexpr std::span<const PeriodicTerm> kL[] = {kL0, kL1, kL2, kL3, kL4, kL5};
constexpr std::span<const PeriodicTerm> kB[] = {kB0, kB1};
constexpr std::span<const PeriodicTerm> kR[] = {kR0, kR1, kR2, kR3, kR4};

// ---- Table A4.3: nutation in longitude and obliquity. Y0..Y4 multiply X0..X4 (eq. 15–19); a, b (Δψ) and c, d (Δε)
// in 0.0001″.
struct NutationTerm {
  std::array<double, 5> y;
  double a, b, c, d;
};

constexpr NutationTerm kNutation[] = {
    {{0, 0, 0, 0, 1}, -171996, -174.2, 92025, 8.9},
    {{-2, 0, 0, 2, 2}, -13187, -1.6, 5736, -3.1},
    {{0, 0, 0, 2, 2}, -2274, -0.2, 977, -0.5},
    {{0, 0, 0, 0, 2}, 2062, 0.2, -895, 0.5},
    {{0, 1, 0, 0, 0}, 1426, -3.4, 54, -0.1},
    {{0, 0, 1, 0, 0}, 712, 0.1, -7, 0},
    {{-2, 1, 0, 2, 2}, -517, 1.2, 224, -0.6},
    {{0, 0, 0, 2, 1}, -386, -0.4, 200, 0},
    {{0, 0, 1, 2, 2}, -301, 0, 129, -0.1},
    {{-2, -1, 0, 2, 2}, 217, -0.5, -95, 0.3},
    {{-2, 0, 1, 0, 0}, -158, 0, 0, 0},
    {{-2, 0, 0, 2, 1}, 129, 0.1, -70, 0},
    {{0, 0, -1, 2, 2}, 123, 0, -53, 0},
    {{2, 0, 0, 0, 0}, 63, 0, 0, 0},
    {{0, 0, 1, 0, 1}, 63, 0.1, -33, 0},
    {{2, 0, -1, 2, 2}, -59, 0, 26, 0},
    {{0, 0, -1, 0, 1}, -58, -0.1, 32, 0},
    {{0, 0, 1, 2, 1}, -51, 0, 27, 0},
    {{-2, 0, 2, 0, 0}, 48, 0, 0, 0},
    {{0, 0, -2, 2, 1}, 46, 0, -24, 0},
    {{2, 0, 0, 2, 2}, -38, 0, 16, 0},
    {{0, 0, 2, 2, 2}, -31, 0, 13, 0},
    {{0, 0, 2, 0, 0}, 29, 0, 0, 0},
    {{-2, 0, 1, 2, 2}, 29, 0, -12, 0},
    {{0, 0, 0, 2, 0}, 26, 0, 0, 0},
    {{-2, 0, 0, 2, 0}, -22, 0, 0, 0},
    {{0, 0, -1, 2, 1}, 21, 0, -10, 0},
    {{0, 2, 0, 0, 0}, 17, -0.1, 0, 0},
    {{2, 0, -1, 0, 1}, 16, 0, -8, 0},
    {{-2, 2, 0, 2, 2}, -16, 0.1, 7, 0},
    {{0, 1, 0, 0, 1}, -15, 0, 9, 0},
    {{-2, 0, 1, 0, 1}, -13, 0, 7, 0},
    {{0, -1, 0, 0, 1}, -12, 0, 6, 0},
    {{0, 0, 2, -2, 0}, 11, 0, 0, 0},
    {{2, 0, -1, 2, 1}, -10, 0, 5, 0},
    {{2, 0, 1, 2, 2}, -8, 0, 3, 0},
    {{0, 1, 0, 2, 2}, 7, 0, -3, 0},
    {{-2, 1, 1, 0, 0}, -7, 0, 0, 0},
    {{0, -1, 0, 2, 2}, -7, 0, 3, 0},
    {{2, 0, 0, 2, 1}, -7, 0, 3, 0},
    {{2, 0, 1, 0, 0}, 6, 0, 0, 0},
    {{-2, 0, 2, 2, 2}, 6, 0, -3, 0},
    {{-2, 0, 1, 2, 1}, 6, 0, -3, 0},
    {{2, 0, -2, 0, 1}, -6, 0, 3, 0},
    {{2, 0, 0, 0, 1}, -6, 0, 3, 0},
    {{0, -1, 1, 0, 0}, 5, 0, 0, 0},
    {{-2, -1, 0, 2, 1}, -5, 0, 3, 0},
    {{-2, 0, 0, 0, 1}, -5, 0, 3, 0},
    {{0, 0, 2, 2, 1}, -5, 0, 3, 0},
    {{-2, 0, 2, 0, 1}, 4, 0, 0, 0},
    {{-2, 1, 0, 2, 1}, 4, 0, 0, 0},
    {{0, 0, 1, -2, 0}, 4, 0, 0, 0},
    {{-1, 0, 1, 0, 0}, -4, 0, 0, 0},
    {{-2, 1, 0, 0, 0}, -4, 0, 0, 0},
    {{1, 0, 0, 0, 0}, -4, 0, 0, 0},
    {{0, 0, 1, 2, 0}, 3, 0, 0, 0},
    {{0, 0, -2, 2, 2}, -3, 0, 0, 0},
    {{-1, -1, 1, 0, 0}, -3, 0, 0, 0},
    {{0, 1, 1, 0, 0}, -3, 0, 0, 0},
    {{0, -1, 1, 2, 2}, -3, 0, 0, 0},
    {{2, -1, -1, 2, 2}, -3, 0, 0, 0},
    {{0, 0, 3, 2, 2}, -3, 0, 0, 0},
    {{2, -1, 0, 2, 2}, -3, 0, 0, 0},
};
static_assert(std::size(kNutation) == 63);

constexpr double kSunRadiusDeg = 0.26667;           // appendix A.2
constexpr double kHorizonRefractionDeg = 0.5667;    // appendix A.2
constexpr double kSunriseElevationDeg = -(kSunRadiusDeg + kHorizonRefractionDeg);  // h0′ ≈ −0.8333°
constexpr double kEarthRadiusM = 6378140.0;         // eq. 35–36
constexpr double kOneMinusFlattening = 0.99664719;  // eq. 34, 36
constexpr double kMinElevationM = -500.0;
constexpr double kMaxElevationM = 11000.0;

double sinDeg(double deg) { return std::sin(degToRad(deg)); }
double cosDeg(double deg) { return std::cos(degToRad(deg)); }
double asinDeg(double x) { return radToDeg(std::asin(std::clamp(x, -1.0, 1.0))); }
double atan2Deg(double y, double x) { return radToDeg(std::atan2(y, x)); }

// Step 3.2.6: an angle in [0, 360).
double limitDegrees(double deg) {
  const double r = deg - 360.0 * std::floor(deg / 360.0);
  return r >= 360.0 ? 0.0 : r;
}

// Eq. 9–11: Σ_k (Σ_i A cos(B + C·JME)) · JME^k / 1e8, in the unit of A times 1e−8.
double seriesSum(std::span<const std::span<const PeriodicTerm>> series, double jme) {
  double total = 0.0;
  double power = 1.0;
  for (const std::span<const PeriodicTerm> terms : series) {
    double sum = 0.0;
    for (const PeriodicTerm& t : terms) sum += t.a * std::cos(t.b + t.c * jme);
    total += sum * power;
    power *= jme;
  }
  return total / 1e8;
}

// The geocentric apparent sun and the sidereal time: steps 3.1–3.11 without the observer.
struct Geocentric {
  double jd, jde, jc, jce, jme;
  double lDeg, bDeg, rAu, thetaDeg, betaDeg;
  double dPsiDeg, dEpsDeg, epsDeg, lambdaDeg, nuDeg, alphaDeg, deltaDeg;
};

Geocentric geocentricSun(double jd, double deltaTSeconds) {
  Geocentric g{};
  g.jd = jd;
  g.jde = jd + deltaTSeconds / 86400.0;      // eq. 5
  g.jc = (jd - 2451545.0) / 36525.0;         // eq. 6
  g.jce = (g.jde - 2451545.0) / 36525.0;     // eq. 7
  g.jme = g.jce / 10.0;                      // eq. 8
  g.lDeg = limitDegrees(radToDeg(seriesSum(kL, g.jme)));  // eq. 11–12, step 3.2.6
  g.bDeg = radToDeg(seriesSum(kB, g.jme));                // step 3.2.7
  g.rAu = seriesSum(kR, g.jme);                           // step 3.2.8
  g.thetaDeg = limitDegrees(g.lDeg + 180.0);              // eq. 13
  g.betaDeg = -g.bDeg;                                    // eq. 14

  const double t = g.jce;
  const std::array<double, 5> x = {
      297.85036 + 445267.111480 * t - 0.0019142 * t * t + t * t * t / 189474.0,  // eq. 15
      357.52772 + 35999.050340 * t - 0.0001603 * t * t - t * t * t / 300000.0,   // eq. 16
      134.96298 + 477198.867398 * t + 0.0086972 * t * t + t * t * t / 56250.0,   // eq. 17
      93.27191 + 483202.017538 * t - 0.0036825 * t * t + t * t * t / 327270.0,   // eq. 18
      125.04452 - 1934.136261 * t + 0.0020708 * t * t + t * t * t / 450000.0,    // eq. 19
  };
  double dPsi = 0.0;
  double dEps = 0.0;
  for (const NutationTerm& n : kNutation) {
    double arg = 0.0;
    for (std::size_t j = 0; j < 5; ++j) arg += x[j] * n.y[j];
    dPsi += (n.a + n.b * t) * sinDeg(arg);  // eq. 20
    dEps += (n.c + n.d * t) * cosDeg(arg);  // eq. 21
  }
  g.dPsiDeg = dPsi / 36000000.0;  // eq. 22
  g.dEpsDeg = dEps / 36000000.0;  // eq. 23

  const double u = g.jme / 10.0;
  const double eps0 =  // eq. 24, arc seconds
      84381.448 +
      u * (-4680.93 +
           u * (-1.55 +
                u * (1999.25 +
                     u * (-51.38 + u * (-249.67 + u * (-39.05 + u * (7.12 + u * (27.87 + u * (5.79 + u * 2.45)))))))));
  g.epsDeg = eps0 / 3600.0 + g.dEpsDeg;               // eq. 25
  const double dTauDeg = -20.4898 / (3600.0 * g.rAu);  // eq. 26
  g.lambdaDeg = limitDegrees(g.thetaDeg + g.dPsiDeg + dTauDeg);  // eq. 27

  const double nu0 = limitDegrees(280.46061837 + 360.98564736629 * (jd - 2451545.0) + 0.000387933 * g.jc * g.jc -
                                  g.jc * g.jc * g.jc / 38710000.0);  // eq. 28
  g.nuDeg = limitDegrees(nu0 + g.dPsiDeg * cosDeg(g.epsDeg));       // eq. 29

  const double sinLambda = sinDeg(g.lambdaDeg);
  g.alphaDeg = limitDegrees(atan2Deg(sinLambda * cosDeg(g.epsDeg) - std::tan(degToRad(g.betaDeg)) * sinDeg(g.epsDeg),
                                     cosDeg(g.lambdaDeg)));  // eq. 30
  g.deltaDeg = asinDeg(sinDeg(g.betaDeg) * cosDeg(g.epsDeg) +
                       cosDeg(g.betaDeg) * sinDeg(g.epsDeg) * sinLambda);  // eq. 31
  return g;
}

// ---- Input checks (boundaries stay on in release builds).
[[noreturn]] void fail(const std::string& message, std::string hint) {
  throw InputError(SourceLocation{}, message, std::move(hint));
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

void checkRange(double v, double lo, double hi, const char* name, const char* unit, const char* hint) {
  if (!(v >= lo && v <= hi)) {
    fail(std::string(name) + " " + number(v) + " " + unit + " is outside [" + number(lo) + ", " + number(hi) + "]",
         hint);
  }
}

void checkElevation(double elevationM) {
  checkRange(elevationM, kMinElevationM, kMaxElevationM, "elevation", "m",
             "elevation is metres above sea level (the Dead Sea shore is about -430 m, Everest 8849 m)");
}

void checkInput(const SpaInput& in) {
  checkRange(in.latitudeDeg, -90.0, 90.0, "latitude", "degrees",
             "latitude is degrees north of the equator, [-90, 90]; south is negative");
  checkRange(in.longitudeDeg, -180.0, 180.0, "longitude", "degrees",
             "longitude is degrees east of Greenwich, [-180, 180]; west is negative");
  checkElevation(in.elevationM);
  checkUtcTime(in.utc, "time");
  if (!std::isnan(in.deltaTSeconds)) {
    checkRange(in.deltaTSeconds, -1e5, 1e5, "delta T", "s",
               "delta T = TT - UT1 is about 69 s in 2025; leave it unset for the Espenak-Meeus estimate");
  }
  if (!(std::abs(in.dut1Seconds) < 1.0)) {
    fail("UT1 - UTC " + number(in.dut1Seconds) + " s is outside (-1, 1)",
         "UT1 - UTC is kept within 0.9 s by leap seconds (IERS Bulletin A); 0 is within that");
  }
  if (!std::isnan(in.pressureHpa)) {
    checkRange(in.pressureHpa, 0.0, 1200.0, "pressure", "hPa",
               "give the mean air pressure in hPa (1013.25 at sea level), or leave it unset for the standard "
               "atmosphere");
  }
  if (!std::isnan(in.temperatureC)) {
    checkRange(in.temperatureC, -100.0, 100.0, "temperature", "degrees C",
               "give the mean air temperature in degrees Celsius, or leave it unset for the standard atmosphere");
  }
}

double deltaTFor(const SpaInput& in, double jd) {
  // Decimal year from the Julian day (2000.0 = 2000-01-01 0h; mean Gregorian year).
  return std::isnan(in.deltaTSeconds) ? deltaTSeconds(2000.0 + (jd - 2451544.5) / 365.2425) : in.deltaTSeconds;
}

}  // namespace

SpaDetail sunPositionDetail(const SpaInput& in) {
  checkInput(in);
  SpaDetail d;
  d.julianDay = julianDay(in.utc, in.dut1Seconds);  // eq. 4
  d.deltaTSeconds = deltaTFor(in, d.julianDay);
  const Geocentric g = geocentricSun(d.julianDay, d.deltaTSeconds);
  d.julianEphemerisDay = g.jde;
  d.heliocentricLongitudeDeg = g.lDeg;
  d.heliocentricLatitudeDeg = g.bDeg;
  d.radiusVectorAu = g.rAu;
  d.geocentricLongitudeDeg = g.thetaDeg;
  d.geocentricLatitudeDeg = g.betaDeg;
  d.nutationLongitudeDeg = g.dPsiDeg;
  d.nutationObliquityDeg = g.dEpsDeg;
  d.trueObliquityDeg = g.epsDeg;
  d.apparentSunLongitudeDeg = g.lambdaDeg;
  d.apparentSiderealTimeDeg = g.nuDeg;

  const double phi = in.latitudeDeg;
  const double hDeg = limitDegrees(g.nuDeg + in.longitudeDeg - g.alphaDeg);  // eq. 32

  // Eq. 33–39: parallax. u is eq. 34 written with atan2 so that it stays exact at φ = ±90°.
  const double xi = 8.794 / (3600.0 * g.rAu);  // eq. 33
  const double u = std::atan2(kOneMinusFlattening * sinDeg(phi), cosDeg(phi));
  const double x = std::cos(u) + in.elevationM / kEarthRadiusM * cosDeg(phi);                        // eq. 35
  const double y = kOneMinusFlattening * std::sin(u) + in.elevationM / kEarthRadiusM * sinDeg(phi);  // eq. 36
  const double denom = cosDeg(g.deltaDeg) - x * sinDeg(xi) * cosDeg(hDeg);  // > 0.9: |δ| < 24°, x·sin ξ < 5e−5
  const double dAlpha = atan2Deg(-x * sinDeg(xi) * sinDeg(hDeg), denom);     // eq. 37
  d.topocentricRightAscensionDeg = limitDegrees(g.alphaDeg + dAlpha);       // eq. 38
  d.topocentricDeclinationDeg =
      atan2Deg((sinDeg(g.deltaDeg) - y * sinDeg(xi)) * cosDeg(dAlpha), denom);  // eq. 39
  const double hPrime = limitDegrees(hDeg - dAlpha);                            // eq. 40
  d.topocentricHourAngleDeg = hPrime;
  const double deltaPrime = d.topocentricDeclinationDeg;

  // Eq. 41–44: elevation and refraction.
  const double e0 = asinDeg(sinDeg(phi) * sinDeg(deltaPrime) + cosDeg(phi) * cosDeg(deltaPrime) * cosDeg(hPrime));
  d.pressureHpa = std::isnan(in.pressureHpa) ? standardPressureHpa(in.elevationM) : in.pressureHpa;
  d.temperatureC = std::isnan(in.temperatureC) ? standardTemperatureC(in.elevationM) : in.temperatureC;
  double de = 0.0;
  // No refraction once the sun's upper limb is below the refracted horizon (e0 < h0′); above it, e0 + 5.11 > 4
  // and the tangent's argument lies in (1.5°, 90.11°], so eq. 42 stays finite. Above e0 ≈ 89.89° the argument
  // passes 90° and eq. 42 turns slightly negative (at most −3.2e−5° at the zenith); kept as published.
  if (e0 >= kSunriseElevationDeg) {
    de = d.pressureHpa / 1010.0 * 283.0 / (273.0 + d.temperatureC) * 1.02 /
         (60.0 * std::tan(degToRad(e0 + 10.3 / (e0 + 5.11))));  // eq. 42
  }
  SunPosition& p = d.position;
  p.trueZenithDeg = std::clamp(90.0 - e0, 0.0, 180.0);         // eq. 44 without refraction
  p.apparentZenithDeg = std::clamp(90.0 - (e0 + de), 0.0, 180.0);  // eq. 43–44

  // Eq. 45–46: azimuth, eastward from north.
  const double num = sinDeg(hPrime);
  const double den = cosDeg(hPrime) * sinDeg(phi) - std::tan(degToRad(deltaPrime)) * cosDeg(phi);
  const double gamma = std::hypot(num, den) < 1e-11 ? 0.0 : atan2Deg(num, den);  // 1e−11 rad ≈ 1e−9°
  p.azimuthDeg = limitDegrees(gamma + 180.0);

  p.declinationDeg = g.deltaDeg;
  p.rightAscensionDeg = g.alphaDeg;
  p.hourAngleDeg = hDeg;
  p.earthSunDistanceAu = g.rAu;

  // Appendix A.1: equation of time.
  const double jme = g.jme;
  const double m = limitDegrees(280.4664567 + 360007.6982779 * jme + 0.03032028 * jme * jme +
                                jme * jme * jme / 49931.0 - jme * jme * jme * jme / 15300.0 -
                                jme * jme * jme * jme * jme / 2000000.0);  // eq. A2
  const double eMinutes = 4.0 * (m - 0.0057183 - g.alphaDeg + g.dPsiDeg * cosDeg(g.epsDeg));  // eq. A1
  p.equationOfTimeMinutes = eMinutes - 1440.0 * std::round(eMinutes / 1440.0);  // A.1: into (−720, 720]
  return d;
}

SunPosition sunPosition(const SpaInput& in) { return sunPositionDetail(in).position; }

SunTimes sunTimes(const SpaInput& in, double utcOffsetHours) {
  checkInput(in);
  checkRange(utcOffsetHours, -18.0, 18.0, "UTC offset", "hours", "a UTC offset is hours east of Greenwich");
  // The local calendar day: from local midnight (as a UTC instant) for 24 hours.
  const UtcTime local = addHours(in.utc, utcOffsetHours);
  const UtcTime start = addHours(UtcTime{local.year, local.month, local.day, 0, 0, 0.0}, -utcOffsetHours);
  const double jd0 = julianDay(start, in.dut1Seconds);
  const double deltaT = deltaTFor(in, jd0);
  const double phi = in.latitudeDeg;
  const double sigma = in.longitudeDeg;

  // A.2.1–A.2.2: ν at the day's start (UT), α and δ at the same clock reading in TT on the days before, of and
  // after (eq. 4–31 with ΔT = 0).
  const double nu = geocentricSun(jd0, 0.0).nuDeg;
  std::array<double, 3> alpha{}, delta{};
  for (int k = 0; k < 3; ++k) {
    const Geocentric g = geocentricSun(jd0 + (k - 1), 0.0);
    alpha[std::size_t(k)] = g.alphaDeg;
    delta[std::size_t(k)] = g.deltaDeg;
  }

  SunTimes times;
  const auto at = [&](double dayFraction) { return addHours(start, 24.0 * dayFraction); };
  const auto limitZeroOne = [](double v) {
    const double r = v - std::floor(v);
    return r >= 1.0 ? 0.0 : r;
  };
  const double m0 = (alpha[1] - sigma - nu) / 360.0;  // eq. A3

  // Eq. A4 without the division: cos H0 = num / den; |num| ≥ den means the sun never crosses h0′ that day (always
  // at the poles, where den = 0).
  const double num = sinDeg(kSunriseElevationDeg) - sinDeg(phi) * sinDeg(delta[1]);
  const double den = cosDeg(phi) * cosDeg(delta[1]);
  if (num <= -den) {
    times.kind = SunTimes::Kind::kPolarDay;
  } else if (num >= den) {
    times.kind = SunTimes::Kind::kPolarNight;
  }
  const double h0 = times.kind == SunTimes::Kind::kNormal ? radToDeg(std::acos(std::clamp(num / den, -1.0, 1.0))) : 0.0;

  // A.2.5–A.2.7: approximate transit, sunrise and sunset as fractions of the local day.
  const std::array<double, 3> mi = {limitZeroOne(m0), limitZeroOne(m0 - h0 / 360.0), limitZeroOne(m0 + h0 / 360.0)};
  // A.2.10: day-to-day differences. The report limits |a| > 2 into [0, 1), which turns the 360° → 0° wrap of α in
  // March into a wrong 0.0x; wrapping into (−180°, 180°] gives the true daily change.
  const auto wrap180 = [](double deg) { return deg - 360.0 * std::round(deg / 360.0); };
  const double a = wrap180(alpha[1] - alpha[0]);
  const double b = wrap180(alpha[2] - alpha[1]);
  const double aPrime = delta[1] - delta[0];
  const double bPrime = delta[2] - delta[1];
  std::array<double, 3> hPrime{}, deltaPrime{}, altitude{};
  for (std::size_t i = 0; i < 3; ++i) {
    const double nuI = nu + 360.985647 * mi[i];                      // eq. A7
    const double n = mi[i] + deltaT / 86400.0;                       // eq. A8
    const double alphaI = alpha[1] + n * (a + b + (b - a) * n) / 2.0;                  // eq. A9
    deltaPrime[i] = delta[1] + n * (aPrime + bPrime + (bPrime - aPrime) * n) / 2.0;     // eq. A10
    hPrime[i] = wrap180(nuI + sigma - alphaI);                                         // eq. A11, (−180, 180]
    altitude[i] = asinDeg(sinDeg(phi) * sinDeg(deltaPrime[i]) +
                          cosDeg(phi) * cosDeg(deltaPrime[i]) * cosDeg(hPrime[i]));  // eq. A12
  }
  times.transit = at(mi[0] - hPrime[0] / 360.0);  // eq. A13
  if (times.kind == SunTimes::Kind::kNormal) {
    // Eq. A14 (sunrise) and its sunset twin; the correction is skipped where its denominator vanishes (a sun that
    // only grazes h0′, where H′ ≈ 0° or 180°).
    const auto refine = [&](std::size_t i) {
      const double d = 360.0 * cosDeg(deltaPrime[i]) * cosDeg(phi) * sinDeg(hPrime[i]);
      return std::abs(d) > 1e-9 ? mi[i] + (altitude[i] - kSunriseElevationDeg) / d : mi[i];
    };
    times.sunrise = at(refine(1));
    times.sunset = at(refine(2));
  }
  return times;
}

double deltaTSeconds(double y) {
  if (!std::isfinite(y)) fail("decimal year " + number(y) + " is not a number", "give a finite decimal year");
  // Espenak & Meeus, "Five Millennium Canon of Solar Eclipses" (NASA/TP-2006-214141), polynomial expressions.
  const auto parabola = [](double year) {
    const double u = (year - 1820.0) / 100.0;
    return -20.0 + 32.0 * u * u;
  };
  if (y < -500.0 || y >= 2150.0) return parabola(y);
  if (y < 500.0) {
    const double u = y / 100.0;
    return 10583.6 + u * (-1014.41 + u * (33.78311 + u * (-5.952053 + u * (-0.1798452 + u * (0.022174192 +
                                                                                          u * 0.0090316521)))));
  }
  if (y < 1600.0) {
    const double u = (y - 1000.0) / 100.0;
    return 1574.2 + u * (-556.01 + u * (71.23472 + u * (0.319781 + u * (-0.8503463 + u * (-0.005050998 +
                                                                                        u * 0.0083572073)))));
  }
  if (y < 1700.0) {
    const double t = y - 1600.0;
    return 120.0 + t * (-0.9808 + t * (-0.01532 + t / 7129.0));
  }
  if (y < 1800.0) {
    const double t = y - 1700.0;
    return 8.83 + t * (0.1603 + t * (-0.0059285 + t * (0.00013336 - t / 1174000.0)));
  }
  if (y < 1860.0) {
    const double t = y - 1800.0;
    return 13.72 + t * (-0.332447 + t * (0.0068612 + t * (0.0041116 + t * (-0.00037436 + t * (0.0000121272 +
                                                                                             t * (-0.0000001699 +
                                                                                                  t * 0.000000000875))))));
  }
  if (y < 1900.0) {
    const double t = y - 1860.0;
    return 7.62 + t * (0.5737 + t * (-0.251754 + t * (0.01680668 + t * (-0.0004473624 + t / 233174.0))));
  }
  if (y < 1920.0) {
    const double t = y - 1900.0;
    return -2.79 + t * (1.494119 + t * (-0.0598939 + t * (0.0061966 - t * 0.000197)));
  }
  if (y < 1941.0) {
    const double t = y - 1920.0;
    return 21.20 + t * (0.84493 + t * (-0.076100 + t * 0.0020936));
  }
  if (y < 1961.0) {
    const double t = y - 1950.0;
    return 29.07 + t * (0.407 + t * (-1.0 / 233.0 + t / 2547.0));
  }
  if (y < 1986.0) {
    const double t = y - 1975.0;
    return 45.45 + t * (1.067 + t * (-1.0 / 260.0 - t / 718.0));
  }
  if (y < 2005.0) {
    const double t = y - 2000.0;
    return 63.86 + t * (0.3345 + t * (-0.060374 + t * (0.0017275 + t * (0.000651814 + t * 0.00002373599))));
  }
  if (y < 2050.0) {
    const double t = y - 2000.0;
    return 62.92 + t * (0.32217 + t * 0.005589);
  }
  return parabola(y) - 0.5628 * (2150.0 - y);
}

double standardPressureHpa(double elevationM) {
  checkElevation(elevationM);
  return 1013.25 * std::pow(1.0 - 2.25577e-5 * elevationM, 5.25588);
}

double standardTemperatureC(double elevationM) {
  checkElevation(elevationM);
  return 15.0 - 0.0065 * elevationM;
}

}  // namespace fly::sunsky
