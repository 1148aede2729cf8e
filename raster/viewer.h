// The interactive viewer (`fly view`): a GLFW window showing the Renderer's tone-mapped image, walked through
// with a first-person camera (raster/camera_controller.h), with keys for the mode, exposure, operator, time
// of day, camera and screenshots, an overlay line with fps, mode, exposure, operator and local time, and an
// on-screen panel (raster/viewer_panel.h) with the same settings, date and time sliders, the camera list and
// the lux probe (raster/lux_probe.h: a click that does not drag reads the baked illuminance there). What
// needs the scene (the time of day) or files (screenshots) is the caller's, through ViewerHost: raster/ sees
// only the RasterRdb (docs/architecture.md). Scripted runs (a frame count and a list of keys) drive the same
// loop for tests under xvfb-run.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/tone_map.h"
#include "raster/camera_controller.h"
#include "raster/gl_context.h"
#include "raster/lux_probe.h"
#include "raster/renderer.h"
#include "raster/viewer_panel.h"
#include "rdb/raster_rdb.h"

namespace fly::raster {

enum class ViewerAction {
  kModeSimple,
  kModeLightMap,
  kModeSunlight,
  kExposureUp,    // +1/3 EV (leaves auto exposure)
  kExposureDown,  // −1/3 EV
  kAutoExposure,  // toggles auto exposure (the log-luminance histogram, base/tone_map.h)
  kNextOperator,  // linear → reinhard → filmic → linear
  kTimeForward,   // +30 min
  kTimeBack,      // −30 min
  kNextCamera,    // the scene's cameras in order, then the view framing the scene
  kReset,         // the start view and exposure
  kScreenshot,
  kTogglePanel,  // shows or hides the panel
  kQuit,
};

// The key table, as `fly view --help` prints it.
extern const char* const kViewerKeysHelp;

// An action by the name of its key, as `fly view --keys` takes them (case-insensitive): 1 2 3 + - E O T
// shift+T C R P F1 Esc. nullopt for anything else.
std::optional<ViewerAction> parseViewerAction(std::string_view key);

inline constexpr double kExposureStepEv = 1.0 / 3.0;
inline constexpr int kTimeStepMinutes = 30;

// What the viewer asks of its caller.
class ViewerHost {
 public:
  virtual ~ViewerHost() = default;
  // Moves the scene's time of day by `minutes` and brings the RasterRdb the viewer shows up to date
  // (rdb::updateRasterRdb). Returns what changed, to re-upload; nullopt when nothing did. `message`: a line
  // for the user (why the time cannot change), or empty.
  virtual std::optional<rdb::RasterRdbChanges> stepTime(int minutes, std::string& message) = 0;
  // The scene's local date and time for the overlay ("2026-09-15 17:30 +03:00"), or "" without a site.
  virtual std::string timeLabel() const = 0;
  // The scene's local date and time for the panel's sliders; nullopt without a time of day.
  virtual std::optional<LocalClock> localClock() const = 0;
  // Sets the scene's time to `clock` (local civil time at the site) and brings the RasterRdb up to date, as
  // stepTime does; `message` says why the time cannot be set (a time the clock skips at a daylight-saving
  // change, a time the weather file does not cover), or is empty.
  virtual std::optional<rdb::RasterRdbChanges> setLocalClock(const LocalClock& clock,
                                                             std::string& message) = 0;
  // The P key: the tone-mapped image without the overlay, sRGB-encoded RGB8, rows from the top, and the mode
  // and tone mapping (the exposure this frame used) it was drawn with.
  virtual void saveScreenshot(const std::vector<uint8_t>& srgb8, uint32_t widthPx, uint32_t heightPx,
                              RenderMode mode, const ToneMapSettings& tone) = 0;
};

struct ViewerOptions {
  RenderMode mode = RenderMode::kSimple;  // one of supportedModes(rdb)
  std::optional<size_t> camera;           // index into rdb.cameras; nullopt: a view framing the scene
  ToneMapSettings toneMap{ToneOperator::kFilmic, 0.0, 4.0f};
  bool autoExposure = true;  // else toneMap.ev100
  double evCompensation = 0.0;  // stops added to the automatic exposure's brightness (one EV100 less per stop)
  // > 0: close after this many frames and after the script (a scripted run); 0: until Esc or the window
  // closes.
  uint64_t frames = 0;
  std::vector<ViewerAction> script;  // applied one per frame, before the frame is drawn, from the first
  CameraControllerSettings controller;
  SunShadowSettings shadows;  // the sun's shadows (raster/sun_shadows.h)
  BallSettings balls;         // measured materials' ball textures (raster/ball_texture.h)
  AmbientOcclusionSettings ambientOcclusion;  // simple mode's SSAO (raster/ambient_occlusion.h)
  BloomSettings bloom;                        // glare before tone mapping (raster/bloom.h)
  bool panel = true;          // start with the panel shown (F1 toggles it)
  // The baked light maps the RasterRdb was built with, for the lux probe's standard errors; may be null.
  const rdb::LightMapStore* lightMaps = nullptr;
  // Probe the surface under this window point (pixels from the top left) at the first frame, as a click
  // there would (scripted runs).
  std::optional<vec2> probeAtPx;
  // Read back the last frame as the window shows it (overlay and panel included) into ViewerResult.
  bool captureWindow = false;
};

struct ViewerResult {
  uint64_t frames = 0;
  double seconds = 0.0;        // wall clock, first frame to last
  std::vector<uint8_t> srgb8;  // the last frame as saveScreenshot gets it
  uint32_t widthPx = 0, heightPx = 0;
  RenderMode mode = RenderMode::kSimple;
  ToneMapSettings tone;             // the last frame's tone mapping (its exposure, automatic or set)
  std::optional<LuxReading> probe;  // the lux probe's last reading
  std::string probeText;            // … as the panel shows it, or why there is none ("" without a probe)
  // With ViewerOptions::captureWindow: the last frame as the window showed it, sRGB RGB8, rows from the top.
  std::vector<uint8_t> windowSrgb8;
  uint32_t windowWidthPx = 0, windowHeightPx = 0;
};

// The panel's line for a reading: "523 lux ± 4.1 (0.78 %), front, node 3 at (1.20, 0.00, -0.50) m" (whole lux
// from 100 lux up, else 4 significant digits; the standard error to 2).
std::string luxReadingText(const LuxReading& reading);

// Runs the window's loop until Esc, the window's close button, or the end of a scripted run. `rdb` is what
// the renderer shows; `host` updates it in place when the time changes. The window's context must be current.
ViewerResult runViewer(GlfwWindowContext& window, const rdb::RasterRdb& rdb, ViewerHost& host,
                       const ViewerOptions& options);

// One line of text in a 5×7 pixel font: ASCII 32–95 (lower case is drawn as upper case, anything else as
// '?'), white on opaque dark grey. Each character takes a cell of 6×9 font pixels with the glyph at (1, 1)
// from the cell's top left; `scale` screen pixels per font pixel (≥ 1). RGBA8, rows from the top,
// (6 · characters + 1) · scale wide and 9 · scale high.
struct TextImage {
  uint32_t widthPx = 0, heightPx = 0;
  std::vector<uint8_t> rgba8;
};
TextImage rasterizeText(std::string_view text, uint32_t scale);

}  // namespace fly::raster
