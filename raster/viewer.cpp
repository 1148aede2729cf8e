#include "raster/viewer.h"

#include <epoxy/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <string>

#include "base/log.h"

namespace fly::raster {

const char* const kViewerKeysHelp =
    "Keys:\n"
    "  W A S D, arrows  walk (1.4 m/s; Shift: run, 4.2 m/s)   PageUp/PageDown  rise/sink\n"
    "  left mouse drag  look around                  left click  lux probe (baked scenes)\n"
    "  1 2 3            mode simple / lightmap / sunlight (those the scene supports)\n"
    "  + -              exposure ±1/3 EV             E  auto exposure on/off (histogram)\n"
    "  O                tone-mapping operator: linear, reinhard, filmic\n"
    "  T, Shift+T       time of day ±30 min (scenes with a site)\n"
    "  C                next camera (the scene's cameras, then a view framing the scene)\n"
    "  R                back to the start view and exposure\n"
    "  P                screenshot fly-view-NNNN.png in the current directory (without the overlay)\n"
    "  F1               show or hide the panel (date and time, mode, exposure, cameras, lux probe)\n"
    "  Esc              quit";

std::optional<ViewerAction> parseViewerAction(std::string_view key) {
  std::string k;
  for (char c : key) k += char(std::tolower(static_cast<unsigned char>(c)));
  if (k == "1") return ViewerAction::kModeSimple;
  if (k == "2") return ViewerAction::kModeLightMap;
  if (k == "3") return ViewerAction::kModeSunlight;
  if (k == "+") return ViewerAction::kExposureUp;
  if (k == "-") return ViewerAction::kExposureDown;
  if (k == "e") return ViewerAction::kAutoExposure;
  if (k == "o") return ViewerAction::kNextOperator;
  if (k == "t") return ViewerAction::kTimeForward;
  if (k == "shift+t") return ViewerAction::kTimeBack;
  if (k == "c") return ViewerAction::kNextCamera;
  if (k == "r") return ViewerAction::kReset;
  if (k == "p") return ViewerAction::kScreenshot;
  if (k == "f1") return ViewerAction::kTogglePanel;
  if (k == "esc") return ViewerAction::kQuit;
  return std::nullopt;
}

namespace {

// The 5×7 glyphs of ASCII 0x20–0x5F: 35 bits each, row by row from the top, 5 bits a row with the leftmost
// column in the row's highest bit.
constexpr std::array<uint64_t, 64> kFont5x7 = {
    0x000000000ULL, 0x108421004ULL, 0x294000000ULL, 0x295F57D4AULL,  // space ! " #
    0x11F4717C4ULL, 0x632222263ULL, 0x32544564DULL, 0x108000000ULL,  // $ % & '
    0x088842082ULL, 0x208210888ULL, 0x009575480ULL, 0x0084F9080ULL,  // ( ) * +
    0x000003088ULL, 0x0000F8000ULL, 0x00000018CULL, 0x002222200ULL,  // , - . /
    0x3A33AE62EULL, 0x11842108EULL, 0x3A211111FULL, 0x7C441062EULL,  // 0 1 2 3
    0x08CA97C42ULL, 0x7E1E0862EULL, 0x1910F462EULL, 0x7C2222108ULL,  // 4 5 6 7
    0x3A317462EULL, 0x3A317844CULL, 0x018C03180ULL, 0x018C03088ULL,  // 8 9 : ;
    0x088882082ULL, 0x001F07C00ULL, 0x208208888ULL, 0x3A2111004ULL,  // < = > ?
    0x3A216D6AEULL, 0x3A31FC631ULL, 0x7A31F463EULL, 0x3A308422EULL,  // @ A B C
    0x72518C65CULL, 0x7E10F421FULL, 0x7E10F4210ULL, 0x3A30BC62FULL,  // D E F G
    0x4631FC631ULL, 0x38842108EULL, 0x1C4210A4CULL, 0x4654C5251ULL,  // H I J K
    0x42108421FULL, 0x4775AC631ULL, 0x4639ACE31ULL, 0x3A318C62EULL,  // L M N O
    0x7A31F4210ULL, 0x3A318D64DULL, 0x7A31F5251ULL, 0x3E107043EULL,  // P Q R S
    0x7C8421084ULL, 0x46318C62EULL, 0x46318C544ULL, 0x4631AD6AAULL,  // T U V W
    0x462A22A31ULL, 0x462A21084ULL, 0x7C222221FULL, 0x39084210EULL,  // X Y Z [
    0x020820820ULL, 0x38421084EULL, 0x115100000ULL, 0x00000001FULL,  // \ ] ^ _
};

constexpr uint32_t kCellW = 6, kCellH = 9;

}  // namespace

TextImage rasterizeText(std::string_view text, uint32_t scale) {
  scale = std::max<uint32_t>(scale, 1);
  TextImage img;
  img.widthPx = (kCellW * uint32_t(text.size()) + 1) * scale;
  img.heightPx = kCellH * scale;
  img.rgba8.assign(size_t(img.widthPx) * img.heightPx * 4, 0);
  for (size_t i = 0; i < img.rgba8.size(); i += 4) {
    img.rgba8[i] = img.rgba8[i + 1] = img.rgba8[i + 2] = 32;
    img.rgba8[i + 3] = 255;
  }
  for (size_t n = 0; n < text.size(); ++n) {
    int c = std::toupper(static_cast<unsigned char>(text[n]));
    if (c < 0x20 || c > 0x5F) c = '?';
    const uint64_t glyph = kFont5x7[size_t(c - 0x20)];
    for (uint32_t row = 0; row < 7; ++row) {
      for (uint32_t col = 0; col < 5; ++col) {
        if (!((glyph >> ((6 - row) * 5 + (4 - col))) & 1u)) continue;
        const uint32_t x0 = (kCellW * uint32_t(n) + 1 + col) * scale, y0 = (1 + row) * scale;
        for (uint32_t y = y0; y < y0 + scale; ++y) {
          for (uint32_t x = x0; x < x0 + scale; ++x) {
            uint8_t* p = &img.rgba8[(size_t(y) * img.widthPx + x) * 4];
            p[0] = p[1] = p[2] = 255;
          }
        }
      }
    }
  }
  return img;
}

namespace {

// Key presses arrive through GLFW's callback between frames; they wait here in order. While the panel is
// shown, GLFW's input goes to it too, and keys it wants (a slider being typed into) go only to it.
struct KeyQueue {
  std::deque<ViewerAction> actions;
  ViewerPanel* panel = nullptr;
};

KeyQueue* queueOf(GLFWwindow* window) {
  return static_cast<KeyQueue*>(glfwGetWindowUserPointer(window));
}

void onChar(GLFWwindow* window, unsigned int codepoint) {
  if (KeyQueue* q = queueOf(window); q && q->panel && q->panel->visible()) q->panel->forwardChar(codepoint);
}

void onMouseButton(GLFWwindow* window, int button, int action, int mods) {
  if (KeyQueue* q = queueOf(window); q && q->panel && q->panel->visible())
    q->panel->forwardMouseButton(button, action, mods);
}

void onScroll(GLFWwindow* window, double xoffset, double yoffset) {
  if (KeyQueue* q = queueOf(window); q && q->panel && q->panel->visible())
    q->panel->forwardScroll(xoffset, yoffset);
}

void onKey(GLFWwindow* window, int key, int scancode, int action, int mods) {
  auto* queue = queueOf(window);
  if (queue && queue->panel && queue->panel->visible()) {
    queue->panel->forwardKey(key, scancode, action, mods);
    if (key != GLFW_KEY_F1 && queue->panel->wantsKeyboard()) return;
  }
  if (action != GLFW_PRESS) return;
  const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
  std::optional<ViewerAction> a;
  switch (key) {
    case GLFW_KEY_1:
    case GLFW_KEY_KP_1:
      a = ViewerAction::kModeSimple;
      break;
    case GLFW_KEY_2:
    case GLFW_KEY_KP_2:
      a = ViewerAction::kModeLightMap;
      break;
    case GLFW_KEY_3:
    case GLFW_KEY_KP_3:
      a = ViewerAction::kModeSunlight;
      break;
    case GLFW_KEY_EQUAL:  // the "=/+" key
    case GLFW_KEY_KP_ADD:
      a = ViewerAction::kExposureUp;
      break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
      a = ViewerAction::kExposureDown;
      break;
    case GLFW_KEY_E:
      a = ViewerAction::kAutoExposure;
      break;
    case GLFW_KEY_O:
      a = ViewerAction::kNextOperator;
      break;
    case GLFW_KEY_T:
      a = shift ? ViewerAction::kTimeBack : ViewerAction::kTimeForward;
      break;
    case GLFW_KEY_C:
      a = ViewerAction::kNextCamera;
      break;
    case GLFW_KEY_R:
      a = ViewerAction::kReset;
      break;
    case GLFW_KEY_P:
      a = ViewerAction::kScreenshot;
      break;
    case GLFW_KEY_F1:
      a = ViewerAction::kTogglePanel;
      break;
    case GLFW_KEY_ESCAPE:
      a = ViewerAction::kQuit;
      break;
    default:
      break;
  }
  if (a && queue) queue->actions.push_back(*a);
}

// The overlay line, rasterised on the CPU (rasterizeText) and copied into the window's top left corner with a
// framebuffer blit: no shader, no blending.
class Overlay {
 public:
  ~Overlay() {
    glDeleteFramebuffers(1, &fbo_);
    glDeleteTextures(1, &texture_);
  }

