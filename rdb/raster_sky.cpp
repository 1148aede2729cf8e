#include "rdb/raster_sky.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rdb/site_lowering.h"

namespace fly::rdb {
namespace {

constexpr uint32_t kMaxSkySize = 8192;
constexpr uint32_t kPixelSamples = 4;  // per axis

// Horizontal illuminance of the sky per channel, lux: ∫ L cos θ dω over the upper hemisphere with sunsky's
// quadrature (the one horizontalIlluminanceLux uses), channel by channel.
Rgb skyHorizontalIlluminanceLux(const sunsky::Sky& sky) {
  Rgb e(0.0f);
  for (int c = 0; c < 3; ++c) {
    e[c] = float(sunsky::integrateHemisphere(
        [&sky, c](const dvec3& d) { return double(sky.radianceCdM2(d)[c]); }, sky.sunDirEnu()));
  }
  return e;
}

}  // namespace

std::optional<RasterSky> buildRasterSky(const sdb::Scene& scene, uint32_t width, uint32_t height) {
  if (width < 1 || width > kMaxSkySize || height < 1 || height > kMaxSkySize) {
    throw std::invalid_argument("buildRasterSky: width and height must be in [1, 8192]");
  }
  const std::optional<SceneDaylight> daylight = lowerDaylight(scene);
  if (!daylight) return std::nullopt;

  RasterSky r;
  r.width = width;
  r.height = height;
  r.sunDirWorld = vec3(daylight->sunDirWorld);
  Rgb groundIrradianceLux(0.0f);  // horizontal illuminance on the ground, sky and sun
  if (daylight->sun) {
    r.hasSun = true;
    r.sunRadianceCdM2 = daylight->sun->radianceCdM2;
    r.sunHalfAngleRad = float(degToRad(sunsky::kSunAngularDiameterDeg / 2.0));
    groundIrradianceLux +=
        daylight->sun->normalIlluminanceLux * float(std::max(0.0, daylight->sunDirWorld.y));
  }
  const sunsky::Sky* sky = daylight->sky.get();
  if (sky) groundIrradianceLux += skyHorizontalIlluminanceLux(*sky);
  r.groundAlbedo = float(daylight->groundAlbedo);
  const dvec3 groundCdM2 = dvec3(groundIrradianceLux) * (daylight->groundAlbedo / kPi);

  r.radianceCdM2.assign(size_t(width) * height, Rgb(0.0f));
  const double n = kPixelSamples;
  for (uint32_t j = 0; j < height; ++j) {
    const double mu0 = std::cos(kPi * j / height), mu1 = std::cos(kPi * (j + 1) / height);  // μ = cos θ = d.y
    for (uint32_t i = 0; i < width; ++i) {
      dvec3 sum(0.0);
      for (uint32_t b = 0; b < kPixelSamples; ++b) {
        const double mu = mu0 + (mu1 - mu0) * (b + 0.5) / n;  // uniform in μ: equal solid angle
        if (mu <= 0.0) {
          sum += groundCdM2 * n;
          continue;
        }
        if (!sky) continue;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        for (uint32_t a = 0; a < kPixelSamples; ++a) {
          const double phi = 2.0 * kPi * (i + (a + 0.5) / n) / width;
          const dvec3 world(sinTheta * std::cos(phi), mu, sinTheta * std::sin(phi));  // φ = atan2(z, x)
          sum += dvec3(sky->radianceCdM2(daylight->frame.enuFromWorld(world)));
        }
      }
      r.radianceCdM2[size_t(j) * width + i] = Rgb(sum / (n * n));
    }
  }
  return r;
}

}  // namespace fly::rdb
