// The sky dome as a hemispherical fisheye image, as an all-sky camera looking straight up sees it:
// equidistant (angular) projection, the zenith at the centre, the horizon on the inscribed circle, north up
// and east on the LEFT (the view from below). Pixels hold radiance in cd/m² (linear Rec.709); outside the
// circle 0.
#pragma once

#include <optional>

#include "base/image_io.h"
#include "base/math.h"
#include "sunsky/sky.h"
#include "sunsky/sun_disc.h"

namespace fly::cli {

// Direction (unit, ENU) seen at image position (u, v) ∈ [0, size)² measured from the top-left corner in
// pixels; nullopt outside the horizon circle.
std::optional<dvec3> fisheyeDirection(double u, double v, int size);

// Solid angle (sr) that a pixel whose centre looks at zenith angle θ covers: (π/size)² · sin θ / θ
// (the Jacobian of the equidistant projection, pixel side 2/size in units of the circle's radius).
double fisheyePixelSolidAngle(double thetaRad, int size);

// Renders the sky (2×2 samples per pixel) and, when given, the sun's disc: its normal illuminance is spread
// over the pixels whose centres lie inside the disc (at least the pixel its centre falls into), so that
// Σ L·cos θ·Ω over the image reproduces the global horizontal illuminance.
ImageRgbF renderSkyFisheye(const sunsky::Sky& sky, const std::optional<sunsky::SunDisc>& sun, int size);

// Σ luminance · cos θ · Ω over the image's pixels, lux: the horizontal illuminance the image represents.
double fisheyeHorizontalIlluminanceLux(const ImageRgbF& image);

}  // namespace fly::cli
