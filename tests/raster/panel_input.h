// Headless input for the viewer's panel in tests: frames of ImGui's own headless setup (a display size, no
// platform backend) with the mouse placed and pressed by the test, and where a click on the time-of-day
// slider lands by ImGui's slider geometry.
#pragma once

#include <imgui.h>

#include <cfloat>
#include <cmath>

#include "raster/viewer_panel.h"

namespace fly::raster::test {

inline constexpr float kPanelDisplayW = 640.0f, kPanelDisplayH = 360.0f;

// One panel frame with the mouse at (x, y) (pixels from the top left; outside the display: none) and its
// left button down or up.
inline PanelEdits panelFrame(ViewerPanel& panel, const PanelState& state, float x, float y, bool down) {
  ImGui::SetCurrentContext(panel.context());
  ImGuiIO& io = ImGui::GetIO();
  io.MousePos = x >= 0.0f ? ImVec2(x, y) : ImVec2(-FLT_MAX, -FLT_MAX);
  io.MouseDown[0] = down;
  return panel.frame(state, kPanelDisplayW, kPanelDisplayH, 1.0f / 60.0f);
}

// Two frames without the mouse: ImGui hides an auto-sized window in its first frame while it measures it.
inline void layOut(ViewerPanel& panel, const PanelState& state) {
  panelFrame(panel, state, -1.0f, -1.0f, false);
  panelFrame(panel, state, -1.0f, -1.0f, false);
}

// The time slider's minute under the window x coordinate `x`: ImGui 1.86's horizontal slider
// (SliderBehaviorT) keeps 2 px of padding at each end and a grab of style.GrabMinSize (its range of 1440
// values is wider than the slider), and maps the grab's centre linearly over what remains, rounding to the
// nearest integer.
inline int timeSliderMinuteAt(const PanelLayout& layout, float x) {
  const float grab = ImGui::GetStyle().GrabMinSize, pad = 2.0f;
  const float lo = layout.timeSliderMin[0] + pad + 0.5f * grab;
  const float usable = layout.timeSliderMax[0] - layout.timeSliderMin[0] - 2.0f * pad - grab;
  const float t = (x - lo) / usable;
  return int(t * 1439.0f + 0.5f);
}

// Clicks the time slider at fraction f of its frame's width (three frames: lay out, press, release) and
// returns the panel's edits of the press.
inline PanelEdits clickTimeSlider(ViewerPanel& panel, const PanelState& state, float f, int& expectedMinute) {
  layOut(panel, state);
  const PanelLayout& l = panel.layout();
  // ImGui rounds the mouse position down to whole pixels (NewFrame, UpdateMouseInputs).
  const float x = std::floor(l.timeSliderMin[0] + f * (l.timeSliderMax[0] - l.timeSliderMin[0]));
  const float y = 0.5f * (l.timeSliderMin[1] + l.timeSliderMax[1]);
  expectedMinute = timeSliderMinuteAt(l, x);
  panelFrame(panel, state, x, y, false);  // hover first, as a real mouse does
  const PanelEdits edits = panelFrame(panel, state, x, y, true);
  panelFrame(panel, state, x, y, false);
  return edits;
}

}  // namespace fly::raster::test
