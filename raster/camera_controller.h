// A first-person camera for walking through a scene at human scale: position in metres (world space, +Y up,
// glTF's frame), yaw about +Y and pitch above the horizon. Walking moves along the view's horizontal
// direction at a person's walking speed (≈ 1.4 m/s, the mean preferred walking speed of adults; Bohannon &
// Andrews 2011), mouse motion turns the view. Pure logic, no GL: the viewer (raster/viewer.h) feeds it input
// and reads worldFromCamera().
#pragma once

#include "base/math.h"

namespace fly::raster {

struct CameraControllerSettings {
  float eyeHeightM = 1.6f;       // frame(): the eye above the scene's lowest point, metres, ≥ 0
  float walkSpeedMps = 1.4f;     // metres per second, > 0
  float runFactor = 3.0f;        // speed multiplier while running (Shift), ≥ 1
  float lookRadPerPx = 0.0025f;  // view rotation per pixel of cursor motion, radians
};

// Movement wanted this frame, each axis in [−1, 1] (a key held: ±1): forward along the view's horizontal
// direction, right, and up along world +Y. A combined direction longer than 1 is normalised, so walking
// diagonally is no faster.
struct WalkInput {
  float forward = 0.0f;
  float right = 0.0f;
  float up = 0.0f;
  bool run = false;
};

class CameraController {
 public:
  // Pitch is clamped to ±kMaxPitchRad (89°), so the view never turns over the pole.
  static constexpr float kMaxPitchRad = 1.5533430f;

  explicit CameraController(const CameraControllerSettings& settings = {});

  // Takes a camera's position and view direction (its −Z); roll is dropped. A camera looking straight up or
  // down takes its yaw from its +Y axis; a degenerate matrix (zero-length axes) keeps the current yaw and
  // pitch.
  void placeAt(const mat4& worldFromCamera);
  // Stands at `eyeM` looking along `directionWorld`; a zero or non-finite direction keeps yaw and pitch.
  void lookAlong(const vec3& eyeM, const vec3& directionWorld);
  // A view of the whole of `boundsM` as a person would see it: the eye eyeHeightM above the bounds' lowest
  // point, to the +X+Z side, turned to the bounds' centre and far enough that the bounding sphere fits in a
  // perspective view of vertical field of view `yfovRad` and aspect `aspect` (width / height).
  void frame(const Bounds3& boundsM, float yfovRad, float aspect);

  // Moves for `dtSeconds` (≤ 0 or non-finite: no motion).
  void walk(const WalkInput& input, double dtSeconds);
  // Turns by a cursor motion in pixels: +dx turns right, +dy (down the screen) looks down. Yaw wraps to
  // (−π, π]; pitch is clamped. Non-finite motion is ignored.
  void look(double dxPx, double dyPx);

  const vec3& eyeM() const { return eyeM_; }
  // Yaw about world +Y from the −Z axis, counter-clockwise seen from above (0: looking along −Z, π/2: −X).
  float yawRad() const { return yawRad_; }
  float pitchRad() const { return pitchRad_; }  // above the horizon, [−89°, 89°]
  vec3 forwardWorld() const;                    // unit view direction
  vec3 forwardHorizontal() const;               // unit, the view direction projected on the XZ plane
  vec3 rightWorld() const;                      // unit, horizontal
  // Rigid, the camera looking down its −Z with +Y up (raster::View::worldFromCamera).
  mat4 worldFromCamera() const;

  const CameraControllerSettings& settings() const { return settings_; }

 private:
  void setAngles(float yawRad, float pitchRad);

  CameraControllerSettings settings_;
  vec3 eyeM_{0.0f};
  float yawRad_ = 0.0f;
  float pitchRad_ = 0.0f;
};

}  // namespace fly::raster
