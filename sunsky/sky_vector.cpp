#include "sunsky/sky_vector.h"

#include <algorithm>
#include <cmath>

namespace fly::sunsky {

namespace {

// ∫∫ L dμ dφ over [μ0, μ1] × [φ0, φ1] (φ clockwise from north, radians) by the tensor rule `gl`.
dvec3 integrateRectangle(const Sky& sky, const GaussLegendre& gl, double mu0, double mu1, double phi0,
                         double phi1) {
  const double muHalf = 0.5 * (mu1 - mu0);
  const double muMid = 0.5 * (mu1 + mu0);
  const double phiHalf = 0.5 * (phi1 - phi0);
  const double phiMid = 0.5 * (phi1 + phi0);
  dvec3 sum(0.0);
  for (std::size_t i = 0; i < gl.nodes.size(); ++i) {
    const double mu = muMid + muHalf * gl.nodes[i];
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    dvec3 ring(0.0);
    for (std::size_t j = 0; j < gl.nodes.size(); ++j) {
      const double phi = phiMid + phiHalf * gl.nodes[j];
      ring += gl.weights[j] *
              dvec3(sky.radianceCdM2(dvec3(sinTheta * std::sin(phi), sinTheta * std::cos(phi), mu)));
    }
    sum += gl.weights[i] * ring;
  }
  return sum * (muHalf * phiHalf);
}

// ∫ L dω over patch p, split at the sun (μs, φs) where it lies inside.
dvec3 integratePatch(const Sky& sky, const GaussLegendre& gl, const SkyPatch& p, bool holdsSun, double sunMu,
                     double sunAzimuth) {
  const double mu0 = std::sin(degToRad(p.minAltitudeDeg));
  const double mu1 = p.maxAltitudeDeg >= 90.0 ? 1.0 : std::sin(degToRad(p.maxAltitudeDeg));
  double phi0 = degToRad(p.minAzimuthDeg);
  double phi1 = degToRad(p.maxAzimuthDeg);
  const bool cap = p.maxAltitudeDeg >= 90.0;
  if (cap) {  // the full circle, starting opposite the sun so that the sun's azimuth is its middle
    phi0 = sunAzimuth - kPi;
    phi1 = sunAzimuth + kPi;
  }
  if (!holdsSun) return integrateRectangle(sky, gl, mu0, mu1, phi0, phi1);

  double phiSplit = sunAzimuth;
  while (phiSplit < phi0) phiSplit += 2.0 * kPi;
  while (phiSplit >= phi1) phiSplit -= 2.0 * kPi;
  const double muSplits[3] = {mu0, std::clamp(sunMu, mu0, mu1), mu1};
  const double phiSplits[3] = {phi0, std::clamp(phiSplit, phi0, phi1), phi1};
  dvec3 sum(0.0);
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      if (muSplits[a + 1] > muSplits[a] && phiSplits[b + 1] > phiSplits[b]) {
        sum += integrateRectangle(sky, gl, muSplits[a], muSplits[a + 1], phiSplits[b], phiSplits[b + 1]);
      }
    }
  }
  return sum;
}

}  // namespace

double SkyVector::luminanceCdM2(int i) const {
  const dvec3& c = radianceCdM2[static_cast<std::size_t>(i)];
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;  // BT.709 luminance (base/color.h), in double
}

SkyVector makeSkyVector(const Sky& sky, const SunDisc& sun, const SkyPatches& patches,
                        const SkyVectorOptions& options) {
  checkInputRange("ground albedo", options.groundAlbedo, 0.0, 1.0, "", "give a reflectance from 0 to 1");
  checkInputRange("quadrature nodes per patch axis", options.nodesPerAxis, 1, 32, "",
                  "give a Gauss–Legendre order from 1 to 32");
  const GaussLegendre gl = gaussLegendre(options.nodesPerAxis);

  SkyVector v;
  v.sun = sun;
  v.sunPlacement = options.sun;
  v.radianceCdM2.assign(static_cast<std::size_t>(patches.count()), dvec3(0.0));

  // The sky's peak: the sun the model was computed for (a model may have moved it onto the horizon).
  const dvec3 peak = glm::normalize(sky.sunDirEnu());
  const int peakPatch = patches.patchIndex(peak);
  const double peakMu = peak.z;
  const double peakAzimuth = std::atan2(peak.x, peak.y);
  for (int i = 1; i < patches.count(); ++i) {
    const SkyPatch& p = patches[i];
    v.radianceCdM2[static_cast<std::size_t>(i)] =
        integratePatch(sky, gl, p, i == peakPatch, peakMu, peakAzimuth) / p.solidAngleSr;
  }

  const double sunNormalLux = luminance(sun.normalIlluminanceLux);
  const bool sunUp = sun.dirEnu.z >= 0.0 && sunNormalLux > 0.0;
  v.sunPatch = sunUp ? patches.patchIndex(sun.dirEnu) : kGroundPatch;
  dvec3 groundIrradiance = dvec3(0.0);  // Rec.709 "lux" per channel on the horizontal
  for (int i = 1; i < patches.count(); ++i) {
    groundIrradiance += v.radianceCdM2[static_cast<std::size_t>(i)] * patches[i].projectedSolidAngleSr;
  }
  if (sunUp) {
    groundIrradiance += dvec3(sun.normalIlluminanceLux) * (sun.dirEnu.z / glm::length(sun.dirEnu));
    if (options.sun == SunInPatches::kContainingPatch) {
      v.radianceCdM2[static_cast<std::size_t>(v.sunPatch)] +=
          dvec3(sun.normalIlluminanceLux) / patches[v.sunPatch].solidAngleSr;
    }
  }
  v.radianceCdM2[kGroundPatch] = groundIrradiance * (options.groundAlbedo / kPi);
  return v;
}

double horizontalIlluminanceLux(const SkyVector& vector, const SkyPatches& patches) {
  double sum = 0.0;
  for (int i = 1; i < patches.count(); ++i) sum += vector.luminanceCdM2(i) * patches[i].projectedSolidAngleSr;
  return sum;
}

}  // namespace fly::sunsky
