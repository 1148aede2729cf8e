#include "sunsky/sky.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/error.h"
#include "sunsky/site_frame.h"

namespace fly::sunsky {

Sky::~Sky() = default;

namespace {
std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
}  // namespace

void checkInputRange(const char* what, double value, double min, double max, const char* unit,
                     const char* hint) {
  if (value >= min && value <= max) return;
  if (std::isnan(value)) throw InputError({}, std::string(what) + " is not a number", hint);
  constexpr double kUnbounded = std::numeric_limits<double>::max();
  std::string message = std::string(what) + " " + formatNumber(value) + unit;
  if (min <= -kUnbounded && max >= kUnbounded) {
    message += " is not finite";
  } else if (max >= kUnbounded) {
    message += " is less than " + formatNumber(min) + unit;
  } else if (min <= -kUnbounded) {
    message += " is more than " + formatNumber(max) + unit;
  } else {
    message += " is outside [" + formatNumber(min) + unit + ", " + formatNumber(max) + unit + "]";
  }
  throw InputError({}, message, hint);
}

dvec3 sunDirectionEnu(double sunZenithDeg, double sunAzimuthDeg) {
  checkInputRange("sun zenith angle", sunZenithDeg, 0.0, 180.0, "°",
                  "give the apparent zenith angle in degrees: 0 = overhead, 90 = on the horizon");
  checkInputRange("sun azimuth", sunAzimuthDeg, -std::numeric_limits<double>::max(),
                  std::numeric_limits<double>::max(), "°", "give degrees clockwise from north");
  return directionFromAzimuthElevation(sunAzimuthDeg, 90.0 - sunZenithDeg);
}

// Newton's method on the Legendre polynomial P_n from the initial guess cos(π(i + 3/4)/(n + 1/2)) (Abramowitz
// & Stegun 22.16.6), P_n by its three-term recurrence.
GaussLegendre gaussLegendre(int n) {
  if (n < 1) throw std::invalid_argument("gaussLegendre: the order must be at least 1");
  GaussLegendre gl{std::vector<double>(n), std::vector<double>(n)};
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p1 = 1.0;  // P_j(z)
      double p2 = 0.0;  // P_{j−1}(z)
      for (int j = 1; j <= n; ++j) {
        const double p3 = p2;
        p2 = p1;
        p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
      }
      derivative = n * (z * p1 - p2) / (z * z - 1.0);
      const double step = p1 / derivative;
      z -= step;
      if (std::abs(step) < 1e-15) break;
    }
    gl.nodes[i] = -z;
    gl.nodes[n - 1 - i] = z;
    gl.weights[i] = gl.weights[n - 1 - i] = 2.0 / ((1.0 - z * z) * derivative * derivative);
  }
  return gl;
}

double integrateHemisphere(const std::function<double(const dvec3&)>& f, const dvec3& peakDirEnu,
                           int thetaSteps) {
  if (thetaSteps < 2) throw std::invalid_argument("integrateHemisphere: thetaSteps must be at least 2");
  const dvec3 peak = glm::normalize(peakDirEnu);
  const double peakAzimuth = std::hypot(peak.x, peak.y) > 1e-12 ? std::atan2(peak.x, peak.y) : 0.0;

  // Panels in μ = cos θ, split at the peak when it lies strictly inside the upper hemisphere.
  double bounds[3] = {0.0, 1.0, 1.0};
  int panels = 1;
  if (peak.z > 1e-9 && peak.z < 1.0 - 1e-9) {
    bounds[1] = peak.z;
    panels = 2;
  }

  const GaussLegendre gl = gaussLegendre(thetaSteps);
  const int azimuthSteps = 4 * thetaSteps;
  constexpr double kAlpha = 0.8;  // azimuth node clustering, see sky.h
  double sum = 0.0;
  for (int p = 0; p < panels; ++p) {
    const double half = 0.5 * (bounds[p + 1] - bounds[p]);
    const double mid = 0.5 * (bounds[p + 1] + bounds[p]);
    for (int i = 0; i < thetaSteps; ++i) {
      const double mu = mid + half * gl.nodes[i];
      const double sinTheta = std::sqrt(std::max(0.0, 1.0 - mu * mu));
      double ring = 0.0;
      for (int j = 0; j < azimuthSteps; ++j) {
        const double t = 2.0 * kPi * j / azimuthSteps;
        const double phi = peakAzimuth + t - kAlpha * std::sin(t);
        const double dPhi = 1.0 - kAlpha * std::cos(t);
        ring += dPhi * f(dvec3(sinTheta * std::sin(phi), sinTheta * std::cos(phi), mu));
      }
      sum += half * gl.weights[i] * mu * ring * (2.0 * kPi / azimuthSteps);
    }
  }
  return sum;
}

double horizontalIlluminanceLux(const Sky& sky, int thetaSteps) {
  return integrateHemisphere([&sky](const dvec3& dir) { return double(luminance(sky.radianceCdM2(dir))); },
                             sky.sunDirEnu(), thetaSteps);
}

double zenithLuminanceCdM2(const Sky& sky) {
  return luminance(sky.radianceCdM2(dvec3(0.0, 0.0, 1.0)));
}

Rgb rec709FromChromaticity(double x, double y, double luminanceY) {
  if (!(luminanceY > 0.0) || !(y > 0.0)) return Rgb(0.0f);
  const double bigX = x / y * luminanceY;
  const double bigZ = (1.0 - x - y) / y * luminanceY;
  // IEC 61966-2-1:1999 (sRGB): CIE XYZ (D65 white) → linear RGB with the Rec.709 primaries.
  double r = 3.2406 * bigX - 1.5372 * luminanceY - 0.4986 * bigZ;
  double g = -0.9689 * bigX + 1.8758 * luminanceY + 0.0415 * bigZ;
  double b = 0.0557 * bigX - 0.2040 * luminanceY + 1.0570 * bigZ;
  r = std::max(r, 0.0);
  g = std::max(g, 0.0);
  b = std::max(b, 0.0);
  // Rescale so that the BT.709 luminance row reproduces Y exactly (it differs from the matrix's inverse in
  // the fourth decimal, and clamping out-of-gamut components changes it).
  const double y709 = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  if (!(y709 > 0.0)) return Rgb(float(luminanceY));
  const double s = luminanceY / y709;
  return Rgb(float(r * s), float(g * s), float(b * s));
}

}  // namespace fly::sunsky
