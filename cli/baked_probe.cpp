#include "cli/baked_probe.h"

#include <cmath>
#include <cstdio>

#include "base/error.h"

namespace fly::cli {

namespace {

std::string pointText(const vec3& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%g, %g, %g)", double(p.x), double(p.y), double(p.z));
  return buf;
}

std::string nodeText(const sdb::Scene& scene, uint32_t sdbNodeId) {
  const auto it = scene.nodes().find(sdb::NodeId{sdbNodeId});
  if (it == scene.nodes().end() || it->second.name.empty()) return "node " + std::to_string(sdbNodeId);
  return "node \"" + it->second.name + "\"";
}

}  // namespace

std::optional<raster::SurfaceHit> sensorSurface(const rdb::RasterRdb& rdb, const vec3& pointWorld,
                                                const vec3& normal, float maxDistanceM) {
  const raster::PickRay ray{pointWorld + maxDistanceM * normal, -normal};
  return raster::pickSurfaceNear(rdb, ray, maxDistanceM, 2.0f * maxDistanceM);
}

std::vector<SensorReading> probeSensors(const rdb::RasterRdb& rdb, const rdb::LightMapStore& store,
                                        const sdb::Scene& scene, const SensorTable& sensors,
                                        float maxDistanceM, const std::string& sensorFile,
                                        const std::string& bakedDir) {
  std::vector<SensorReading> readings;
  for (size_t i = 0; i < sensors.positionsM.size(); ++i) {
    const vec3& p = sensors.positionsM[i];
    const SourceLocation at{sensorFile, sensors.lineNumbers.at(i)};
    const std::string distance = csvNumber(maxDistanceM) + " m";
    const std::optional<raster::SurfaceHit> hit = sensorSurface(rdb, p, sensors.normals[i], maxDistanceM);
    if (!hit) {
      throw InputError(
          at, "no surface within " + distance + " of the point " + pointText(p) + " along its normal",
          "move the point onto a baked surface, or raise --max-distance (default 0.05 m)");
    }
    const std::optional<raster::LuxReading> lux = raster::probeIlluminance(rdb, &store, *hit);
    const std::string node = nodeText(scene, rdb.meshes[hit->mesh].sdbNodeId);
    if (!lux) {
      throw InputError(at,
                       "the surface nearest the point " + pointText(p) + " (" + node + ") has no light map",
                       "move the point onto a baked surface");
    }
    if (!lux->stdErrorLuminanceLux) {
      throw InputError(
          {bakedDir},
          "keeps no standard errors for " + node + " (the point " + pointText(p) + " at " + at.str() + ")",
          "bake the scene again with this fly, which writes them");
    }
    SensorReading r{*lux, std::abs(hit->distanceM - maxDistanceM)};
    if (!std::isfinite(r.lux.illuminanceLuminanceLux) || !std::isfinite(*r.lux.stdErrorLuminanceLux)) {
      throw InputError({bakedDir}, "holds an illuminance or error too large for a float at " + node,
                       "bake the scene again");
    }
    readings.push_back(r);
  }
  return readings;
}

std::string probeCsv(const SensorTable& sensors, const std::vector<SensorReading>& readings) {
  std::string csv = sensors.header + ",illuminance_lux,std_error_lux,source,distance_m\n";
  for (size_t i = 0; i < readings.size(); ++i) {
    const SensorReading& r = readings[i];
    csv += sensors.lines[i] + "," + csvNumber(r.lux.illuminanceLuminanceLux) + "," +
           csvNumber(*r.lux.stdErrorLuminanceLux) + "," +
           (r.lux.fromLightTexture ? "light-texture" : "vertices") + "," +
           csvNumber(std::round(double(r.distanceM) * 1e6) * 1e-6) + "\n";
  }
  return csv;
}

}  // namespace fly::cli
