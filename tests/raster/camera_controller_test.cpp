#include "raster/camera_controller.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fly::raster {
namespace {

constexpr float kEps = 1e-5f;

void expectVecNear(const vec3& a, const vec3& b, float eps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

TEST(CameraController, WalkingOneSecondForwardMovesWalkingSpeedAlongTheHorizontalViewDirection) {
  CameraController c;
  // Looking 30° down towards +X (yaw −90°): walking ignores the pitch.
  c.lookAlong(vec3(1.0f, 1.6f, 2.0f), vec3(std::cos(0.5236f), -std::sin(0.5236f), 0.0f));
  EXPECT_NEAR(c.yawRad(), -0.5f * kPiF, kEps);
  c.walk({.forward = 1.0f}, 1.0);
  expectVecNear(c.eyeM(), vec3(1.0f + 1.4f, 1.6f, 2.0f), kEps);
  // Running: ×3; backwards for half a second.
  c.walk({.forward = -1.0f, .run = true}, 0.5);
  expectVecNear(c.eyeM(), vec3(1.0f + 1.4f - 2.1f, 1.6f, 2.0f), kEps);
  // Right of a view along +X is +Z; up is world +Y.
  c.walk({.right = 1.0f}, 1.0);
  expectVecNear(c.eyeM(), vec3(0.3f, 1.6f, 3.4f), kEps);
  c.walk({.up = -1.0f}, 0.25);
  expectVecNear(c.eyeM(), vec3(0.3f, 1.25f, 3.4f), kEps);
}

TEST(CameraController, DiagonalWalkingIsNoFaster) {
  CameraController c;  // yaw 0: forward is −Z, right is +X
  c.walk({.forward = 1.0f, .right = 1.0f}, 2.0);
  const float leg = 2.0f * 1.4f / std::sqrt(2.0f);
  expectVecNear(c.eyeM(), vec3(leg, 0.0f, -leg), kEps);
  EXPECT_NEAR(glm::length(c.eyeM()), 2.8f, kEps);
}

TEST(CameraController, PitchClampsAt89Degrees) {
  CameraController c({.lookRadPerPx = 0.01f});
  c.look(0.0, -1000.0);  // cursor far up: 10 rad of pitch asked
  EXPECT_NEAR(c.pitchRad(), float(degToRad(89.0)), kEps);
  EXPECT_GT(c.forwardWorld().y, 0.9998f);
  c.look(0.0, 5000.0);
  EXPECT_NEAR(c.pitchRad(), -float(degToRad(89.0)), kEps);
  // A camera pointing straight down is clamped too, its yaw taken from its image's top (+Y): here +X.
  c.placeAt(frameTransform(vec3(0, 0, 1), vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 3, 0)));
  EXPECT_NEAR(c.pitchRad(), -float(degToRad(89.0)), kEps);
  EXPECT_NEAR(c.yawRad(), -0.5f * kPiF, kEps);
  expectVecNear(c.eyeM(), vec3(0, 3, 0), kEps);
}

TEST(CameraController, YawWrapsToMinusPiPi) {
  CameraController c({.lookRadPerPx = 0.001f});
  c.look(-3000.0, 0.0);  // 3 rad left
  EXPECT_NEAR(c.yawRad(), 3.0f, kEps);
  c.look(-1000.0, 0.0);  // 4 rad ≡ 4 − 2π
  EXPECT_NEAR(c.yawRad(), 4.0f - 2.0f * kPiF, 1e-4f);
  c.look(20000.0, 0.0);  // 20 rad right: 4 − 20 = −16 ≡ −16 + 6π
  EXPECT_NEAR(c.yawRad(), -16.0f + 6.0f * kPiF, 1e-3f);
  EXPECT_GT(c.yawRad(), -kPiF);
  EXPECT_LE(c.yawRad(), kPiF);
  // Looking along −Z + a full turn gives the same forward vector.
  CameraController d;
  d.look(-2.0 * double(kPiF) / 0.0025, 0.0);
  expectVecNear(d.forwardWorld(), vec3(0, 0, -1), 1e-4f);
}

TEST(CameraController, ZeroDirectionZeroDtAndNanGiveNoNan) {
  CameraController c;
  c.lookAlong(vec3(1, 2, 3), vec3(0.0f));
  c.look(std::nan(""), 1.0);
  c.walk({.forward = 1.0f}, 0.0);
  c.walk({.forward = 1.0f}, -1.0);
  c.walk({.forward = std::nanf("")}, 1.0);
  c.walk({.forward = 1.0f}, std::nan(""));
  c.placeAt(mat4(0.0f));  // no axes at all: the origin is taken, the angles kept
  EXPECT_TRUE(isFinite(c.worldFromCamera()));
  expectVecNear(c.eyeM(), vec3(0.0f), 0.0f);
  EXPECT_EQ(c.yawRad(), 0.0f);
  EXPECT_EQ(c.pitchRad(), 0.0f);
}

TEST(CameraController, PlaceAtRoundTripsACameraWithoutRoll) {
  // A camera at (−1.7, 1.6, 2.2) looking at (2.0, 0.6, −0.6) (box-room's "sunlit-wall").
  const vec3 eye(-1.7f, 1.6f, 2.2f);
  const vec3 f = glm::normalize(vec3(2.0f, 0.6f, -0.6f) - eye);
  const vec3 x = glm::normalize(glm::cross(f, vec3(0, 1, 0)));
  const vec3 y = glm::cross(-f, x);
  const mat4 m = frameTransform(x, y, -f, eye);
  CameraController c;
  c.placeAt(m);
  const mat4 back = c.worldFromCamera();
  for (int col = 0; col < 4; ++col) expectVecNear(vec3(back[col]), vec3(m[col]), 1e-5f);
  // The frame is orthonormal and right-handed.
  EXPECT_NEAR(glm::determinant(mat3(back)), 1.0f, 1e-5f);
}

TEST(CameraController, FrameShowsEveryCornerFromEyeHeight) {
  const float yfov = 0.8726646f, aspect = 16.0f / 9.0f;
  for (const Bounds3 b :
       {Bounds3{vec3(-3, 0, -2), vec3(3, 2.7f, 2)}, Bounds3{vec3(10, 5, 10), vec3(30, 14, 22)},
        Bounds3{vec3(0, 0, 0), vec3(0.1f, 0.1f, 0.1f)}}) {
    CameraController c;
    c.frame(b, yfov, aspect);
    if (b.size().x > 1.0f) {
      EXPECT_NEAR(c.eyeM().y, b.min.y + 1.6f, kEps);  // a person standing
    }
    const mat4 cameraFromWorld = glm::inverse(c.worldFromCamera());
    for (int i = 0; i < 8; ++i) {
      const vec3 corner((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                        (i & 4) ? b.max.z : b.min.z);
      const vec3 p(cameraFromWorld * vec4(corner, 1.0f));
      ASSERT_LT(p.z, 0.0f) << i;  // in front
      EXPECT_LE(std::abs(p.y / p.z), std::tan(0.5f * yfov) + 1e-5f) << i;
      EXPECT_LE(std::abs(p.x / p.z), std::tan(0.5f * yfov) * aspect + 1e-5f) << i;
    }
  }
}

}  // namespace
}  // namespace fly::raster