  void draw(const std::string& text, uint32_t scale, int windowW, int windowH) {
    if (text != text_ || scale != scale_) upload(text, scale);
    const GLint w = std::min(GLint(image_.widthPx), windowW), h = std::min(GLint(image_.heightPx), windowH);
    // Texture row 0 is the text's top: flip it onto the window's top rows (GL's rows start at the bottom).
    glBlitNamedFramebuffer(fbo_, 0, 0, 0, w, h, 0, windowH, w, windowH - h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }

 private:
  void upload(const std::string& text, uint32_t scale) {
    image_ = rasterizeText(text, scale);
    text_ = text;
    scale_ = scale;
    if (image_.widthPx != textureW_ || image_.heightPx != textureH_) {
      glDeleteFramebuffers(1, &fbo_);
      glDeleteTextures(1, &texture_);
      glCreateTextures(GL_TEXTURE_2D, 1, &texture_);
      glTextureStorage2D(texture_, 1, GL_RGBA8, GLsizei(image_.widthPx), GLsizei(image_.heightPx));
      glCreateFramebuffers(1, &fbo_);
      glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, texture_, 0);
      textureW_ = image_.widthPx;
      textureH_ = image_.heightPx;
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(texture_, 0, 0, 0, GLsizei(image_.widthPx), GLsizei(image_.heightPx), GL_RGBA,
                        GL_UNSIGNED_BYTE, image_.rgba8.data());
  }

  GLuint texture_ = 0, fbo_ = 0;
  uint32_t textureW_ = 0, textureH_ = 0;
  TextImage image_;
  std::string text_;
  uint32_t scale_ = 0;
};

// What the viewer is looking through: one of the scene's cameras (index < rdb.cameras.size()) or the view
// framing the scene (index = rdb.cameras.size()).
struct ViewSource {
  size_t index = 0;
  View view;  // projection; the pose comes from the controller
};

}  // namespace

namespace {

// Lux in plain digits: whole lux from 100 lux up, else `digits` significant digits (no exponent notation).
std::string luxNumber(double lux, int digits) {
  char b[32];
  if (std::abs(lux) >= 100.0) {
    std::snprintf(b, sizeof b, "%.0f", lux);
  } else {
    std::snprintf(b, sizeof b, "%.*g", digits, lux);
  }
  return b;
}

}  // namespace

std::string luxReadingText(const LuxReading& r) {
  char line[200];
  std::string text = luxNumber(r.illuminanceLuminanceLux, 4) + " lux";
  if (r.stdErrorLuminanceLux) {
    const double e = *r.stdErrorLuminanceLux,
                 rel = r.illuminanceLuminanceLux > 0.0f ? 100.0 * e / double(r.illuminanceLuminanceLux) : 0.0;
    std::snprintf(line, sizeof line, " (%.2g %%)", rel);
    text += " ± " + luxNumber(e, 2) + line;
  } else if (r.fromLightTexture) {
    text += " (light texture)";
  }
  std::snprintf(line, sizeof line, ", %s, node %u at (%.2f, %.2f, %.2f) m", r.back ? "back" : "front",
                r.sdbNodeId, double(r.pointWorld.x), double(r.pointWorld.y), double(r.pointWorld.z));
  return text + line;
}

ViewerResult runViewer(GlfwWindowContext& window, const rdb::RasterRdb& rdb, ViewerHost& host,
                       const ViewerOptions& options) {
  using Clock = std::chrono::steady_clock;
  const std::vector<RenderMode> modes = supportedModes(rdb);
  if (std::find(modes.begin(), modes.end(), options.mode) == modes.end())
    throw std::invalid_argument(std::string("runViewer: the scene does not support ") +
                                renderModeName(options.mode) + " mode");
  if (options.camera && *options.camera >= rdb.cameras.size())
    throw std::invalid_argument("runViewer: camera index out of range");

  Renderer renderer;
  renderer.upload(rdb);
  renderer.setSunShadows(options.shadows);
  renderer.setBallSettings(options.balls);
  renderer.setAmbientOcclusion(options.ambientOcclusion);
  renderer.setBloom(options.bloom);
  Overlay overlay;
  ViewerPanel panel;
  panel.setVisible(options.panel);
  panel.initGl();
  KeyQueue keys;
  keys.panel = &panel;
  GLFWwindow* w = window.window();
  panel.attachWindow(w);
  glfwSetWindowUserPointer(w, &keys);
  glfwSetKeyCallback(w, onKey);
  glfwSetCharCallback(w, onChar);
  glfwSetMouseButtonCallback(w, onMouseButton);
  glfwSetScrollCallback(w, onScroll);
  glfwSwapInterval(1);

  CameraController controller(options.controller);
  int fbW = 0, fbH = 0;
  window.framebufferSize(fbW, fbH);
  const size_t startIndex = options.camera ? *options.camera : rdb.cameras.size();
  ViewSource source;
  auto setSource = [&](size_t index) {
    source.index = index;
    if (index < rdb.cameras.size()) {
      source.view = viewOfCamera(rdb.cameras[index]);
      controller.placeAt(rdb.cameras[index].worldFromCamera);
    } else {
      source.view = View{};  // 50° perspective, near 5 cm, no far plane: room for walking away
      controller.frame(rdb.boundsM, source.view.yfovRad, fbH > 0 ? float(fbW) / float(fbH) : 16.0f / 9.0f);
    }
  };
  setSource(startIndex);

  RenderMode mode = options.mode;
  ToneMapSettings tone = options.toneMap;
  bool autoExposure = options.autoExposure;
  std::string message;  // shown after the overlay line for a few seconds
  Clock::time_point messageUntil{};
  auto say = [&](const std::string& m) {
    log::info(m);
    message = m;
    messageUntil = Clock::now() + std::chrono::seconds(4);
  };

  ViewerResult result;
  std::optional<vec3> probePoint;  // where the last reading was taken, marked on the panel's layer
  // The lux probe at a framebuffer point (pixels from the top left) of the view shown now.
  auto probeAt = [&](double xPx, double yPx) {
    if (!rdb.variants.lightMap) {
      result.probeText = "no light maps to probe: view a baked directory";
    } else {
      View view = source.view;
      view.worldFromCamera = controller.worldFromCamera();
      const std::optional<SurfaceHit> hit =
          pickSurface(rdb, pickRay(view, xPx, yPx, uint32_t(std::max(fbW, 1)), uint32_t(std::max(fbH, 1))));
      const std::optional<LuxReading> reading =
          hit ? probeIlluminance(rdb, options.lightMaps, *hit) : std::nullopt;
      if (reading) result.probe = reading;
      probePoint = reading ? std::optional<vec3>(reading->pointWorld) : std::nullopt;
      result.probeText = reading ? luxReadingText(*reading)
                         : hit   ? "that surface has no light map"
                                 : "no surface there";
    }
    log::info("lux probe: " + result.probeText);
  };
  bool mouseWasDown = false, dragFromPanel = false;
  double pressX = 0.0, pressY = 0.0;
  const Clock::time_point start = Clock::now();
  Clock::time_point last = start, fpsStart = start;
  uint64_t fpsFrames = 0;
  double fps = 0.0;
  double lastX = 0.0, lastY = 0.0;
  glfwGetCursorPos(w, &lastX, &lastY);
  bool quit = false;
  while (!quit && !window.shouldClose()) {
    window.pollEvents();
    if (result.frames < options.script.size()) keys.actions.push_back(options.script[result.frames]);

    // The panel: shows the settings as they are and hands back what the user changed in it.
    window.framebufferSize(fbW, fbH);
    PanelState state;
    state.modes = modes;
    state.mode = mode;
    state.tone = tone;
    state.autoExposure = autoExposure;
    for (const rdb::RasterCamera& c : rdb.cameras) state.cameraNames.push_back(c.name);
    state.camera = source.index;
    state.clock = host.localClock();
    state.timeLabel = host.timeLabel();
    state.probeAvailable = rdb.variants.lightMap;
    state.probeText = result.probeText;
    if (probePoint && fbW > 0 && fbH > 0) {
      View shown = source.view;
      shown.worldFromCamera = controller.worldFromCamera();
      if (const std::optional<vec2> px = projectToImage(shown, *probePoint, uint32_t(fbW), uint32_t(fbH))) {
        int winW = 0, winH = 0;  // ImGui's display coordinates are the window's
        glfwGetWindowSize(w, &winW, &winH);
        state.probeMarker =
            std::array<float, 2>{px->x * float(winW) / float(fbW), px->y * float(winH) / float(fbH)};
      }
    }
    const PanelEdits edits = panel.frame(state, float(fbW), float(fbH),
                                         float(std::chrono::duration<double>(Clock::now() - last).count()));
    if (edits.mode) mode = *edits.mode;
    if (edits.autoExposure) autoExposure = *edits.autoExposure;
    if (edits.ev100) {
      autoExposure = false;
      tone.ev100 = *edits.ev100;
    }
    if (edits.op) tone.op = *edits.op;
    if (edits.camera) setSource(*edits.camera);
    if (edits.clock) {
      std::string why;
      const std::optional<rdb::RasterRdbChanges> changes = host.setLocalClock(*edits.clock, why);
      if (changes) renderer.update(rdb, *changes);
      if (!why.empty()) say(why);
    }

    bool screenshot = false;
    while (!keys.actions.empty()) {
      const ViewerAction a = keys.actions.front();
      keys.actions.pop_front();
      switch (a) {
        case ViewerAction::kModeSimple:
        case ViewerAction::kModeLightMap:
        case ViewerAction::kModeSunlight: {
          const RenderMode m = a == ViewerAction::kModeSimple     ? RenderMode::kSimple
                               : a == ViewerAction::kModeLightMap ? RenderMode::kLightMap
                                                                  : RenderMode::kSunlight;
          if (std::find(modes.begin(), modes.end(), m) != modes.end()) {
            mode = m;
          } else {
            say(std::string("no ") + renderModeName(m) + " mode: " +
                (m == RenderMode::kLightMap ? "the scene has no light maps (view a baked directory)"
                                            : "the scene has neither sky nor sun"));
          }
          break;
        }
        case ViewerAction::kExposureUp:
        case ViewerAction::kExposureDown:
          autoExposure = false;  // from the exposure shown now
          tone.ev100 += a == ViewerAction::kExposureUp ? kExposureStepEv : -kExposureStepEv;
          break;
        case ViewerAction::kAutoExposure:
          autoExposure = !autoExposure;
          break;
        case ViewerAction::kNextOperator:
          tone.op = ToneOperator((int(tone.op) + 1) % 3);
          break;
        case ViewerAction::kTimeForward:
        case ViewerAction::kTimeBack: {
          std::string why;
          const std::optional<rdb::RasterRdbChanges> changes =
              host.stepTime(a == ViewerAction::kTimeForward ? kTimeStepMinutes : -kTimeStepMinutes, why);
          if (changes) renderer.update(rdb, *changes);
          if (!why.empty()) say(why);
          break;
        }
        case ViewerAction::kNextCamera:
          setSource((source.index + 1) % (rdb.cameras.size() + 1));
          break;
        case ViewerAction::kReset:
          setSource(startIndex);
          tone = options.toneMap;
          autoExposure = options.autoExposure;
          break;
        case ViewerAction::kScreenshot:
          screenshot = true;
          break;
        case ViewerAction::kTogglePanel:
          panel.setVisible(!panel.visible());
          break;
        case ViewerAction::kQuit:
          quit = true;
          break;
      }
    }
    if (quit) break;

    // Walking and looking. A long frame (a screenshot written, the window dragged) moves at most 0.25 s.
    const Clock::time_point now = Clock::now();
    const double dt = std::min(std::chrono::duration<double>(now - last).count(), 0.25);
    last = now;
    auto held = [&](int k1, int k2) {
      return glfwGetKey(w, k1) == GLFW_PRESS || glfwGetKey(w, k2) == GLFW_PRESS;
    };
    WalkInput walk;
    walk.forward = float(held(GLFW_KEY_W, GLFW_KEY_UP)) - float(held(GLFW_KEY_S, GLFW_KEY_DOWN));
    walk.right = float(held(GLFW_KEY_D, GLFW_KEY_RIGHT)) - float(held(GLFW_KEY_A, GLFW_KEY_LEFT));
    walk.up = float(glfwGetKey(w, GLFW_KEY_PAGE_UP) == GLFW_PRESS) -
              float(glfwGetKey(w, GLFW_KEY_PAGE_DOWN) == GLFW_PRESS);
    walk.run = held(GLFW_KEY_LEFT_SHIFT, GLFW_KEY_RIGHT_SHIFT);
    if (panel.wantsKeyboard()) walk = WalkInput{};
    controller.walk(walk, dt);
    // The left button: a drag that starts outside the panel looks around; a click that does not move (3
    // pixels at most) probes the surface under it.
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(w, &x, &y);
    const bool mouseDown = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (mouseDown && !mouseWasDown) {
      dragFromPanel = panel.wantsMouse();
      pressX = x;
      pressY = y;
    }
    if (mouseDown && !dragFromPanel) controller.look(x - lastX, y - lastY);
    if (!mouseDown && mouseWasDown && !dragFromPanel && std::hypot(x - pressX, y - pressY) <= 3.0) {
      int winW = 0, winH = 0;
      glfwGetWindowSize(w, &winW, &winH);  // the cursor is in window coordinates
      const double sx = winW > 0 ? double(fbW) / winW : 1.0, sy = winH > 0 ? double(fbH) / winH : 1.0;
      probeAt(x * sx, y * sy);
    }
    mouseWasDown = mouseDown;
    lastX = x;
    lastY = y;

    window.framebufferSize(fbW, fbH);
    if (fbW < 1 || fbH < 1) {  // minimised
      glfwWaitEventsTimeout(0.1);
      continue;
    }
    if (options.probeAtPx && result.frames == 0) probeAt(options.probeAtPx->x, options.probeAtPx->y);
    View view = source.view;
    view.worldFromCamera = controller.worldFromCamera();
    // Emission given as a display colour at the exposure's white (the last frame's exposure).
    renderer.setDisplayWhite(1.0f / exposureScale(tone.ev100));
    renderer.render(view, mode, uint32_t(fbW), uint32_t(fbH));
    if (autoExposure) {
      const std::vector<float> rgb = renderer.luminanceRgb();
      std::vector<float> lum(rgb.size() / 3);
      for (size_t i = 0; i < lum.size(); ++i)
        lum[i] = luminance(Rgb(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]));
      tone.ev100 = autoExposureEv100Histogram(lum) - options.evCompensation;
    }
    renderer.toneMap(tone);
    if (screenshot) host.saveScreenshot(renderer.srgb8(), renderer.width(), renderer.height(), mode, tone);
    renderer.present(uint32_t(fbW), uint32_t(fbH));

    ++fpsFrames;
    const double fpsSeconds = std::chrono::duration<double>(now - fpsStart).count();
    if (fpsSeconds >= 0.5) {
      fps = double(fpsFrames) / fpsSeconds;
      fpsFrames = 0;
      fpsStart = now;
    }
    char line[160];
    std::snprintf(line, sizeof line, "%s FPS  %s  EV100 %.1f%s  %s",
                  fps > 0.0 ? std::to_string(std::lround(fps)).c_str() : "--", renderModeName(mode),
                  tone.ev100, autoExposure ? " AUTO" : "", toneOperatorName(tone.op));
    std::string text = line;
    const std::string time = host.timeLabel();
    if (!time.empty()) text += "  " + time;
    if (!message.empty() && now < messageUntil) text += "  | " + message;
    overlay.draw(text, fbW >= 1600 ? 2u : 1u, fbW, fbH);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    panel.render();
    if (options.captureWindow) {
      result.windowWidthPx = uint32_t(fbW);
      result.windowHeightPx = uint32_t(fbH);
      std::vector<uint8_t> rows(size_t(fbW) * fbH * 3);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
      glReadBuffer(GL_BACK);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(0, 0, fbW, fbH, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
      result.windowSrgb8.resize(rows.size());
      const size_t stride = size_t(fbW) * 3;
      for (int row = 0; row < fbH; ++row)  // GL's rows start at the bottom
        std::copy_n(&rows[size_t(fbH - 1 - row) * stride], stride, &result.windowSrgb8[size_t(row) * stride]);
    }
    window.swapBuffers();

    ++result.frames;
    if (options.frames > 0 && result.frames >= options.frames && result.frames > options.script.size()) break;
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (result.frames > 0) {
    result.srgb8 = renderer.srgb8();
    result.widthPx = renderer.width();
    result.heightPx = renderer.height();
  }
  result.mode = mode;
  result.tone = tone;
  glfwSetKeyCallback(w, nullptr);
  glfwSetCharCallback(w, nullptr);
  glfwSetMouseButtonCallback(w, nullptr);
  glfwSetScrollCallback(w, nullptr);
  glfwSetWindowUserPointer(w, nullptr);
  return result;
}

}  // namespace fly::raster
