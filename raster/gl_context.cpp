#include "raster/gl_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "base/log.h"

namespace fly::raster {

namespace {

void APIENTRY debugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                           const GLchar* message, const void* /*user*/) {
  (void)source;
  char head[48];
  std::snprintf(head, sizeof head, "OpenGL (type 0x%x, id %u): ", unsigned(type), unsigned(id));
  const std::string text = head + std::string(message, length >= 0 ? size_t(length) : std::strlen(message));
  // Errors always reach the user; drivers' performance notes and low-severity hints (NVIDIA's shader
  // recompilation, buffer-usage and allocation notes) only with --verbose.
  if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH) {
    log::error(text);
  } else if (severity == GL_DEBUG_SEVERITY_MEDIUM && type != GL_DEBUG_TYPE_PERFORMANCE) {
    log::warn(text);
  } else {
    log::debug(text);
  }
}

std::string eglErrorName() {
  char b[32];
  std::snprintf(b, sizeof b, "EGL error 0x%x", unsigned(eglGetError()));
  return b;
}

// A context made current with no surface (EGL_KHR_surfaceless_context), rendering into FBOs.
class EglContext : public GlContext {
 public:
  EglContext() {
    if (!epoxy_has_egl()) {
      throw GlUnavailableError(
          "no EGL library could be loaded (libEGL.so.1); install libegl1 and a driver "
          "(Debian: libegl-mesa0 libgl1-mesa-dri)");
    }
    const bool clientExt = epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base");
    if (!clientExt) {
      throw GlUnavailableError(
          "EGL has no driver with EGL_EXT_platform_base, so it cannot run without a display; "
          "install Mesa (Debian: libegl-mesa0 libgl1-mesa-dri) or a GPU driver with EGL");
    }
    std::string tried;
    // 1. The devices (a GPU, or Mesa's software device).
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration") &&
        epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device")) {
      EGLint count = 0;
      eglQueryDevicesEXT(0, nullptr, &count);
      std::vector<EGLDeviceEXT> devices(size_t(count > 0 ? count : 0));
      if (count > 0) eglQueryDevicesEXT(count, devices.data(), &count);
      for (EGLDeviceEXT d : devices) {
        if (tryDisplay(eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, d, nullptr), tried)) {
          platform_ = "egl-device";
          break;
        }
      }
      if (devices.empty()) tried += " EGL lists no devices;";
    } else {
      tried += " no EGL_EXT_device_enumeration / EGL_EXT_platform_device;";
    }
    // 2. Mesa's surfaceless platform.
    if (context_ == EGL_NO_CONTEXT) {
      if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        if (tryDisplay(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                       tried)) {
          platform_ = "egl-surfaceless";
        }
      } else {
        tried += " no EGL_MESA_platform_surfaceless;";
      }
    }
    if (context_ == EGL_NO_CONTEXT) {
      throw GlUnavailableError(
          "no headless OpenGL 4.5 core context:" + tried +
          " install Mesa (Debian: libegl-mesa0 libgl1-mesa-dri) or a GPU driver with EGL");
    }
    initCurrent(platform_);
  }

  ~EglContext() override {
    if (context_ != EGL_NO_CONTEXT) {
      if (eglGetCurrentContext() == context_)
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display_, context_);
    }
    // The display stays initialised: EGL displays are shared per process, and terminating one would end other
    // contexts on it.
  }

  void makeCurrent() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      throw GlUnavailableError("eglMakeCurrent failed: " + eglErrorName());
    }
  }

 private:
  // Initialises `display` and makes a 4.6 or 4.5 core context current on it; appends why not to `tried`.
  bool tryDisplay(EGLDisplay display, std::string& tried) {
    if (display == EGL_NO_DISPLAY) {
      tried += " no display (" + eglErrorName() + ");";
      return false;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
      tried += " eglInitialize failed (" + eglErrorName() + ");";
      return false;
    }
    if (!epoxy_has_egl_extension(display, "EGL_KHR_surfaceless_context")) {
      tried += " a display without EGL_KHR_surfaceless_context;";
      return false;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      tried += " no desktop OpenGL on this display;";
      return false;
    }
    const EGLint configAttribs[] = {
        EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint numConfigs = 0;
    const bool haveConfig =
        eglChooseConfig(display, configAttribs, &config, 1, &numConfigs) && numConfigs > 0;
    for (int minorWanted : {6, 5}) {
      const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                       4,
                                       EGL_CONTEXT_MINOR_VERSION,
                                       minorWanted,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                       EGL_CONTEXT_OPENGL_DEBUG,
                                       EGL_TRUE,
                                       EGL_NONE};
      // A config is optional: with EGL_KHR_no_config_context the context needs none (FBOs carry
      // depth/stencil).
      const EGLContext c =
          eglCreateContext(display, haveConfig ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, contextAttribs);
      if (c == EGL_NO_CONTEXT) continue;
      if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) {
        eglDestroyContext(display, c);
        continue;
      }
      display_ = display;
      context_ = c;
      return true;
    }
    tried += " no OpenGL 4.5 core context (" + eglErrorName() + ");";
    return false;
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string platform_;
};

}  // namespace

void GlContext::initCurrent(const std::string& platform) {
  info_.platform = platform;
  glGetIntegerv(GL_MAJOR_VERSION, &info_.major);
  glGetIntegerv(GL_MINOR_VERSION, &info_.minor);
  auto str = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
  };
  info_.vendor = str(GL_VENDOR);
  info_.renderer = str(GL_RENDERER);
  if (info_.major < 4 || (info_.major == 4 && info_.minor < 5)) {
    throw GlUnavailableError("the OpenGL context is version " + std::to_string(info_.major) + "." +
                             std::to_string(info_.minor) + " (" + info_.renderer + "); fly needs 4.5 core");
  }
  // KHR_debug is core in 4.3: errors and warnings reach the log as they happen.
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(debugMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  log::debug("OpenGL " + std::to_string(info_.major) + "." + std::to_string(info_.minor) + " core, " +
             info_.vendor + ", " + info_.renderer + " (" + platform + ")");
}

std::unique_ptr<GlContext> createHeadlessContext() {
  return std::make_unique<EglContext>();
}

GlfwWindowContext::GlfwWindowContext(int widthPx, int heightPx, const std::string& title) {
  if (!glfwInit()) {
    throw GlUnavailableError("GLFW could not start (no X display? DISPLAY is " +
                             std::string(std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "unset") +
                             "); run under a display or xvfb-run, or render headless");
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  glfwWindowHint(GLFW_STENCIL_BITS, 8);
  window_ = glfwCreateWindow(widthPx, heightPx, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw GlUnavailableError("GLFW could not open a window with an OpenGL 4.5 core context");
  }
  glfwMakeContextCurrent(window_);
  try {
    initCurrent("glfw");
  } catch (...) {
    glfwDestroyWindow(window_);
    glfwTerminate();
    throw;
  }
}

GlfwWindowContext::~GlfwWindowContext() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

void GlfwWindowContext::makeCurrent() {
  glfwMakeContextCurrent(window_);
}
void GlfwWindowContext::swapBuffers() {
  glfwSwapBuffers(window_);
}
bool GlfwWindowContext::shouldClose() const {
  return glfwWindowShouldClose(window_);
}
void GlfwWindowContext::pollEvents() {
  glfwPollEvents();
}
void GlfwWindowContext::framebufferSize(int& widthPx, int& heightPx) const {
  glfwGetFramebufferSize(window_, &widthPx, &heightPx);
}

}  // namespace fly::raster
