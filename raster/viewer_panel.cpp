#include "raster/viewer_panel.h"

#include <epoxy/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace fly::raster {

namespace {

std::chrono::year_month_day dateOf(const LocalClock& c) {
  return std::chrono::year(c.year) / std::chrono::month(unsigned(c.month)) /
         std::chrono::day(unsigned(c.day));
}

// The width at which the panel wraps its longer lines (the time label, the probe's reading), pixels.
constexpr float kTextWidth = 250.0f;

constexpr const char* kOperatorNames[] = {"linear", "reinhard", "filmic"};  // ToneOperator's order
constexpr const char* kMonthNames[] = {"Jan", "Feb", "Mar", "Apr", "May", "Jun",
                                       "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"};

}  // namespace

int dayOfYear(const LocalClock& clock) {
  using namespace std::chrono;
  const sys_days d{dateOf(clock)};
  const sys_days jan1{year(clock.year) / January / 1};
  return int((d - jan1).count()) + 1;
}

LocalClock withDayOfYear(const LocalClock& clock, int day) {
  using namespace std::chrono;
  const year y(clock.year);
  day = std::clamp(day, 1, y.is_leap() ? 366 : 365);
  const year_month_day ymd{sys_days{y / January / 1} + days(day - 1)};
  LocalClock c = clock;
  c.month = int(unsigned(ymd.month()));
  c.day = int(unsigned(ymd.day()));
  return c;
}

ViewerPanel::ViewerPanel() {
  ImGuiContext* previous = ImGui::GetCurrentContext();
  context_ = ImGui::CreateContext();
  ImGui::SetCurrentContext(context_);
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini in the user's directory
  io.LogFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui::GetStyle().Alpha = 0.92f;
  // The font atlas, so that frames can be laid out before (or without) the OpenGL3 backend.
  unsigned char* pixels = nullptr;
  int w = 0, h = 0;
  io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
  ImGui::SetCurrentContext(previous ? previous : context_);
}

ViewerPanel::~ViewerPanel() {
  ImGui::SetCurrentContext(context_);
  if (gl_) ImGui_ImplOpenGL3_Shutdown();
  if (window_ != nullptr) ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext(context_);
}

void ViewerPanel::initGl() {
  ImGui::SetCurrentContext(context_);
  if (!gl_) gl_ = ImGui_ImplOpenGL3_Init("#version 450 core");
  if (!gl_) throw std::runtime_error("the viewer's panel: ImGui's OpenGL3 backend did not start");
}

void ViewerPanel::attachWindow(GLFWwindow* window) {
  ImGui::SetCurrentContext(context_);
  if (window_ == nullptr && ImGui_ImplGlfw_InitForOpenGL(window, false)) window_ = window;
}

void ViewerPanel::forwardKey(int key, int scancode, int action, int mods) {
  if (window_ == nullptr) return;
  ImGui::SetCurrentContext(context_);
  ImGui_ImplGlfw_KeyCallback(window_, key, scancode, action, mods);
}

void ViewerPanel::forwardChar(unsigned int codepoint) {
  if (window_ == nullptr) return;
  ImGui::SetCurrentContext(context_);
  ImGui_ImplGlfw_CharCallback(window_, codepoint);
}

void ViewerPanel::forwardMouseButton(int button, int action, int mods) {
  if (window_ == nullptr) return;
  ImGui::SetCurrentContext(context_);
  ImGui_ImplGlfw_MouseButtonCallback(window_, button, action, mods);
}

void ViewerPanel::forwardScroll(double xoffset, double yoffset) {
  if (window_ == nullptr) return;
  ImGui::SetCurrentContext(context_);
  ImGui_ImplGlfw_ScrollCallback(window_, xoffset, yoffset);
}

bool ViewerPanel::wantsKeyboard() const {
  if (!visible_ || !framed_) return false;
  ImGui::SetCurrentContext(context_);
  return ImGui::GetIO().WantCaptureKeyboard;
}

bool ViewerPanel::wantsMouse() const {
  if (!visible_ || !framed_) return false;
  ImGui::SetCurrentContext(context_);
  return ImGui::GetIO().WantCaptureMouse;
}

