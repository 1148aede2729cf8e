// `fly probe`: a bake's light maps read at sensor points as the viewer's lux probe reads them
// (raster/lux_probe.h), on the surface nearest each point along the sensor's normal.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "base/math.h"
#include "cli/sensor_csv.h"
#include "raster/lux_probe.h"
#include "rdb/light_map_store.h"
#include "rdb/raster_rdb.h"
#include "sdb/scene.h"

namespace fly::cli {

// The surface nearest `pointWorld` along the unit `normal`, within maxDistanceM (> 0) on either side: of the
// hits of a ray from point + normal·d towards −normal, the one nearest the point. Its `back` is then the side
// `normal` faces (the ray meets a surface's back exactly when normal points to that back). nullopt when none
// is that close.
std::optional<raster::SurfaceHit> sensorSurface(const rdb::RasterRdb& rdb, const vec3& pointWorld,
                                                const vec3& normal, float maxDistanceM);

struct SensorReading {
  raster::LuxReading lux;  // stdErrorLuminanceLux is set
  float distanceM = 0.0f;  // from the sensor's point to the surface read
};

// Every sensor's reading (sensors.lineNumbers given). InputError naming `sensorFile`, the line and the point
// when no surface lies within maxDistanceM or the surface found has no light map; naming `bakedDir` when the
// bake kept no standard errors there. `scene` names the nodes in the messages.
std::vector<SensorReading> probeSensors(const rdb::RasterRdb& rdb, const rdb::LightMapStore& store,
                                        const sdb::Scene& scene, const SensorTable& sensors,
                                        float maxDistanceM, const std::string& sensorFile,
                                        const std::string& bakedDir);

// The output: the sensor rows as written with fly illuminance's columns illuminance_lux,std_error_lux (lux,
// the luminance), then source ("vertices" or "light-texture") and distance_m (metres, to the micrometre:
// finer digits would be the float positions' rounding).
std::string probeCsv(const SensorTable& sensors, const std::vector<SensorReading>& readings);

}  // namespace fly::cli
