// What `fly view`'s window asks of the scene (raster::ViewerHost): the time of day — stepped by keys or set
// by the panel's date and time sliders — applied to the SDB scene and carried into the RasterRdb the viewer
// shows (sdb::Scene::setTime → ChangeSet → rdb::updateRasterRdb → Renderer::update), the local time for the
// overlay and the panel, and numbered screenshots.
#pragma once

#include <optional>
#include <string>

#include "base/png_metadata.h"
#include "base/tone_map.h"
#include "cli/raster_scene.h"
#include "raster/viewer.h"
#include "rdb/raster_rdb.h"

namespace fly::cli {

class SceneViewHost : public raster::ViewerHost {
 public:
  // `rdb` was built from scene.scene (with scene.lightMaps); both outlive the host. environment: an
  // --environment stands in for the sky and the sun, so the time of day has nothing to change.
  // dotsPerInch: the screenshots' print resolution (--dpi; 0 = none).
  SceneViewHost(RasterScene& scene, rdb::RasterRdb& rdb, bool environment = false, double dotsPerInch = 0.0)
      : s_(scene), rdb_(rdb), environment_(environment), dotsPerInch_(dotsPerInch) {}

  std::optional<rdb::RasterRdbChanges> stepTime(int minutes, std::string& message) override;
  std::string timeLabel() const override;
  std::optional<raster::LocalClock> localClock() const override;
  std::optional<rdb::RasterRdbChanges> setLocalClock(const raster::LocalClock& clock,
                                                     std::string& message) override;
  // fly-view-NNNN.png in the current directory (the first free number); a failure is logged, not thrown.
  void saveScreenshot(const std::vector<uint8_t>& srgb8, uint32_t widthPx, uint32_t heightPx,
                      raster::RenderMode mode, const ToneMapSettings& tone) override;
  // A screenshot's metadata (cli/image_metadata.h): the scene's daylight at the time shown (the keys or the
  // panel may have changed it), the scene, the mode, the exposure and the print resolution.
  PngMetadata screenshotMetadata(const std::string& title, raster::RenderMode mode,
                                 const ToneMapSettings& tone) const;

 private:
  // Why the scene has no time to change ("" when it has one).
  std::string noTimeOfDay() const;
  // Sets the scene's time to `localDateTime`; on an InputError (a time the weather file does not cover, one
  // the clock skips) puts the time before back and returns the error as `message`.
  std::optional<rdb::RasterRdbChanges> setTime(const std::string& localDateTime, std::string& message);

  RasterScene& s_;
  rdb::RasterRdb& rdb_;
  bool environment_;
  double dotsPerInch_;
  int counter_ = 0;
};

}  // namespace fly::cli
