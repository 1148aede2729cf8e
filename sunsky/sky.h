// The sky as a light source: radiance in physical units over the upper hemisphere of the site's local frame
// (ENU: x = east, y = north, z = up; directions are unit vectors pointing towards the sky), and the
// integrals every sky model needs (horizontal illuminance, zenith luminance).
//
// Light is linear Rec.709 RGB scaled so that luminance(rgb) is in cd/m² (docs/architecture.md, "Units and frames"). A
// model without colour (CIE, Perez) is neutral: R = G = B = L, the D65 white of Rec.709.
#pragma once

#include <functional>
#include <vector>

#include "base/color.h"
#include "base/math.h"

namespace fly::sunsky {

class Sky {
 public:
  virtual ~Sky();

  // Radiance arriving from `dirEnu` (unit vector towards the sky), cd/m² per channel; 0 below the horizon
  // (dirEnu.z < 0). Never negative, never NaN. Allocation-free.
  virtual Rgb radianceCdM2(const dvec3& dirEnu) const = 0;

  // The sun direction the distribution is computed for (unit, ENU); models that move a sun below the horizon
  // onto it say so. The quadrature below refines around this direction, where skies peak.
  virtual dvec3 sunDirEnu() const = 0;
};

// The unit ENU direction of the sun at apparent zenith angle sunZenithDeg ([0, 180]) and azimuth
// sunAzimuthDeg (degrees clockwise from north, any finite value). InputError for a value out of range or not
// finite.
dvec3 sunDirectionEnu(double sunZenithDeg, double sunAzimuthDeg);

// Boundary check of a model input: unless min ≤ value ≤ max, InputError with `hint` and the message
// "<what> <value><unit> is outside [min, max]" ("is less than min" when max is ±DBL_MAX or infinite, and so
// on; "<what> is not a number" for NaN).
void checkInputRange(const char* what, double value, double min, double max, const char* unit,
                     const char* hint);

// Gauss–Legendre quadrature of order n ≥ 1 on [−1, 1]: nodes ascending, weights summing to 2; exact for
// polynomials of degree ≤ 2n − 1.
struct GaussLegendre {
  std::vector<double> nodes;
  std::vector<double> weights;
};
GaussLegendre gaussLegendre(int n);

// Gauss–Legendre nodes per cos θ panel of the hemisphere quadrature (see integrateHemisphere).
inline constexpr int kDefaultThetaSteps = 32;

// ∫ f(ω) cos θ dω over the upper hemisphere (θ from the zenith), for an f that peaks around `peakDirEnu`.
// Quadrature: μ = cos θ is split into panels [0, μpeak] and [μpeak, 1] with `thetaSteps` Gauss–Legendre nodes
// each, so the kink of a circumsolar peak lies on a panel boundary; azimuth uses the trapezoidal rule
// (spectrally accurate for smooth periodic integrands) on 4·thetaSteps nodes, mapped by
// φ(t) = φpeak + 2πt − α·sin 2πt (α = 0.8) so that nodes are 9× denser at the peak's azimuth than opposite
// it, with one node line through the peak. Used to normalise skies and to measure them.
double integrateHemisphere(const std::function<double(const dvec3&)>& f, const dvec3& peakDirEnu,
                           int thetaSteps = kDefaultThetaSteps);

// Illuminance on an unobstructed horizontal surface from the whole sky, the sun's disc excluded:
// ∫ L cos θ dω, lux, L = luminance(radianceCdM2).
double horizontalIlluminanceLux(const Sky& sky, int thetaSteps = kDefaultThetaSteps);

// Luminance of the sky at the zenith, cd/m².
double zenithLuminanceCdM2(const Sky& sky);

// Linear Rec.709 RGB of a colour given by CIE 1931 chromaticity (x, y), y > 0, and luminance Y ≥ 0, through
// the XYZ → linear sRGB matrix of IEC 61966-2-1:1999 (D65 white), rescaled so that luminance() equals Y
// exactly. Outside the Rec.709 gamut the negative components are first set to 0.
Rgb rec709FromChromaticity(double x, double y, double luminanceY);

}  // namespace fly::sunsky
