#include "sdb/camera.h"

#include <stdexcept>

namespace fly::sdb {

mat4 lookAtTransform(const vec3& eyeM, const vec3& targetM, const vec3& up) {
  const vec3 toTarget = targetM - eyeM;
  const float distance = glm::length(toTarget);
  if (!(distance > 0.0f) || !isFinite(toTarget)) {
    throw std::invalid_argument("camera position and target are the same point");
  }
  const vec3 back = -toTarget / distance;  // local +Z points away from the view (glTF cameras look down −Z)
  const vec3 side = glm::cross(up, back);
  const float sideLength = glm::length(side);
  // 1e-6 ≈ 0.00006°: an up vector closer to the view direction than that defines no roll.
  if (!(sideLength > 1e-6f * glm::length(up))) {
    throw std::invalid_argument("camera up vector is parallel to the view direction (or zero)");
  }
  const vec3 x = side / sideLength;
  const vec3 y = glm::cross(back, x);
  mat4 m(1.0f);
  m[0] = vec4(x, 0.0f);
  m[1] = vec4(y, 0.0f);
  m[2] = vec4(back, 0.0f);
  m[3] = vec4(eyeM, 1.0f);
  return m;
}

}  // namespace fly::sdb
