// The viewer's on-screen panel (Dear ImGui): date and time of day (the sun and its shadows follow), render
// mode, exposure and tone-mapping operator, the scene's cameras, and the lux probe's reading. The panel only
// shows a PanelState and returns what the user changed as PanelEdits; the viewer (raster/viewer.h) applies
// them as it applies keys. It owns its ImGui context. In a window it takes input through ImGui's GLFW backend
// (attachWindow; the viewer forwards GLFW's callbacks with forwardKey … and keeps the keys and mouse clicks
// the panel does not want); headless (tests) the caller sets the display size and ImGui's input itself.
// Drawing needs the OpenGL3 backend in the current context (initGl); without it the panel still lays out and
// takes input, drawing nothing.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "base/tone_map.h"
#include "raster/renderer.h"

struct GLFWwindow;
struct ImGuiContext;

namespace fly::raster {

// A local civil date and time of day at the scene's site (its time zone).
struct LocalClock {
  int year = 2026, month = 1, day = 1;  // month 1–12, day 1–31 (a valid date)
  int minuteOfDay = 720;                // 0 … 1439

  bool operator==(const LocalClock&) const = default;
};

// Day of the year (1 = 1 January) of a clock's date, and the date of a day of `year` (clamped to the year).
int dayOfYear(const LocalClock& clock);
LocalClock withDayOfYear(const LocalClock& clock, int day);

// What the panel shows.
struct PanelState {
  std::vector<RenderMode> modes;  // supportedModes
  RenderMode mode = RenderMode::kSimple;
  ToneMapSettings tone;
  bool autoExposure = true;
  std::vector<std::string> cameraNames;  // the scene's cameras; index cameraNames.size() = the framing view
  size_t camera = 0;
  std::optional<LocalClock> clock;  // nullopt: the scene has no time of day
  std::string timeLabel;            // e.g. "2026-09-15 17:30 +03:00"
  bool probeAvailable = false;      // the scene has light maps to probe
  std::string probeText;            // the last reading (or why there is none)
  // Where the last reading's point is on the display (pixels from the top left, ImGui's display
  // coordinates), marked with a ring; nullopt: no mark.
  std::optional<std::array<float, 2>> probeMarker;
};

// What the user changed in the panel this frame.
struct PanelEdits {
  std::optional<RenderMode> mode;
  std::optional<bool> autoExposure;
  std::optional<double> ev100;  // a fixed exposure (leaves auto exposure)
  std::optional<ToneOperator> op;
  std::optional<size_t> camera;
  std::optional<LocalClock> clock;

  bool any() const { return mode || autoExposure || ev100 || op || camera || clock; }
};

// The screen rectangles (pixels from the top left) of the panel's window and its time-of-day slider's frame
// (without its label) in the last frame: where clicks go (tests aim at them).
struct PanelLayout {
  float windowMin[2] = {0, 0}, windowMax[2] = {0, 0};
  float timeSliderMin[2] = {0, 0}, timeSliderMax[2] = {0, 0};
};

// The EV100 range of the exposure slider: from a moonlit night (≈ −6) to a sunlit snowfield (≈ 17).
inline constexpr float kPanelMinEv100 = -6.0f;
inline constexpr float kPanelMaxEv100 = 20.0f;

class ViewerPanel {
 public:
  ViewerPanel();
  ~ViewerPanel();
  ViewerPanel(const ViewerPanel&) = delete;
  ViewerPanel& operator=(const ViewerPanel&) = delete;

  // The OpenGL3 backend in the current GL context (4.5 core); the panel then draws in render().
  void initGl();
  // Input from `window` (ImGui's GLFW backend, without installing its callbacks).
  void attachWindow(GLFWwindow* window);
  // GLFW callbacks the viewer forwards while the panel is visible.
  void forwardKey(int key, int scancode, int action, int mods);
  void forwardChar(unsigned int codepoint);
  void forwardMouseButton(int button, int action, int mods);
  void forwardScroll(double xoffset, double yoffset);

  ImGuiContext* context() const { return context_; }

  bool visible() const { return visible_; }
  void setVisible(bool on) { visible_ = on; }

  // Lays out one frame of the panel over a display displayWidthPx × displayHeightPx (ignored with a window:
  // the backend measures it) and returns the user's edits. Hidden, it does nothing and returns none.
  PanelEdits frame(const PanelState& state, float displayWidthPx, float displayHeightPx, float deltaSeconds);
  // Draws the last frame into the bound framebuffer (after the scene; needs initGl). Hidden: nothing.
  void render();

  // ImGui wants the keyboard / mouse this frame (a widget is active or under the mouse): the viewer leaves
  // them to it. False while hidden.
  bool wantsKeyboard() const;
  bool wantsMouse() const;
  const PanelLayout& layout() const { return layout_; }

 private:
  ImGuiContext* context_ = nullptr;
  GLFWwindow* window_ = nullptr;  // attachWindow's
  bool gl_ = false, visible_ = true, framed_ = false;
  PanelLayout layout_;
};

}  // namespace fly::raster
