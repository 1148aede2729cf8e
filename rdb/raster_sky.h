// The sky dome the GL engine draws in sunlight mode: the scene's sunsky sky for its site and local time (its
// colours follow the sun, from dawn to noon) tabulated as an equirectangular image in world directions, and
// the sun's disc as parameters for the shader. Built from rdb::lowerDaylight, as the TraceRdb's sky and sun
// are, so the baker and the GL engine see the same daylight.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "sdb/scene.h"
#include "sunsky/hosek_wilkie.h"

namespace fly::rdb {

// Reflectance of the ground drawn below the horizon by default (sdb::SkySettings::groundAlbedo: grey, a
// common default for grass, soil and pavement), the ground albedo the clear sky assumes.
inline constexpr float kRasterGroundAlbedo = float(sunsky::kDefaultGroundAlbedo);

// An equirectangular image over the full sphere of WORLD directions (glTF frame, +Y up). For a unit direction
// d: φ = atan2(d.z, d.x) wrapped to [0, 2π), θ = acos(d.y) the polar angle from +Y. Pixel (i, j) at
// radianceCdM2[j·width + i] covers φ ∈ [2π·i/width, 2π·(i+1)/width) and θ ∈ [π·j/height, π·(j+1)/height)
// (row 0 at the zenith) and holds the mean radiance over the pixel's solid angle, cd/m² per channel (linear
// Rec.709, luminance() photometric). Above the horizon (d.y > 0) it is the sky; the sun's disc is NOT in the
// image (the shader draws it from sunDirWorld, sunRadianceCdM2 and sunHalfAngleRad). Below the horizon it is
// a uniform Lambertian ground of reflectance groundAlbedo lit by the whole sky and the sun: albedo ·
// (E_sky + E_sun) / π per channel, E the horizontal illuminance in lux. This ground is only what a viewer
// sees where the scene has no geometry; the baker's sky (TraceSky) is black below the horizon.
struct RasterSky {
  uint32_t width = 0, height = 0;
  std::vector<Rgb> radianceCdM2;  // width·height pixels, row-major from the zenith row
  bool hasSun = false;            // the scene has a sun and it is above the horizon
  vec3 sunDirWorld{0, 1, 0};      // unit, towards the sun's apparent position (also when below the horizon)
  Rgb sunRadianceCdM2{0};         // mean radiance of the disc, cd/m² per channel; 0 without hasSun
  float sunHalfAngleRad = 0;      // angular radius of the disc (0.533° / 2); 0 without hasSun
  float groundAlbedo = kRasterGroundAlbedo;  // the ground's below the horizon (sdb::SkySettings::groundAlbedo)
};

// The sky dome of `scene` at `width` × `height` pixels (each in [1, 8192]; std::invalid_argument outside),
// or nullopt when the scene has neither a sky nor a sun. A sun without a sky model gives a black sky above
// the horizon. Each pixel averages 4 × 4 directions stratified in φ and cos θ (equal solid angle). Errors of
// lowerDaylight (InputError for a bad site, time or weather file) pass through.
std::optional<RasterSky> buildRasterSky(const sdb::Scene& scene, uint32_t width = 256, uint32_t height = 128);

}  // namespace fly::rdb
