#include "raster/room_probe.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fly::raster {

namespace {

// Near plane of the probe's faces, m: closer than this to the eye nothing is reflected that matters.
constexpr float kProbeNearM = 0.02f;

}  // namespace

RoomProbe::RoomProbe(EnvironmentLight::Compile compile) : cube_(std::move(compile)) {}

float RoomProbe::sideDistanceM(const std::vector<float>& depth, uint32_t facePx, float nearM) {
  // Window depth z of an infinite-far perspective view: z = 1 − n / d, d the distance along the view axis.
  std::vector<float> distances;
  size_t central = 0;
  const uint32_t lo = facePx / 4, hi = facePx - facePx / 4;
  for (uint32_t y = lo; y < hi; ++y) {
    for (uint32_t x = lo; x < hi; ++x) {
      ++central;
      const float z = depth[size_t(y) * facePx + x];
      if (z < 1.0f) distances.push_back(nearM / std::max(1.0f - z, std::numeric_limits<float>::min()));
    }
  }
  if (distances.size() * 2 <= central) return kOpenSideM;  // mostly sky
  // The median of the central half, sky counted as beyond everything.
  const size_t k = central / 2;
  std::nth_element(distances.begin(), distances.begin() + std::ptrdiff_t(k), distances.end());
  return std::min(distances[k], kOpenSideM);
}

void RoomProbe::capture(const vec3& centreM, const std::function<Face(const View&)>& drawFace) {
  std::array<float, 6> side{};
  uint32_t face = 0;
  cube_.capture(0, centreM, kProbeNearM, std::numeric_limits<float>::infinity(), [&](const View& view) {
    const Face drawn = drawFace(view);
    side[face++] = sideDistanceM(drawn.depth, facePx(), kProbeNearM);
    return CubeReflections::Face{drawn.luminance};
  });
  centreM_ = centreM;
  boxMaxM_ = centreM + vec3(side[0], side[2], side[4]);
  boxMinM_ = centreM - vec3(side[1], side[3], side[5]);
  captured_ = true;
}

}  // namespace fly::raster
