// Daylight for hand-built test and benchmark scenes: Helsinki (60.17° N, 24.94° E, Europe/Helsinki) at a local
// time, under a clear sky with the sun.
#pragma once

#include <string>

#include "sdb/scene.h"

namespace fly::test {

inline void setHelsinkiClearSky(sdb::Scene& scene, const std::string& localTime) {
  sdb::Site site;
  site.latitudeDeg = 60.17;
  site.longitudeDeg = 24.94;
  site.timeZone = "Europe/Helsinki";
  scene.setSite(site);
  scene.setTime({localTime});
  sdb::SkySettings sky;
  sky.model = sdb::SkyModel::kClear;
  sky.sun = true;
  scene.setSky(sky);
}

}  // namespace fly::test
