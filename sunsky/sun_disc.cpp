#include "sunsky/sun_disc.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "sunsky/sky.h"

namespace fly::sunsky {

namespace {

// CIE 1931 2° standard colorimetric observer (CIE 015:2004), 380–780 nm in 10 nm steps.
constexpr int kBands = 41;
constexpr double kFirstWavelengthNm = 380.0;
constexpr double kBandWidthNm = 10.0;
constexpr std::array<double, kBands> kCmfX = {
    0.001368, 0.004243, 0.01431, 0.04351, 0.13438,  0.2839,   0.34828,  0.3362,  0.2908,  0.19536, 0.09564,
    0.03201,  0.0049,   0.0093,  0.06327, 0.1655,   0.2904,   0.43345,  0.5945,  0.7621,  0.9163,  1.0263,
    1.0622,   1.0026,   0.85445, 0.6424,  0.4479,   0.2835,   0.1649,   0.0874,  0.04677, 0.0227,  0.011359,
    0.00579,  0.002899, 0.00144, 0.00069, 0.000332, 0.000166, 0.000083, 0.000042};
constexpr std::array<double, kBands> kCmfY = {
    0.000039, 0.00012,  0.000396, 0.00121,  0.004,   0.0116,  0.023,   0.038,   0.06,  0.09098, 0.13902,
    0.20802,  0.323,    0.503,    0.71,     0.862,   0.954,   0.99495, 0.995,   0.952, 0.87,    0.757,
    0.631,    0.503,    0.381,    0.265,    0.175,   0.107,   0.061,   0.032,   0.017, 0.00821, 0.004102,
    0.002091, 0.001047, 0.00052,  0.000249, 0.00012, 0.00006, 0.00003, 0.000015};
constexpr std::array<double, kBands> kCmfZ = {
    0.00645, 0.02005, 0.06785, 0.2074,  0.6456,  1.3856, 1.74706, 1.77211, 1.6692, 1.28764, 0.81295,
    0.46518, 0.272,   0.1582,  0.07825, 0.04216, 0.0203, 0.00875, 0.0039,  0.0021, 0.00165, 0.0011,
    0.0008,  0.00034, 0.00019, 0.00005, 0.00002, 0.0,    0.0,     0.0,     0.0,    0.0,     0.0,
    0.0,     0.0,     0.0,     0.0,     0.0,     0.0,    0.0,     0.0};

// Ozone absorption coefficient k_o, cm⁻¹, at the same wavelengths: Vigroux's values as tabulated by Iqbal,
// "An Introduction to Solar Radiation" (Academic Press 1983), p. 127 (Chappuis band); the table has no
// entries between 355 and 445 nm, where k_o < 0.003 cm⁻¹ and is taken as 0.
constexpr std::array<double, kBands> kOzoneAbsorption = {
    0.0,   0.0,   0.0,   0.0,   0.0,   0.0,   0.0,   0.003, 0.006, 0.009, 0.014, 0.021, 0.03,  0.04,
    0.048, 0.063, 0.075, 0.085, 0.103, 0.12,  0.12,  0.115, 0.125, 0.12,  0.105, 0.09,  0.079, 0.067,
    0.057, 0.048, 0.036, 0.028, 0.023, 0.018, 0.014, 0.011, 0.010, 0.009, 0.007, 0.004, 0.0};

// Total ozone column, atm-cm (Preetham, Shirley & Smits 1999; a typical mid-latitude value).
constexpr double kOzoneColumnCm = 0.35;

// Air mass of the ozone layer, taken at 22 km: m_o = (1 + h/R) / sqrt(cos²Z + 2h/R), R = 6370 km (Iqbal 1983,
// ch. 5). It stays ≈ 12 at the horizon, where the relative air mass of the whole atmosphere reaches 38.
double ozoneAirMass(double zenithDeg) {
  constexpr double kHeightOverRadius = 22.0 / 6370.0;
  const double cosZ = std::cos(degToRad(zenithDeg));
  return (1.0 + kHeightOverRadius) / std::sqrt(cosZ * cosZ + 2.0 * kHeightOverRadius);
}

// The extraterrestrial solar spectrum as a black body at the Sun's nominal effective temperature, 5772 K
// (IAU 2015 Resolution B3), relative spectral radiance ∝ λ⁻⁵ / (exp(c2 / λT) − 1), c2 = 1.438777·10⁻² m·K.
double solarSpectrum(double wavelengthNm) {
  constexpr double kC2 = 1.438777e-2;
  constexpr double kTemperatureK = 5772.0;
  const double lambdaM = wavelengthNm * 1e-9;
  return 1.0 / (std::pow(lambdaM * 1e6, 5.0) * std::expm1(kC2 / (lambdaM * kTemperatureK)));
}

// Rayleigh optical depth of the standard atmosphere at sea level, λ in µm (Leckner, "The spectral
// distribution of solar radiation at the earth's surface — elements of a model", Solar Energy 20 (1978)
// 143–150).
double rayleighOpticalDepth(double lambdaUm) {
  return 0.008735 * std::pow(lambdaUm, -4.08);
}

// Ångström aerosol optical depth β·λ^−α, α = 1.3 (Ångström's mean), β = 0.04608·T − 0.04586 (Preetham,
// Shirley & Smits 1999, appendix, from turbidity T).
double aerosolOpticalDepth(double lambdaUm, double turbidity) {
  const double beta = 0.04608 * turbidity - 0.04586;
  return beta * std::pow(lambdaUm, -1.3);
}

struct SunColour {
  double transmittanceY;  // luminance-weighted transmittance of the atmosphere, (0, 1]
  double x, y;            // CIE 1931 chromaticity of the transmitted sunlight
};

SunColour transmittedSunlight(double zenithDeg, double turbidity, double pressureHpa) {
  const double airMass = relativeAirMass(zenithDeg);
  const double ozoneMass = ozoneAirMass(zenithDeg);
  const double pressureRatio = pressureHpa / 1013.25;
  double x = 0.0, y = 0.0, z = 0.0, y0 = 0.0;
  for (int k = 0; k < kBands; ++k) {
    const double lambdaNm = kFirstWavelengthNm + kBandWidthNm * k;
    const double lambdaUm = lambdaNm * 1e-3;
    const double opticalDepth =
        pressureRatio * rayleighOpticalDepth(lambdaUm) + aerosolOpticalDepth(lambdaUm, turbidity);
    const double extraterrestrial = solarSpectrum(lambdaNm);
    const double transmitted = extraterrestrial * std::exp(-airMass * opticalDepth -
                                                           ozoneMass * kOzoneColumnCm * kOzoneAbsorption[k]);
    x += transmitted * kCmfX[k];
    y += transmitted * kCmfY[k];
    z += transmitted * kCmfZ[k];
    y0 += extraterrestrial * kCmfY[k];
  }
  const double sum = x + y + z;
  return {y / y0, x / sum, y / sum};
}

// Validates the input and returns the disc's direction.
dvec3 checkedDirection(const SunDiscInput& in) {
  checkInputRange("turbidity", in.turbidity, kMinTurbidity, kMaxTurbidity, "",
                  "Preetham's turbidity: 2 = very clear, 3 = clear, 6 = hazy, 10 = very hazy");
  checkInputRange("pressure", in.pressureHpa, 300.0, 1100.0, " hPa", "give the station pressure in hPa");
  checkInputRange("day of year", in.dayOfYear, 1.0, 366.0, "", "give the day of the year, 1 = 1 January");
  return sunDirectionEnu(in.zenithDeg, in.azimuthDeg);
}

SunDisc discOf(const dvec3& dirEnu, const SunColour& colour, double directNormalLux) {
  SunDisc disc;
  disc.dirEnu = dirEnu;
  disc.normalIlluminanceLux = rec709FromChromaticity(colour.x, colour.y, directNormalLux);
  disc.radianceCdM2 = disc.normalIlluminanceLux / float(sunDiscSolidAngleSr());
  return disc;
}

}  // namespace

double sunDiscSolidAngleSr() {
  return 2.0 * kPi * (1.0 - std::cos(degToRad(kSunAngularDiameterDeg / 2.0)));
}

double eccentricityCorrection(int dayOfYear) {
  checkInputRange("day of year", dayOfYear, 1.0, 366.0, "", "give the day of the year, 1 = 1 January");
  const double dayAngle = 2.0 * kPi * (dayOfYear - 1) / 365.0;  // Γ, radians
  return 1.000110 + 0.034221 * std::cos(dayAngle) + 0.001280 * std::sin(dayAngle) +
         0.000719 * std::cos(2.0 * dayAngle) + 0.000077 * std::sin(2.0 * dayAngle);
}

double relativeAirMass(double zenithDeg) {
  const double z = std::clamp(zenithDeg, 0.0, 90.0);
  return 1.0 / (std::cos(degToRad(z)) + 0.50572 * std::pow(96.07995 - z, -1.6364));
}

SunDisc clearSkySunDisc(const SunDiscInput& in) {
  const dvec3 dir = checkedDirection(in);
  if (in.zenithDeg > 90.0) return SunDisc{dir};  // below the horizon: no light
  const SunColour colour = transmittedSunlight(in.zenithDeg, in.turbidity, in.pressureHpa);
  return discOf(dir, colour,
                kLuminousSolarConstantLux * eccentricityCorrection(in.dayOfYear) * colour.transmittanceY);
}

SunDisc sunDiscWithIlluminance(const SunDiscInput& in, double directNormalLux) {
  const dvec3 dir = checkedDirection(in);
  checkInputRange("direct normal illuminance", directNormalLux, 0.0,
                  kLuminousSolarConstantLux * eccentricityCorrection(in.dayOfYear), " lx",
                  "the direct normal illuminance cannot exceed the extraterrestrial one (133.8 klx at 1 AU)");
  if (in.zenithDeg > 90.0) return SunDisc{dir};  // below the horizon: no light
  return discOf(dir, transmittedSunlight(in.zenithDeg, in.turbidity, in.pressureHpa), directNormalLux);
}

}  // namespace fly::sunsky
