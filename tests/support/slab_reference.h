// An independent reference for clear glass as a pane (base/clear_pane.h): the slab of two Fresnel faces with
// absorption, written out from the Fresnel equations (Born and Wolf, "Principles of Optics") for the tests.
#pragma once

#include <cmath>

namespace fly::test {

// The slab of index n whose internal transmittance at normal incidence is tau0, at cos θ = c > 0: per
// polarisation the Fresnel reflectance R of one face (θt from Snell's law), τ = τ0^(1 / cos θt), T = (1 − R)²
// τ / (1 − R² τ²); the mean of s and p.
inline double slab(double c, double n, double tau0) {
  const double sinT = std::sqrt(1.0 - c * c) / n;
  const double cosT = std::sqrt(1.0 - sinT * sinT);
  const double rs = (c - n * cosT) / (c + n * cosT);
  const double rp = (n * c - cosT) / (n * c + cosT);
  const double tau = std::pow(tau0, 1.0 / cosT);
  double t = 0.0;
  for (const double r : {rs * rs, rp * rp})
    t += 0.5 * (1.0 - r) * (1.0 - r) * tau / (1.0 - r * r * tau * tau);
  return t;
}

// τ0 with slab(1, n, τ0) = normalT, by bisection (slab(1, n, τ0) increases with τ0); 1 where even the
// lossless slab transmits less.
inline double bisectedTau0(double n, double normalT) {
  if (slab(1.0, n, 1.0) <= normalT) return 1.0;
  double lo = 0.0;
  double hi = 1.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (slab(1.0, n, mid) < normalT ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace fly::test
