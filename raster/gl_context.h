// An OpenGL 4.5 core context behind one interface, two ways (docs/architecture.md):
// headless through EGL with no display server (device platform, falling back to Mesa's surfaceless platform;
// rendering goes into framebuffer objects) and a GLFW window for interactive use. Functions are loaded
// through libepoxy; GL debug messages (KHR_debug) go to the log (base/log.h).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

struct GLFWwindow;

namespace fly::raster {

// No OpenGL 4.5 core context could be made; the message says what is missing (EGL library, EGL extension,
// a device, an X display, the GL version) and how to get it.
class GlUnavailableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GlInfo {
  int major = 0;  // the context's OpenGL version, ≥ 4.5
  int minor = 0;
  std::string vendor;    // GL_VENDOR, e.g. "Mesa"
  std::string renderer;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string platform;  // "egl-device", "egl-surfaceless" or "glfw"
};

class GlContext {
 public:
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes the context current on the calling thread (the constructors leave it current).
  virtual void makeCurrent() = 0;
  const GlInfo& info() const { return info_; }

 protected:
  GlContext() = default;
  // Queries the version and names of the current context, checks ≥ 4.5 and routes KHR_debug to the log.
  void initCurrent(const std::string& platform);

 private:
  GlInfo info_;
};

// A context with no surface: render into framebuffer objects. Tries the EGL devices
// (EGL_EXT_device_enumeration, EGL_EXT_platform_device), then EGL_MESA_platform_surfaceless; requests 4.6
// core, then 4.5. GlUnavailableError when none works.
std::unique_ptr<GlContext> createHeadlessContext();

// A GLFW window with a 4.5 (or newer) core context, `widthPx` × `heightPx`, double-buffered.
class GlfwWindowContext : public GlContext {
 public:
  GlfwWindowContext(int widthPx, int heightPx, const std::string& title);
  ~GlfwWindowContext() override;

  void makeCurrent() override;
  void swapBuffers();
  bool shouldClose() const;
  void pollEvents();
  // The framebuffer's size in pixels (may differ from the window's on high-DPI screens).
  void framebufferSize(int& widthPx, int& heightPx) const;
  GLFWwindow* window() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace fly::raster
