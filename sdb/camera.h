// Cameras (glTF camera model). A camera looks down its node's local −Z with +Y up.
#pragma once

#include <limits>
#include <string>

#include "base/math.h"

namespace fly::sdb {

enum class Projection { kPerspective, kOrthographic };

struct Camera {
  std::string name;
  Projection projection = Projection::kPerspective;
  float yfovRad = 0.8726646f;  // vertical field of view, radians, (0, π); default 50°
  float aspectRatio = 0.0f;    // width / height; 0 = take the output image's
  float znearM = 0.05f;        // metres, > 0
  float zfarM = std::numeric_limits<float>::infinity();  // metres, > znear; ∞ = infinite projection
  float xmagM = 1.0f;          // orthographic half width, metres
  float ymagM = 1.0f;          // orthographic half height, metres
};

// A view matrix-free placement: the parentFromLocal transform of a camera node at `eyeM` looking at `targetM`
// with `up` (world frame, metres). Throws std::invalid_argument when eye == target or up is parallel to the view.
mat4 lookAtTransform(const vec3& eyeM, const vec3& targetM, const vec3& up);

}  // namespace fly::sdb
