// Hourly illuminance at sensors from their daylight coefficients and a sky matrix: Radiance's two-phase method,
// E(h) = Σ_p DC_p · L_p(h) for each hour's patch radiances L_p (sunsky/sky_matrix.h), with the sun's direct
// part, traced apart (SunInPatches::kSeparate), added from its own series (docs/annual-daylight.md).
//
// The coefficients come from a Monte-Carlo estimate in K independent replicates; each hour's value is the
// mean of the K relit replicates and its standard error their spread, s / √K, so that the error of the
// coefficients reaches every hour honestly (and is shared between hours: annual_metrics.h's bound).
#pragma once

#include <cstddef>
#include <vector>

#include "base/color.h"
#include "daylight/annual_metrics.h"
#include "sunsky/sky_matrix.h"

namespace fly::daylight {

// The illuminance each sensor receives per unit radiance of each patch (sunsky::SkyPatches' numbering,
// patch 0 the ground), per Rec.709 channel (interreflections tint it), in K replicates.
struct DaylightCoefficients {
  int patchCount = 0;           // the patches' count(), ground included
  std::size_t sensorCount = 0;
  int replicates = 1;           // ≥ 1; a standard error needs ≥ 2
  // lux per cd/m², element (k · sensorCount + s) · patchCount + p for replicate k, sensor s, patch p.
  std::vector<Rgb> luxPerCdM2;
};

// The sun's direct illuminance at each sensor and hour (lux, hour-major: element h · sensors + s), with its
// standard errors (empty: exact).
struct SunDirectIlluminance {
  std::vector<double> lux;
  std::vector<double> standardErrorLux;
};

// Per sensor, the luminance part (Y) of its illuminance in each hour of `sky` (lux), with standard errors when
// the coefficients have replicates or the sun's series has errors (combined in quadrature). InputError when
// the patch counts differ, the sizes do not match, or a coefficient or sun value is negative or not finite.
std::vector<IlluminanceSeries> coefficientIlluminance(const DaylightCoefficients& coefficients,
                                                      const sunsky::SkyMatrix& sky,
                                                      const SunDirectIlluminance* sun = nullptr);

}  // namespace fly::daylight
