// Vector and matrix types (glm) and the constants fly uses. World space is glTF's: right-handed, +Y up, metres.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <numbers>

namespace fly {

using glm::dmat4;
using glm::dvec2;
using glm::dvec3;
using glm::mat3;
using glm::mat4;
using glm::quat;
using glm::vec2;
using glm::vec3;
using glm::vec4;

inline constexpr double kPi = std::numbers::pi;
inline constexpr float kPiF = std::numbers::pi_v<float>;

inline constexpr double degToRad(double deg) { return deg * (kPi / 180.0); }
inline constexpr double radToDeg(double rad) { return rad * (180.0 / kPi); }

// True when every component is finite (no NaN, no Inf).
inline bool isFinite(const vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
inline bool isFinite(const vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool isFinite(const vec4& v) { return isFinite(vec3(v)) && std::isfinite(v.w); }
bool isFinite(const mat4& m);

// The transform parentFromLocal of a frame whose local axes are x, y, z (unit, orthogonal, expressed in the
// parent frame) with its origin at `origin`.
inline mat4 frameTransform(const vec3& x, const vec3& y, const vec3& z, const vec3& origin) {
  return mat4(vec4(x, 0.0f), vec4(y, 0.0f), vec4(z, 0.0f), vec4(origin, 1.0f));
}

// Axis-aligned bounds in metres; empty until a point is added.
struct Bounds3 {
  vec3 min{std::numeric_limits<float>::infinity()};
  vec3 max{-std::numeric_limits<float>::infinity()};

  bool empty() const { return min.x > max.x; }
  void extend(const vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Bounds3& b) {
    if (!b.empty()) {
      extend(b.min);
      extend(b.max);
    }
  }
  vec3 size() const { return empty() ? vec3(0.0f) : max - min; }
};

}  // namespace fly
