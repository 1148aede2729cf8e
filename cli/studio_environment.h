// The studio environment of `--environment studio` (cli/environment_option.h): a photographer's product
// setup as an equirectangular radiance image in cd/m² (rdb::RasterSky's layout, world +Y up, no sun), made in
// code. A dim grey dome and floor with three rectangular softboxes, luminances typical of diffused studio
// lights (front diffusers of a few thousand cd/m²):
//   dome      above the horizon, 30 cd/m² (a grey cyclorama under the room's spill)
//   floor     below the horizon, 10 cd/m²
//   key       4000 cd/m², centred at azimuth 45° (between +X and +Z), elevation 30°, 30° wide × 40° high
//   fill      1200 cd/m², azimuth 300° (between +X and −Z), elevation 15°, 20° wide × 40° high
//   top strip 2500 cd/m², overhead at elevation 75° towards azimuth 180°, 80° long × 12° across
// Azimuth φ = atan2(z, x) as rdb::RasterSky; a softbox covers the directions whose angles along its two axes,
// seen from its centre direction, lie within its half widths (a rectangle seen from the object).
#pragma once

#include <cstdint>

#include "rdb/raster_sky.h"

namespace fly::cli {

// The studio environment at width × height pixels (each pixel the mean of 4 × 4 directions stratified in φ
// and cos θ, as rdb::buildRasterSky); std::invalid_argument outside [4, 8192] × [2, 4096].
rdb::RasterSky studioEnvironment(uint32_t width = 512, uint32_t height = 256);

}  // namespace fly::cli
