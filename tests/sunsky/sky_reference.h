// A reference for the sky tests: ∫ L cos θ dω over the upper hemisphere by the midpoint rule in polar
// coordinates about the sun (the circumsolar peak is smooth there; the horizon cuts the grid), independent
// of the Gauss–Legendre quadrature that normalises the skies.
#pragma once

#include <cmath>

#include "sunsky/sky.h"

namespace fly::sunsky::testing {

inline double referenceHorizontalIlluminanceLux(const Sky& sky, int steps = 200) {
  const dvec3 p = sky.sunDirEnu();
  const dvec3 u =
      glm::normalize(glm::cross(p, std::abs(p.z) < 0.9 ? dvec3(0.0, 0.0, 1.0) : dvec3(1.0, 0.0, 0.0)));
  const dvec3 v = glm::cross(p, u);
  const double h = kPi / steps;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double gamma = (i + 0.5) * h;
    double ring = 0.0;
    for (int j = 0; j < 2 * steps; ++j) {
      const double psi = (j + 0.5) * h;
      const dvec3 d = std::cos(gamma) * p + std::sin(gamma) * (std::cos(psi) * u + std::sin(psi) * v);
      if (d.z > 0.0) ring += luminance(sky.radianceCdM2(d)) * d.z;
    }
    sum += ring * std::sin(gamma);
  }
  return sum * h * h;
}

}  // namespace fly::sunsky::testing
