#include "cli/view_host.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "base/error.h"
#include "base/image_io.h"
#include "base/log.h"
#include "cli/image_metadata.h"
#include "cli/scene_daylight.h"

namespace fly::cli {

std::string SceneViewHost::noTimeOfDay() const {
  if (environment_) return "the --environment stands in for the sky and sun: the time of day does not change it";
  if (s_.scene.hasSite() && !s_.scene.time().localDateTime.empty()) return "";
  return s_.scene.time().sunDirection ? "no time of day: the sun is placed directly (--sun-dir)"
                                      : "no time of day: the scene has no site";
}

std::optional<rdb::RasterRdbChanges> SceneViewHost::setTime(const std::string& localDateTime,
                                                            std::string& message) {
  const sdb::SiteTime before = s_.scene.time();
  const rdb::LightMapStore* maps = s_.lightMaps ? &*s_.lightMaps : nullptr;
  try {
    return rdb::updateRasterRdb(rdb_, s_.scene, s_.scene.setTime(sdb::SiteTime{localDateTime}), maps);
  } catch (const InputError& e) {  // back to the time before
    message = e.what();
    return rdb::updateRasterRdb(rdb_, s_.scene, s_.scene.setTime(before), maps);
  }
}

std::optional<rdb::RasterRdbChanges> SceneViewHost::stepTime(int minutes, std::string& message) {
  if (message = noTimeOfDay(); !message.empty()) return std::nullopt;
  // Steps in UTC, so that a daylight-saving change neither repeats nor skips a step; the new time carries
  // its offset, which the local clock alone would leave ambiguous in the autumn overlap.
  return setTime(sceneLocalTime(s_.scene, minutes / 60.0), message);
}

std::optional<raster::LocalClock> SceneViewHost::localClock() const {
  if (!noTimeOfDay().empty()) return std::nullopt;
  const std::string t = sceneLocalTime(s_.scene);  // 2026-09-15T17:30:00+03:00
  raster::LocalClock c;
  int hour = 0, minute = 0;
  if (std::sscanf(t.c_str(), "%d-%d-%dT%d:%d", &c.year, &c.month, &c.day, &hour, &minute) != 5)
    return std::nullopt;
  c.minuteOfDay = hour * 60 + minute;
  return c;
}

std::optional<rdb::RasterRdbChanges> SceneViewHost::setLocalClock(const raster::LocalClock& clock,
                                                                  std::string& message) {
  if (message = noTimeOfDay(); !message.empty()) return std::nullopt;
  if (localClock() == clock) return std::nullopt;
  // Local civil time in the site's zone (sunsky/civil_time.h, parseTime).
  char text[32];
  std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d", clock.year, clock.month, clock.day,
                clock.minuteOfDay / 60, clock.minuteOfDay % 60);
  return setTime(text, message);
}

std::string SceneViewHost::timeLabel() const {
  if (!noTimeOfDay().empty()) return "";
  std::string t = sceneLocalTime(s_.scene);  // 2026-09-15T17:30:00+03:00
  std::string label = t.substr(0, 10) + " " + t.substr(11, 5) + " " + t.substr(19);
  // Over a bake that keeps the sun's direct light apart, the indirect light stays as baked.
  if (!s_.bakedSunTime.empty()) label += ", indirect baked at " + s_.bakedSunTime;
  return label;
}

PngMetadata SceneViewHost::screenshotMetadata(const std::string& title, raster::RenderMode mode,
                                              const ToneMapSettings& tone) const {
  ImageSettings settings = daylightSettings(s_.scene);
  char exposure[96];
  std::snprintf(exposure, sizeof exposure, "EV100 %.2f, white point %.2f, tone operator %s", tone.ev100,
                double(tone.whitePoint), toneOperatorName(tone.op));
  settings.insert(settings.end(), {{"fly:scene", s_.scenePath.string()},
                                   {"fly:mode", raster::renderModeName(mode)},
                                   {"fly:exposure", exposure}});
  return imageMetadata(title, settings, dotsPerInch_);
}

void SceneViewHost::saveScreenshot(const std::vector<uint8_t>& srgb8, uint32_t widthPx, uint32_t heightPx,
                                   raster::RenderMode mode, const ToneMapSettings& tone) {
  std::filesystem::path name;
  do {
    char b[32];
    std::snprintf(b, sizeof b, "fly-view-%04d.png", ++counter_);
    name = b;
  } while (std::filesystem::exists(name));
  try {
    writePng(name, int(widthPx), int(heightPx), 3, srgb8.data(), screenshotMetadata("fly view", mode, tone));
    std::cout << "screenshot " << name.string() << " (" << widthPx << "×" << heightPx << ")" << std::endl;
  } catch (const std::exception& e) {  // a full disk or a read-only directory does not end the session
    log::error(std::string("screenshot not saved: ") + e.what());
  }
}

}  // namespace fly::cli
