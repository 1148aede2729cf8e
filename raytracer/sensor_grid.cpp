#include "raytracer/sensor_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace fly::raytracer {

namespace {

// The lattice along one axis: count points spacingM apart, centred on [lo, hi].
struct Axis {
  size_t count = 0;
  double first = 0.0;
};

Axis latticeAxis(float lo, float hi, float spacingM) {
  const double size = double(hi) - double(lo);
  const double n = std::max(1.0, std::floor(size / double(spacingM)));
  return {size_t(n), 0.5 * (double(lo) + double(hi)) - 0.5 * (n - 1.0) * double(spacingM)};
}

// The height of triangle t's plane at (x, z), for a triangle facing up (|n.y| ≥ kFloorMinNormalY): exact for
// a horizontal one, unlike the hit distance, whose error grows with the ray's length.
float planeHeightM(const rdb::TraceRdb& rdb, uint32_t t, const vec3& n, float x, float z) {
  const vec3& p0 = rdb.positionsM[rdb.indices[3 * size_t(t)]];
  return float(double(p0.y) -
               (double(n.x) * (double(x) - p0.x) + double(n.z) * (double(z) - p0.z)) / double(n.y));
}

}  // namespace

double floorGridColumnCount(const rdb::TraceRdb& rdb, float spacingM) {
  if (rdb.boundsM.empty()) return 0.0;
  const double nx = std::max(1.0, std::floor((double(rdb.boundsM.max.x) - rdb.boundsM.min.x) / spacingM));
  const double nz = std::max(1.0, std::floor((double(rdb.boundsM.max.z) - rdb.boundsM.min.z) / spacingM));
  return nx * nz;
}

std::vector<GridSensor> floorSensorGrid(const rdb::TraceRdb& rdb, const EmbreeScene& scene, float heightM,
                                        float spacingM) {
  std::vector<GridSensor> sensors;
  if (rdb.boundsM.empty()) return sensors;
  const Axis ax = latticeAxis(rdb.boundsM.min.x, rdb.boundsM.max.x, spacingM);
  const Axis az = latticeAxis(rdb.boundsM.min.z, rdb.boundsM.max.z, spacingM);
  const vec3 up(0.0f, 1.0f, 0.0f), down(0.0f, -1.0f, 0.0f);
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const float topY = rdb.boundsM.max.y + 1.0f;  // above every triangle
  for (size_t iz = 0; iz < az.count; ++iz) {
    const auto z = float(az.first + double(iz) * double(spacingM));
    for (size_t ix = 0; ix < ax.count; ++ix) {
      const auto x = float(ax.first + double(ix) * double(spacingM));
      // Walk down the vertical line through every surface, moving just below each one hit.
      vec3 origin(x, topY, z);
      while (const std::optional<Hit> hit = scene.intersect(origin, down, kInf)) {
        const vec3 p(x, origin.y - hit->distanceM, z);
        const float magnitudeM = std::max(maxAbs(p), scene.triangleMagnitudeM(hit->triangle));
        if (hit->geometricNormal.y >= kFloorMinNormalY) {
          const vec3 floorPoint(x, planeHeightM(rdb, hit->triangle, hit->geometricNormal, x, z), z);
          // The first surface straight above: none (sky), or a ceiling (facing down) at least heightM away.
          const std::optional<Hit> above =
              scene.intersect(offsetRayOrigin(floorPoint, up, magnitudeM), up, kInf);
          if (!above || (above->geometricNormal.y <= 0.0f && above->distanceM >= heightM)) {
            sensors.push_back({floorPoint + heightM * up, up, floorPoint.y});
          }
        }
        origin = offsetRayOrigin(p, down, magnitudeM);
      }
    }
  }
  const auto key = [](const GridSensor& s) {
    return std::tuple(std::llround(double(s.floorHeightM) * 1e3), s.positionM.z, s.positionM.x,
                      s.floorHeightM);
  };
  std::sort(sensors.begin(), sensors.end(),
            [&key](const GridSensor& a, const GridSensor& b) { return key(a) < key(b); });
  return sensors;
}

}  // namespace fly::raytracer
