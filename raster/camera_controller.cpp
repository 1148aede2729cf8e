#include "raster/camera_controller.h"

#include <algorithm>
#include <cmath>

namespace fly::raster {

namespace {

// `a` wrapped to (−π, π].
float wrapAngle(float a) {
  const float twoPi = 2.0f * kPiF;
  a = std::fmod(a, twoPi);  // (−2π, 2π)
  if (a > kPiF) a -= twoPi;
  if (a <= -kPiF) a += twoPi;
  return a;
}

}  // namespace

CameraController::CameraController(const CameraControllerSettings& settings) : settings_(settings) {}

void CameraController::setAngles(float yawRad, float pitchRad) {
  if (!std::isfinite(yawRad) || !std::isfinite(pitchRad)) return;
  yawRad_ = wrapAngle(yawRad);
  pitchRad_ = std::clamp(pitchRad, -kMaxPitchRad, kMaxPitchRad);
}

void CameraController::placeAt(const mat4& worldFromCamera) {
  const vec3 eye(worldFromCamera[3]);
  if (isFinite(eye)) eyeM_ = eye;
  const vec3 back(worldFromCamera[2]);
  const vec3 up(worldFromCamera[1]);
  if (!isFinite(back) || !isFinite(up) || glm::length(back) < 1e-12f) return;
  const vec3 f = -glm::normalize(back);
  vec2 horizontal(f.x, f.z);
  // Straight up or down: the image's top (the camera's +Y) shows where the camera faces when looking down,
  // and the opposite way when looking up.
  if (glm::length(horizontal) < 1e-6f) horizontal = (f.y < 0.0f ? 1.0f : -1.0f) * vec2(up.x, up.z);
  const float yaw = glm::length(horizontal) < 1e-12f ? yawRad_ : std::atan2(-horizontal.x, -horizontal.y);
  setAngles(yaw, std::asin(std::clamp(f.y, -1.0f, 1.0f)));
}

void CameraController::lookAlong(const vec3& eyeM, const vec3& directionWorld) {
  if (isFinite(eyeM)) eyeM_ = eyeM;
  if (!isFinite(directionWorld) || glm::length(directionWorld) < 1e-12f) return;
  const vec3 f = glm::normalize(directionWorld);
  const float yaw = (f.x == 0.0f && f.z == 0.0f) ? yawRad_ : std::atan2(-f.x, -f.z);
  setAngles(yaw, std::asin(std::clamp(f.y, -1.0f, 1.0f)));
}

void CameraController::frame(const Bounds3& boundsM, float yfovRad, float aspect) {
  const vec3 center = boundsM.empty() ? vec3(0.0f) : 0.5f * (boundsM.min + boundsM.max);
  const float floorY = boundsM.empty() ? 0.0f : boundsM.min.y;
  const float radius = std::max(1e-3f, boundsM.empty() ? 0.0f : 0.5f * glm::length(boundsM.size()));
  const float halfFovY = 0.5f * std::clamp(yfovRad, 1e-3f, kPiF - 1e-3f);
  const float halfFovX = std::atan(std::tan(halfFovY) * std::max(aspect, 1e-3f));
  // Any eye at least this far from the centre sees the whole bounding sphere when it faces the centre.
  const float distance = radius / std::sin(std::min(halfFovY, halfFovX));
  const float dy = center.y - (floorY + settings_.eyeHeightM);
  // At eye height when the sphere allows it; else (a small object far below the eye) half the distance
  // out, which leaves the eye farther than `distance` and the pitch above −64°.
  const float horizontal =
      std::max(std::sqrt(std::max(distance * distance - dy * dy, 0.0f)), 0.5f * distance);
  const vec3 out = glm::normalize(vec3(1.0f, 0.0f, 1.0f));
  const vec3 eye = vec3(center.x, floorY + settings_.eyeHeightM, center.z) + horizontal * out;
  lookAlong(eye, center - eye);
}

vec3 CameraController::forwardWorld() const {
  const float c = std::cos(pitchRad_);
  return {-std::sin(yawRad_) * c, std::sin(pitchRad_), -std::cos(yawRad_) * c};
}

vec3 CameraController::forwardHorizontal() const {
  return {-std::sin(yawRad_), 0.0f, -std::cos(yawRad_)};
}

vec3 CameraController::rightWorld() const {
  return {std::cos(yawRad_), 0.0f, -std::sin(yawRad_)};
}

void CameraController::walk(const WalkInput& input, double dtSeconds) {
  if (!(dtSeconds > 0.0) || !std::isfinite(dtSeconds)) return;
  vec3 direction =
      input.forward * forwardHorizontal() + input.right * rightWorld() + vec3(0.0f, input.up, 0.0f);
  if (!isFinite(direction)) return;
  const float length = glm::length(direction);
  if (length > 1.0f) direction /= length;
  const float speedMps = settings_.walkSpeedMps * (input.run ? settings_.runFactor : 1.0f);
  eyeM_ += direction * float(double(speedMps) * dtSeconds);
}

void CameraController::look(double dxPx, double dyPx) {
  if (!std::isfinite(dxPx) || !std::isfinite(dyPx)) return;
  setAngles(yawRad_ - float(dxPx) * settings_.lookRadPerPx, pitchRad_ - float(dyPx) * settings_.lookRadPerPx);
}

mat4 CameraController::worldFromCamera() const {
  const vec3 x = rightWorld();
  const vec3 z = -forwardWorld();
  const vec3 y = glm::cross(z, x);
  return frameTransform(x, y, z, eyeM_);
}

}  // namespace fly::raster
