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
  return frameTransform(x, glm::cross(back, x), back, eyeM);
}

}  // namespace fly::sdb