PanelEdits ViewerPanel::frame(const PanelState& state, float displayWidthPx, float displayHeightPx,
                              float deltaSeconds) {
  PanelEdits edits;
  framed_ = false;
  if (!visible_) return edits;
  ImGui::SetCurrentContext(context_);
  ImGuiIO& io = ImGui::GetIO();
  if (gl_) ImGui_ImplOpenGL3_NewFrame();
  if (window_ != nullptr) {
    ImGui_ImplGlfw_NewFrame();
  } else {
    io.DisplaySize = ImVec2(displayWidthPx, displayHeightPx);
  }
  io.DeltaTime = std::max(deltaSeconds, 1e-4f);
  ImGui::NewFrame();
  framed_ = true;

  // Below the viewer's overlay line, at the left edge.
  ImGui::SetNextWindowPos(ImVec2(8.0f, 28.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("fly view", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings);
  ImGui::PushItemWidth(170.0f);

  if (state.clock) {
    ImGui::TextUnformatted("Sun");
    LocalClock c = *state.clock;
    int day = dayOfYear(c);
    const std::chrono::year y(c.year);
    char dateText[32];
    std::snprintf(dateText, sizeof dateText, "%s %d", kMonthNames[std::clamp(c.month, 1, 12) - 1], c.day);
    if (ImGui::SliderInt("date", &day, 1, y.is_leap() ? 366 : 365, dateText, ImGuiSliderFlags_AlwaysClamp)) {
      edits.clock = withDayOfYear(c, day);
    }
    int minute = c.minuteOfDay;
    char timeText[16];
    std::snprintf(timeText, sizeof timeText, "%02d:%02d", minute / 60, minute % 60);
    const bool timeMoved =
        ImGui::SliderInt("time", &minute, 0, 24 * 60 - 1, timeText, ImGuiSliderFlags_AlwaysClamp);
    // The slider's frame (the item's rectangle also holds its label, to the right).
    const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    layout_.timeSliderMin[0] = lo.x;
    layout_.timeSliderMin[1] = lo.y;
    layout_.timeSliderMax[0] = lo.x + ImGui::CalcItemWidth();
    layout_.timeSliderMax[1] = hi.y;
    if (timeMoved) {
      LocalClock moved = edits.clock.value_or(c);
      moved.minuteOfDay = minute;
      edits.clock = moved;
    }
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + kTextWidth);
    ImGui::TextWrapped("%s", state.timeLabel.c_str());
    ImGui::PopTextWrapPos();
    ImGui::PopStyleColor();
    ImGui::Separator();
  }

  ImGui::TextUnformatted("Mode");
  for (const RenderMode m : state.modes) {
    ImGui::SameLine();
    if (ImGui::RadioButton(renderModeName(m), state.mode == m) && state.mode != m) edits.mode = m;
  }

  bool autoExposure = state.autoExposure;
  if (ImGui::Checkbox("auto exposure", &autoExposure)) edits.autoExposure = autoExposure;
  float ev100 = float(state.tone.ev100);
  if (ImGui::SliderFloat("EV100", &ev100, kPanelMinEv100, kPanelMaxEv100, "%.1f")) edits.ev100 = ev100;
  int op = int(state.tone.op);
  if (ImGui::Combo("operator", &op, kOperatorNames, 3) && op != int(state.tone.op))
    edits.op = ToneOperator(op);
  ImGui::Separator();

  ImGui::TextUnformatted("Camera");
  for (size_t i = 0; i <= state.cameraNames.size(); ++i) {
    const std::string label =
        i < state.cameraNames.size() ? state.cameraNames[i] + "##camera" + std::to_string(i) : "whole scene";
    if (ImGui::Selectable(label.c_str(), state.camera == i) && state.camera != i) edits.camera = i;
  }
  ImGui::Separator();

  ImGui::TextUnformatted("Lux probe");
  if (state.probeAvailable) {
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + kTextWidth);
    ImGui::TextWrapped("%s", state.probeText.empty() ? "click a surface to read the baked illuminance"
                                                     : state.probeText.c_str());
    ImGui::PopTextWrapPos();
  } else {
    ImGui::TextDisabled("no light maps: view a baked directory");
  }
  ImGui::TextDisabled("F1 hides this panel");
  if (state.probeMarker) {  // a ring with a dot where the probe read, over the scene
    const ImVec2 c((*state.probeMarker)[0], (*state.probeMarker)[1]);
    ImDrawList* draw = ImGui::GetForegroundDrawList();
    draw->AddCircle(c, 7.0f, IM_COL32(0, 0, 0, 255), 0, 3.0f);
    draw->AddCircle(c, 7.0f, IM_COL32(255, 220, 0, 255), 0, 1.5f);
    draw->AddCircleFilled(c, 1.5f, IM_COL32(255, 220, 0, 255));
  }

  ImGui::PopItemWidth();
  const ImVec2 wlo = ImGui::GetWindowPos(), wsize = ImGui::GetWindowSize();
  layout_.windowMin[0] = wlo.x;
  layout_.windowMin[1] = wlo.y;
  layout_.windowMax[0] = wlo.x + wsize.x;
  layout_.windowMax[1] = wlo.y + wsize.y;
  ImGui::End();
  ImGui::Render();
  return edits;
}

void ViewerPanel::render() {
  if (!visible_ || !framed_ || !gl_) return;
  ImGui::SetCurrentContext(context_);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace fly::raster
